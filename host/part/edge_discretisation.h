#pragma once
// Every edge of a part cut into vertices once (docs/cad.md "Meshing a part"), so that every face
// that uses the edge takes the same vertices and the faces meet without cracks. An edge is cut
// where its chords leave the curve by more than the deflection or turn by more than the angle,
// tested at each chord's middle and quarter points; the curve's points are one face's surface at
// that face's coedge (the first face that uses the edge), which is what OCCT's p-curve and
// 3-D curve agree on within the edge's tolerance.
#include <shapespline/part/coedge_path.h>
#include <shapespline/part/face_evaluator.h>
#include <shapespline/part/part_model.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace shapespline::part {

// One use of an edge by a face: the face's index in Part::faces, the loop and the coedge in it.
struct EdgeUse {
  int face = 0, loop = 0, coedge = 0;
};

struct DiscreteEdge {
  int id = 0;
  bool degenerate = false;          // a point: one vertex, at t.front()
  std::vector<double> t;            // ascending: the vertices' edge parameters
  std::vector<glm::dvec3> points;   // the vertices
  std::vector<EdgeUse> uses;
};

// A face's coedges as paths, per loop: paths[face][loop][coedge].
using CoedgePaths = std::vector<std::vector<std::vector<CoedgePath>>>;

struct EdgeTolerances {
  double deflection = 0.0;  // largest distance of a chord from the curve (model units)
  double angle = 0.0;       // largest turn of the curve over one chord (radians)
};

// The discretised edges, one per edge id that a coedge names (in ascending id). Edges run on
// `threads` threads; `evaluator` must then be thread-safe or serialise itself. More than
// `maxVertices` vertices over all edges throws TriangleBudgetExceeded (face_triangulation.h): each
// one costs the mesh at least a triangle, so the cut stops before it outgrows the budget.
std::vector<DiscreteEdge> discretiseEdges(const Part& part, const CoedgePaths& paths, const EdgeTolerances& tolerances,
                                          FaceEvaluator& evaluator, int threads, int64_t maxVertices);

}  // namespace shapespline::part
