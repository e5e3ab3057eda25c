#pragma once
// A part's mesh as pictures draw it (`render part.json`, `view part.json`): each face's triangles
// on vertices of its own, shaded with the face's own normals up to its edges (so a sharp edge stays
// sharp), and the part's edges (where two faces meet, or a face ends) as lines.
#include <shapespline/part/part_mesher.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace shapespline::part {

struct ShadedMesh {
  std::vector<glm::vec3> positions, normals;  // one per (vertex, face) pair
  std::vector<uint32_t> triangles;            // 3 indices per triangle, the PartMesh's order
  std::vector<int32_t> faceIds;               // one per triangle (the part's face id)
  std::vector<uint32_t> edgeLines;            // line list: mesh edges between two faces or open
};

// Needs a mesh made with MeshOptions::cornerNormals (std::invalid_argument otherwise).
ShadedMesh shadedMesh(const PartMesh& mesh);

}  // namespace shapespline::part
