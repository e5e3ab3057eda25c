#pragma once
// The query structure of closest-point projection (docs/math.md "Closest points"), built once per
// surface or part and kept apart from the code that answers queries with it (part/closest_points.h),
// as OpenSubdiv keeps its `far` tables apart from its `osd` evaluators.
//
// Every polynomial patch (a uniform family's patch, or a knot-vector surface's non-empty knot
// interval) is written in Bernstein form and cut by de Casteljau until its control net is nearly
// flat; each piece, a cell, keeps the box of its Bézier control points, which holds every point of
// the piece (the convex-hull property; a rational piece's projected points, its Bézier weights
// being positive). A trimmed face adds its trim loops' segments, halved until each piece meets few
// cells, and each cell lists the pieces that meet it: where a cell's nearest point lies outside the
// loops, its nearest point inside them is on one of those pieces. Cells wholly outside a face's
// loops are left out. A bounding-volume hierarchy over the cells lets a query visit them in the
// order of their boxes' distance and stop at the first box farther than the best point found.
#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>
#include <shapespline/part/part_model.h>

#include <glm/vec2.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace shapespline::part {

struct Box {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
  void add(const glm::dvec3& p);
  void add(const Box& b);
  bool empty() const { return lo.x > hi.x; }
  glm::dvec3 centre() const { return 0.5 * (lo + hi); }
  // Squared distance from q to the box (0 inside).
  double distance2(const glm::dvec3& q) const;
};

// One surface the tree is built over: a part's face, or a model on its own.
struct ProjectionFace {
  const Surface* surface = nullptr;
  int id = 0;             // reported with each foot point
  bool reversed = false;  // the outward normal is -(du x dv)
};

// A patch's polynomial over its local [0, 1]^2 in the powers of (u - 1/2) and (v - 1/2): (n + 1) x
// (m + 1) homogeneous coefficients (w P, w; w = 1 where the patch is not rational), row-major by the
// power of u, from ProjectionTree::coefficients()[first]. Centred, so the powers stay within 1/2
// and the sums lose few digits; the search evaluates it by Horner's rule (part/closest_points.cpp),
// with no knot search and no basis recursion.
struct ProjectionPatch {
  int face = 0, i = 0, j = 0;  // patch (i, j) of face `face` (a curve: span i)
  int n = 0, m = 0;
  std::size_t first = 0;
  bool rational = false;
};

// A piece of a face's patch: patch (i, j) over local [u0, u1] x [v0, v1], with the parallelogram of
// its corners (middle, and the mean edge vectors along u and v: where Newton starts) and how much
// it bends towards either side of du x dv: the largest principal curvature towards each side,
// sampled on 3 x 3 points and widened by half (infinite at a point that is not regular). A query on
// one side nearer than about the inverse of that side's curvature has one nearest point on the
// piece.
struct ProjectionCell {
  int index = 0;  // in ProjectionTree::cells()
  int face = 0, i = 0, j = 0;
  int patch = 0;  // in ProjectionTree::patches()
  double u0 = 0.0, u1 = 1.0, v0 = 0.0, v1 = 1.0;
  glm::dvec3 middle{0.0}, alongU{0.0}, alongV{0.0};
  double bendsUp = 0.0, bendsDown = 0.0;  // towards +(du x dv), towards -(du x dv)
  // The oriented box: the cell lies where lo[k] <= (p - middle) . axis[k] <= hi[k].
  glm::dvec3 axis[3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {0.0, 0.0, 0.0};
  // Squared distance from q to the oriented box (0 inside).
  double distance2(const glm::dvec3& q) const {
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double t = glm::dot(q - middle, axis[k]);
      const double out = t < lo[k] ? lo[k] - t : (t > hi[k] ? t - hi[k] : 0.0);
      sum += out * out;
    }
    return sum;
  }
};

// A piece [t0, t1] of segment `segment` of a face's trim loop (segment k runs from loop point k, at
// t = 0, to k + 1, the last back to the first).
struct ProjectionRun {
  int face = 0, loop = 0, segment = 0;
  double t0 = 0.0, t1 = 1.0;
  Box box;  // its lifted ends and middle, widened by twice the middle's bulge (see the .cpp)
};

// A piece of a curve: span `span` over local [t0, t1].
struct ProjectionSpan {
  int span = 0;
  double t0 = 0.0, t1 = 1.0;
};

class ProjectionTree {
 public:
  // The faces' cells and trim runs. ModelError for a surface the method cannot bound (α-EB, whose
  // patches are not polynomial).
  static ProjectionTree ofFaces(std::vector<ProjectionFace> faces);
  // Every converted face of the part (which must outlive the tree).
  static ProjectionTree ofPart(const Part& part);
  // A curve's spans, cut likewise (ModelError for α-EB).
  static ProjectionTree ofCurve(const Curve& curve);

  enum class LeafKind : unsigned char { Cell, Span };
  struct Leaf {
    Box box;
    LeafKind kind = LeafKind::Cell;
    int index = 0;  // into cells() or spans()
  };
  // A node covers leaves first .. first + count - 1 when count > 0; otherwise its children are the
  // next node and node `right`.
  struct Node {
    Box box;
    int first = 0, count = 0, right = 0;
  };

  const std::vector<ProjectionFace>& faces() const { return faces_; }
  const std::vector<ProjectionCell>& cells() const { return cells_; }
  const std::vector<ProjectionPatch>& patches() const { return patches_; }
  const std::vector<glm::dvec4>& coefficients() const { return coefficients_; }
  const std::vector<ProjectionRun>& runs() const { return runs_; }
  const std::vector<ProjectionSpan>& spans() const { return spans_; }
  // The trim pieces that meet cell k: runs()[cellRuns()[cellRunStart()[k] .. cellRunStart()[k + 1])].
  std::span<const int> runsOf(int cell) const {
    return {cellRuns_.data() + cellRunStart_[cell], cellRuns_.data() + cellRunStart_[cell + 1]};
  }
  const std::vector<Leaf>& leaves() const { return leaves_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  const Curve* curve() const { return curve_; }
  // The diagonal of everything's box: the scale of every tolerance.
  double diagonal() const { return diagonal_; }

 private:
  void buildHierarchy();

  std::vector<ProjectionFace> faces_;
  const Curve* curve_ = nullptr;
  std::vector<ProjectionCell> cells_;
  std::vector<ProjectionPatch> patches_;
  std::vector<glm::dvec4> coefficients_;
  std::vector<ProjectionRun> runs_;
  std::vector<ProjectionSpan> spans_;
  std::vector<int> cellRunStart_, cellRuns_;
  std::vector<Leaf> leaves_;
  std::vector<Node> nodes_;
  double diagonal_ = 0.0;
};

}  // namespace shapespline::part
