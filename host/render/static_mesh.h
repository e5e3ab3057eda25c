#pragma once
// StaticMesh: an indexed triangle mesh made on the host (a part's shaded mesh, host/part), uploaded
// once in the tessellator's vertex layout (shaders/tess_layout.h) with optional line-list indices,
// and drawn as a MeshDraw by OffscreenRenderer or the viewer's swapchain pass.
#include <shapespline/render/renderer.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/context.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>

namespace shapespline::render {

// The colours parts are drawn in (`render part.json`, `view part.json`): a light steel grey, as CAD
// viewers shade parts, nearly black edges, and an orange picked face.
inline constexpr glm::vec3 kPartColour{0.62f, 0.66f, 0.72f};
inline constexpr glm::vec3 kPartEdgeColour{0.05f, 0.05f, 0.08f};
inline constexpr glm::vec3 kPickedFaceColour{0.95f, 0.55f, 0.15f};

class StaticMesh {
 public:
  // positions and normals one per vertex; triangles 3 and lines 2 indices each, all below the
  // vertex count (std::invalid_argument otherwise, before any upload). Throws VulkanError.
  StaticMesh(vk::Context& ctx, std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
             std::span<const uint32_t> triangles, std::span<const uint32_t> lines);

  // Triangles first .. first + count - 1 and lines likewise (counted in triangles and lines, not
  // indices), drawn as one MeshDraw; the whole mesh by default.
  struct Range {
    uint32_t first = 0, count = 0;
  };
  MeshDraw draw(Range triangles, Range lines) const;
  MeshDraw draw() const { return draw({0, triangleCount()}, {0, lineCount()}); }
  uint32_t triangleCount() const { return triangleIndices_ / 3; }
  uint32_t lineCount() const { return lineIndices_ / 2; }

 private:
  vk::Buffer vertices_, triangles_, lines_;
  uint32_t triangleIndices_ = 0, lineIndices_ = 0;
};

}  // namespace shapespline::render
