#pragma once
// Closest points on a surface, a part or a curve, in fp64 on the CPU (docs/math.md "Closest points"):
// for each query point the global minimum of the distance, with where it is (face, parameters),
// the distance and the normal. The pieces come from a ProjectionTree (part/projection_tree.h),
// visited nearest box first; on each piece whose box is nearer than the best point so far, Newton's
// method on the squared distance (second derivatives, the step held inside the piece, halved until
// the distance falls) finds the piece's nearest point; a trimmed face's point counts only inside
// its loops, and the loops themselves are pieces (Newton along each segment lifted onto the face),
// so a foot point on a face's boundary lies on its trim loop.
#include <shapespline/core/trim_classifier.h>
#include <shapespline/part/projection_tree.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace shapespline::part {

struct FootPoint {
  glm::dvec3 point{0.0};
  glm::dvec3 normal{0.0};  // unit; a face's outward normal (its `reversed` applied); a curve: 0
  double u = 0.0, v = 0.0;  // the model's parameters (a curve: t in u, v = 0)
  double distance = 0.0;
  // Outside positive when the query asked for a sign (a closed shell), else equal to distance.
  double signedDistance = 0.0;
  int face = 0;           // the face's id (a model on its own: 0)
  bool boundary = false;  // on a face's trim loop rather than inside it
};

class ClosestPoints {
 public:
  // The tree must outlive this object. `tolerance` (model units, >= 0): a piece is searched only if
  // it could hold a point nearer than the best so far by more than this, so every foot is within
  // `tolerance` of the nearest and clouds near the surface stop after fewer pieces; 0 searches every
  // piece that could be as near, which also resolves ties by the rule in docs/math.md.
  explicit ClosestPoints(const ProjectionTree& tree, double tolerance = 0.0);

  // The foot point of q. With `signedDistance`, the sign is that of q - foot along the outward
  // normal at the foot, or, where the foot is on a boundary, along the sum of the outward normals of
  // the faces that meet there (so that q outside a sharp edge is outside). Thread-safe.
  FootPoint of(const glm::dvec3& q, bool signedDistance) const;
  // out[k] = of(points[k]) on `threads` threads (0: every core).
  void of(std::span<const glm::dvec3> points, std::span<FootPoint> out, bool signedDistance, int threads) const;

  const ProjectionTree& tree() const { return tree_; }
  double tolerance() const { return tolerance_; }

  // Newton stops when a step moves the parameters by less than this, in a piece's local units (the
  // piece's patch is [0, 1]): a few hundred ulps of 1, far below what changes the distance.
  static constexpr double kStepTolerance = 1e-14;
  // A Newton step shorter than this (local units) where the distance curves up in every direction
  // is taken even if the distance does not fall: so near the minimum the distance is flat to its
  // rounding, and a rounding-level rise would stop Newton short of it (off the surface, at
  // parameters about 1e-9 away).
  static constexpr double kTrustedStep = 1e-6;
  // A foot this near (a fraction of the diagonal) cannot be bettered: the query is on the surface.
  static constexpr double kOnSurfaceFraction = 1e-13;

  // The nearest point a search found (d2 infinite: none, every piece outside its loops).
  struct Candidate {
    double d2 = std::numeric_limits<double>::infinity();
    glm::dvec3 point{0.0};
    double u = 0.0, v = 0.0;  // global parameters
    int face = 0;             // index into tree.faces()
    bool boundary = false;
    // Where the normal is read: the patch and local parameters (cells), or the global ones (runs).
    int i = 0, j = 0;
    double lu = 0.0, lv = 0.0;
    // The local partials at the point where Newton left them there (zero otherwise): their cross
    // product gives the normal without another evaluation where it is regular.
    glm::dvec3 du{0.0}, dv{0.0};
  };
  // The foot point of q at the nearest point a search found: the normal, the face's id and, with
  // `signedDistance`, the sign. Both searches end here: this one's and the GPU's
  // (part/gpu_closest_points.h).
  FootPoint finish(const glm::dvec3& q, const Candidate& best, bool signedDistance) const;

 private:
  // Newton from where q falls on the cell's parallelogram, or from the patch parameters `from`;
  // false when it did not settle (see newtonOnPatch). `everySide`: every side on the domain's
  // border is searched, not only the one Newton ended on. A foot outside the face's loops gives way
  // to the nearest point on the loop pieces that meet the cell (those whose boxes are within bestD2).
  bool solveCell(const glm::dvec3& q, const ProjectionCell& cell, const glm::dvec2* from, bool everySide, double bestD2,
                 Candidate& out) const;
  // The nearest point on cell `cell`'s loop pieces within bestD2 (kept in `out` if nearer).
  void solveRuns(const glm::dvec3& q, int cell, double bestD2, Candidate& out) const;
  void solveRun(const glm::dvec3& q, const ProjectionRun& run, Candidate& out) const;
  void solveSpan(const glm::dvec3& q, const ProjectionSpan& span, Candidate& out) const;
  // A leaf's squared lower bound on the distance from q: its box's, and for a cell the larger of
  // that and its oriented box's.
  double leafBound(const glm::dvec3& q, const ProjectionTree::Leaf& leaf) const;
  // The cells whose bound (leafBound) is at most reach2:
  // where the faces that meet at an edge foot lie, for its sign.
  std::vector<int> cellsWithin(const glm::dvec3& q, double reach2) const;

  const ProjectionTree& tree_;
  double tolerance_ = 0.0;
  std::vector<std::optional<TrimClassifier>> inside_;  // per face: its loops, if it has any
};

}  // namespace shapespline::part
