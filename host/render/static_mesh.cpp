#include <shapespline/render/static_mesh.h>

#include <shapespline/shaders/tess_layout.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

namespace shapespline::render {
namespace {

vk::Buffer indexBuffer(vk::Context& ctx, std::span<const uint32_t> indices, const char* label) {
  vk::Buffer b = vk::Buffer::create(ctx, std::max<size_t>(indices.size(), 1) * sizeof(uint32_t),
                                    VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                    vk::MemoryUse::DeviceLocal, label);
  if (!indices.empty()) b.uploadSpan(indices);
  return b;
}

}  // namespace

StaticMesh::StaticMesh(vk::Context& ctx, std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                       std::span<const uint32_t> triangles, std::span<const uint32_t> lines) {
  if (normals.size() != positions.size()) throw std::invalid_argument("StaticMesh: one normal per position");
  if (triangles.size() % 3 != 0 || lines.size() % 2 != 0)
    throw std::invalid_argument("StaticMesh: 3 indices per triangle and 2 per line");
  if (triangles.size() > std::numeric_limits<uint32_t>::max() || lines.size() > std::numeric_limits<uint32_t>::max())
    throw std::invalid_argument("StaticMesh: more indices than one draw takes");
  const auto inRange = [&](uint32_t i) { return i < positions.size(); };
  if (!std::all_of(triangles.begin(), triangles.end(), inRange) || !std::all_of(lines.begin(), lines.end(), inRange))
    throw std::invalid_argument("StaticMesh: an index beyond the vertices");
  // Position, normal, (U, V) = 0: the layout the surface pipeline reads.
  std::vector<gpu::tess_layout::TessVertex> packed(std::max<size_t>(positions.size(), 1), gpu::tess_layout::TessVertex{});
  for (size_t v = 0; v < positions.size(); ++v) {
    std::copy_n(&positions[v].x, 3, packed[v].position);
    std::copy_n(&normals[v].x, 3, packed[v].normal);
  }
  vertices_ = vk::Buffer::create(ctx, packed.size() * sizeof(packed[0]),
                                 VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 vk::MemoryUse::DeviceLocal, "static_mesh.vertices");
  vertices_.uploadSpan(std::span<const gpu::tess_layout::TessVertex>(packed));
  triangles_ = indexBuffer(ctx, triangles, "static_mesh.triangles");
  lines_ = indexBuffer(ctx, lines, "static_mesh.lines");
  triangleIndices_ = static_cast<uint32_t>(triangles.size());
  lineIndices_ = static_cast<uint32_t>(lines.size());
}

MeshDraw StaticMesh::draw(Range triangles, Range lines) const {
  if (triangles.first + uint64_t(triangles.count) > triangleCount() || lines.first + uint64_t(lines.count) > lineCount())
    throw std::out_of_range("StaticMesh::draw: a range beyond the mesh");
  MeshDraw d;
  d.vertexBuffer = vertices_.handle();
  d.indexBuffer = triangles_.handle();
  d.firstIndex = triangles.first * 3;
  d.indexCount = triangles.count * 3;
  if (lines.count > 0) {
    d.wireIndexBuffer = lines_.handle();
    d.wireFirstIndex = lines.first * 2;
    d.wireIndexCount = lines.count * 2;
  }
  return d;
}

}  // namespace shapespline::render
