#pragma once
// One face's triangles (docs/cad.md "Meshing a part"): its trim loops, as the discretised edges'
// vertices, are the constraints of a Delaunay triangulation in the face's parameters (scaled by the
// surface's mean first partials, so that a triangle's shape in the plane is close to its shape in
// space), and points are added inside until the mesh is within the deflection of the surface and
// turns by no more than the angle: each round evaluates every triangle's centroid and every inner
// edge's midpoint in one list, and inserts those where the surface is further than the deflection
// from the triangle's plane interpolation (an upper bound of the mesh's distance there, since the
// surface point is a point of the surface) or where the normals differ by more than the angle.
#include <shapespline/part/face_evaluator.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace shapespline::part {

// A vertex of a trim loop: its (U, V) on this face and the part-wide vertex it is (shared by every
// face through the edge, or with the pole's other loop points on a degenerate edge).
struct LoopVertex {
  glm::dvec2 uv{0.0};
  uint32_t vertex = 0;
};

struct FaceTolerances {
  double deflection = 0.0;
  double angle = 0.0;
};

struct FaceTriangles {
  // Vertices added inside the face: their points and unit normals (oriented as the face's outward
  // normal, reversed applied; zero where the surface has none, as at a pole).
  std::vector<glm::dvec3> points, normals;
  // Part-wide vertex ids for loop vertices; interior vertex k is kInterior + k.
  std::vector<std::array<uint32_t, 3>> triangles;
  // The face's own unit normal at each loop vertex, in the loops' order (zero where it has none).
  std::vector<glm::dvec3> loopNormals;
  static constexpr uint32_t kInterior = 0x80000000u;
};

// The trim loops cross each other (or themselves): a face that cannot be triangulated.
class CrossingTrimLoops : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The triangle budget ran out while refining.
class TriangleBudgetExceeded : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `positions[v]` is the part-wide point of loop vertex v. `budget` is the triangles the whole part
// may still use; the face's triangles are taken from it as they are made.
FaceTriangles triangulateFace(const Surface& surface, bool reversed, const std::vector<std::vector<LoopVertex>>& loops,
                              const std::vector<glm::dvec3>& positions, const FaceTolerances& tolerances,
                              FaceEvaluator& evaluator, std::atomic<int64_t>& budget);

}  // namespace shapespline::part
