#pragma once
// SurfaceMesh: the seam between the viewer and the tessellator that makes its surface mesh. Each
// frame the viewer calls record() before its render pass and draws draw() inside it; the
// implementation (surface_mesh.cpp) is the screen-space adaptive tessellator
// (gpu/adaptive_tessellator.h) when it is built, the fixed-rate one otherwise.
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/render/camera.h>
#include <shapespline/render/renderer.h>
#include <shapespline/vk/context.h>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <memory>
#include <string>

namespace shapespline::viewer {

class SurfaceMesh {
 public:
  virtual ~SurfaceMesh() = default;
  // "adaptive" or "fixed rate N".
  virtual std::string name() const = 0;
  // Pixel tolerance of the adaptive rates (the fixed-rate mesh ignores it).
  virtual void setTolerance(float px) = 0;
  // Tessellates for the frame's camera and viewport into cmd (compute passes, before the render pass).
  virtual void record(VkCommandBuffer cmd, const render::Camera& camera, VkExtent2D extent) = 0;
  // How to draw the last recorded mesh; wireframe: its triangle edges as well.
  virtual render::MeshDraw draw(bool wireframe) const = 0;
  // Triangles of the last recorded frame. May wait for the queue to be idle (the adaptive counts
  // are read back): call it a few times a second, not per frame.
  virtual uint64_t triangleCount() const = 0;
};

// The surface must outlive the mesh. Throws std::invalid_argument for a surface the tessellators
// do not take (knot-vector B-splines).
std::unique_ptr<SurfaceMesh> makeSurfaceMesh(std::shared_ptr<vk::Context> ctx, gpu::GpuSurface& surface,
                                             float tolerancePx, bool triangleWireframe);

}  // namespace shapespline::viewer
