#pragma once
// Painter: what `shapespline render` draws with, so that the front end makes no Vulkan call. It
// owns a Vulkan context with a graphics queue and an OffscreenRenderer of one image size; a
// SurfaceDrawing is a surface tessellated on the GPU (fp32, gpu/tessellator.h) with its wire edges,
// whose λ and α can change between frames without re-uploading the net.
#include <shapespline/core/surface.h>
#include <shapespline/render/camera.h>
#include <shapespline/render/renderer.h>
#include <shapespline/render/static_mesh.h>

#include <memory>
#include <stdexcept>
#include <vector>

namespace shapespline::render {

class SurfaceDrawing;

// No Vulkan device to draw with: "render needs a Vulkan device with a graphics queue: REASON".
class NoRenderDeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Painter {
 public:
  // Throws NoRenderDeviceError when there is no device, VulkanError for other failures.
  Painter(int width, int height);
  ~Painter();
  Painter(const Painter&) = delete;
  Painter& operator=(const Painter&) = delete;

  int width() const { return renderer_->width(); }
  int height() const { return renderer_->height(); }

  // `rate` segments per patch edge (knot-vector B-splines: per non-empty knot interval);
  // `wireframe`: also upload the triangle edges.
  std::unique_ptr<SurfaceDrawing> tessellate(const Surface& surface, int rate, bool wireframe);

  // A mesh made on the host (a part's shaded mesh), uploaded once; draw it as one of a Scene's meshes.
  std::unique_ptr<StaticMesh> upload(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                                     std::span<const uint32_t> triangles, std::span<const uint32_t> lines);

  // The surface (tessellated in the frame's command buffer) under `overlay`'s lines and markers.
  Image draw(SurfaceDrawing& surface, const Scene& overlay, const Camera& camera);
  // Only the scene's own meshes and overlay (curves, nets, markers, uploaded meshes).
  Image draw(const Scene& overlay, const Camera& camera);

 private:
  std::shared_ptr<vk::Context> ctx_;
  std::unique_ptr<OffscreenRenderer> renderer_;
};

class SurfaceDrawing {
 public:
  ~SurfaceDrawing();
  // New parameters, shown at the next Painter::draw (the tessellation pass re-evaluates them).
  void setLambda(double lambda);
  void setAlphas(const std::vector<double>& alpha);

 private:
  friend class Painter;
  struct Impl;
  explicit SurfaceDrawing(std::unique_ptr<Impl> impl);
  MeshDraw mesh() const;
  void record(VkCommandBuffer cmd);
  std::unique_ptr<Impl> impl_;
};

}  // namespace shapespline::render
