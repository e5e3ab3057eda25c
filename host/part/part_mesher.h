#pragma once
// A part's watertight mesh (docs/cad.md "Meshing a part"): every edge discretised once
// (edge_discretisation.h), every face triangulated in its parameters on those vertices
// (face_triangulation.h), the faces' triangles welded into one indexed mesh with a face id per
// triangle, each face wound along its outward normal (part.json's `reversed`). Closed shells come
// out closed: the only vertices two faces share are edge vertices, and both faces take the same.
#include <shapespline/io/triangle_mesh.h>
#include <shapespline/part/face_evaluator.h>
#include <shapespline/part/part_model.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace shapespline::part {

// The documented default budget: a mesh past it is refused (docs/cad.md).
inline constexpr int64_t kDefaultTriangleBudget = 50'000'000;

struct MeshOptions {
  double deflection = 0.0;  // absolute, in the part's units; > 0
  double angle = 0.5;       // radians, in (0, pi)
  int64_t maxTriangles = kDefaultTriangleBudget;
  int threads = 0;  // 0: every core of the process
  // Also keep each face's own normal at every triangle corner (PartMesh::cornerNormals): pictures
  // shade a face up to its edges with its own normals, not with the mean across a sharp edge.
  bool cornerNormals = false;
};

struct PartMesh {
  io::TriangleMesh mesh;  // normals: the mean of the faces' unit normals at each vertex
  // With MeshOptions::cornerNormals: the unit normal of the triangle's face at each of its corners
  // (3 per triangle, in the triangles' order); the vertex's mean where the face has none (a pole).
  std::vector<glm::vec3> cornerNormals;
  int64_t boundaryEdges = 0;     // mesh edges used by one triangle (a closed shell has none)
  int64_t nonManifoldEdges = 0;  // mesh edges used by more than two triangles
  int faces = 0;
  int edges = 0;
};

// The length of the diagonal of the box of every face's control points (which holds the part):
// what a relative deflection is a fraction of.
double partDiagonal(const Part& part);

// ModelError naming the face ("faces[3].coedges") for a face imported without coedges or whose trim
// loops cross; TriangleBudgetExceeded when the mesh would need more than maxTriangles.
PartMesh meshPart(const Part& part, const MeshOptions& options, FaceEvaluator& evaluator);

}  // namespace shapespline::part
