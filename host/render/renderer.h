#pragma once
// OffscreenRenderer: a headless Vulkan graphics pipeline (runs on lavapipe) that draws tessellated
// surfaces (gpu/tessellator.h vertex layout) with two-sided headlight shading, optional wireframe
// over them, and overlay lines / markers (curves, control nets, data points) into an RGBA8 image
// read back to the host. Needs a Context whose queue family supports graphics.
#include <shapespline/render/camera.h>
#include <shapespline/shaders/tess_layout.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/context.h>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace shapespline::render {

using OverlayVertex = gpu::tess_layout::OverlayVertex;

// Row-major RGBA8, top row first. Alpha is 255 where something was drawn and 0 on the background
// (whose colour is in rgb), so the alpha channel is the coverage mask.
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;
  const uint8_t* pixel(int x, int y) const { return rgba.data() + (size_t(y) * width + x) * 4; }
};

// One indexed triangle mesh in the tessellator's vertex layout; wireIndexBuffer (optional) holds
// line-list indices into the same vertices. With indirectBuffer set, the triangles are drawn by
// vkCmdDrawIndexedIndirect from the VkDrawIndexedIndirectCommand at indirectOffset (counts the GPU
// wrote, gpu/adaptive_tessellator.h) and indexCount is ignored. wireframe: draw the edges of the
// same triangles (same draw, polygonMode LINE) where there is no wireIndexBuffer; only on devices
// with fillModeNonSolid (ScenePipelines::triangleWireframe), nothing otherwise.
struct MeshDraw {
  VkBuffer vertexBuffer = VK_NULL_HANDLE;
  VkBuffer indexBuffer = VK_NULL_HANDLE;
  uint32_t indexCount = 0;
  VkBuffer wireIndexBuffer = VK_NULL_HANDLE;
  uint32_t wireIndexCount = 0;
  glm::vec3 color{0.35f, 0.55f, 0.85f};
  glm::vec3 wireColor{0.08f, 0.08f, 0.12f};
  // Last, so that positional initialisers of the fields above keep their meaning.
  VkBuffer indirectBuffer = VK_NULL_HANDLE;
  VkDeviceSize indirectOffset = 0;
  bool wireframe = false;
  // The first index of each buffer drawn (direct draws): a range of a mesh drawn on its own, as a
  // picked face in another colour.
  uint32_t firstIndex = 0, wireFirstIndex = 0;
};

struct Scene {
  std::vector<MeshDraw> meshes;
  std::vector<OverlayVertex> lines;    // line list
  std::vector<OverlayVertex> markers;  // triangle list (see addMarker)
  glm::vec3 background{1.0f, 1.0f, 1.0f};
  // Recorded into the frame's command buffer before the render pass (e.g. SurfaceTessellator::record).
  std::function<void(VkCommandBuffer)> prepare;
};

// Overlay helpers: a polyline as line-list segments; a square marker of sizePx pixels (two triangles).
void addPolyline(std::vector<OverlayVertex>& out, const std::vector<glm::dvec3>& points, const glm::vec4& color);
void addMarker(std::vector<OverlayVertex>& out, const glm::dvec3& p, float sizePx, const glm::vec4& color);
// A polyline widthPx pixels wide as marker triangles (lines are 1 px on every device): each segment a
// quad whose sides are offset across its direction on screen as `camera` sees it in a width x height
// image, each vertex covered by a marker square so that the joins have no gaps.
void addWidePolyline(std::vector<OverlayVertex>& out, const std::vector<glm::dvec3>& points, float widthPx,
                     const glm::vec4& color, const Camera& camera, int width, int height);

class OffscreenRenderer {
 public:
  // Throws std::runtime_error when the context's queue cannot do graphics, VulkanError otherwise.
  OffscreenRenderer(std::shared_ptr<vk::Context> ctx, int width, int height);
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }

  // Records scene.prepare, the render pass and the readback into one command buffer, submits and
  // waits. Returns the image.
  Image render(const Scene& scene, const Camera& camera);
  // The same without reading the image back (timing a frame).
  void renderOnly(const Scene& scene, const Camera& camera);

 private:
  struct Impl;
  void draw(const Scene& scene, const Camera& camera, bool readback);
  std::shared_ptr<vk::Context> ctx_;
  int width_, height_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace shapespline::render
