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

class StaticMesh {
 public:
  // positions and normals one per vertex; triangles 3 and lines 2 indices each, all below the
  // vertex count (std::invalid_argument otherwise, before any upload). Throws VulkanError.
  StaticMesh(vk::Context& ctx, std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
             std::span<const uint32_t> triangles, std::span<const uint32_t> lines);

  // The triangles, with the lines as their wireframe when `withLines` (and there are any).
  MeshDraw draw(bool withLines) const;
  uint32_t triangleCount() const { return triangleIndices_ / 3; }

 private:
  vk::Buffer vertices_, triangles_, lines_;
  uint32_t triangleIndices_ = 0, lineIndices_ = 0;
};

}  // namespace shapespline::render
