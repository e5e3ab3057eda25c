#include <shapespline/part/shaded_mesh.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <unordered_map>

namespace shapespline::part {

ShadedMesh shadedMesh(const PartMesh& part) {
  const io::TriangleMesh& mesh = part.mesh;
  if (part.cornerNormals.size() != mesh.triangles.size() * 3)
    throw std::invalid_argument("shadedMesh: the mesh was made without MeshOptions::cornerNormals");
  ShadedMesh out;
  out.faceIds = mesh.faceIds;
  out.triangles.reserve(mesh.triangles.size() * 3);
  // A face's triangles are consecutive (part_mesher.cpp), so its vertices are numbered per run.
  std::unordered_map<uint32_t, uint32_t> ownVertex;  // welded vertex -> this face's copy
  // Each mesh edge (a < b) seen so far: the face of its first triangle and its copy of a and b.
  struct Side {
    int32_t face;
    uint32_t a, b;
    bool shared = false;  // a second triangle of the same face uses it: not a line
    bool drawn = false;
  };
  std::unordered_map<uint64_t, Side> sides;
  sides.reserve(mesh.triangles.size() * 2);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (t == 0 || mesh.faceIds[t] != mesh.faceIds[t - 1]) ownVertex.clear();
    std::array<uint32_t, 3> local{};
    for (size_t j = 0; j < 3; ++j) {
      const uint32_t v = mesh.triangles[t][j];
      const auto [it, added] = ownVertex.try_emplace(v, static_cast<uint32_t>(out.positions.size()));
      if (added) {
        out.positions.emplace_back(mesh.positions[v]);
        out.normals.push_back(part.cornerNormals[t * 3 + j]);
      }
      local[j] = it->second;
      out.triangles.push_back(it->second);
    }
    for (size_t j = 0; j < 3; ++j) {
      const uint32_t a = mesh.triangles[t][j], b = mesh.triangles[t][(j + 1) % 3];
      const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      const auto [it, added] = sides.try_emplace(key, Side{mesh.faceIds[t], local[j], local[(j + 1) % 3]});
      if (added) continue;
      Side& side = it->second;
      if (side.face == mesh.faceIds[t]) side.shared = true;
      else if (!side.drawn) side.drawn = true;  // two faces meet here
    }
  }
  for (const auto& [key, side] : sides)
    if (side.drawn || !side.shared) {  // between faces, or open (one triangle)
      out.edgeLines.push_back(side.a);
      out.edgeLines.push_back(side.b);
    }
  return out;
}

}  // namespace shapespline::part
