#pragma once
// Plain data describing a curve or surface model (docs/format.md). No evaluation here:
// evaluators (core/curve.h, core/surface.h, gpu/) take these by const reference.
#include <shapespline/core/family.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace shapespline {

// The shape-defining part of a family of local basis functions (docs/math.md §1–§9).
struct FamilySpec {
  Construction construction = Construction::ExtendedBSpline;
  int degree = 0;           // Xu-Wang degree 4..6 (ExtendedBSpline, AlphaEB)
  int order = 0;            // UBP/GUBP 3..10, BSpline 2..10 (u order for surfaces)
  double lambda = 0.0;      // ExtendedBSpline, AlphaEB, GB, UBP
  std::vector<double> mu;   // GUBP: the half vector mu_0..mu_{floor(k/2)}

  bool operator==(const FamilySpec&) const = default;
};

struct CurveModel {
  FamilySpec family;
  bool closed = false;
  int dimension = 2;                 // 2 or 3; 2-D points carry z = 0
  std::vector<glm::dvec3> points;
  std::vector<double> alpha;         // AlphaEB only: one value per point (a scalar is expanded)
  std::vector<double> knots;         // ExtendedBSpline/GB: span boundaries; BSpline: full knot vector
  std::vector<double> weights;       // BSpline with a knot vector: one positive weight per point
                                     // (a rational B-spline, docs/math.md §10.8); empty: all 1
};

// The trimming loops of a face (docs/format.md "Trim"): closed polylines in the surface's (U,V)
// knot parameters, the last point not repeating the first; outer loops counter-clockwise, holes
// clockwise. A sample is inside by the even-odd rule; one within `tolerance` (a parameter-space
// distance) of a loop counts as inside. Written by `shapespline import` from a CAD face.
struct TrimLoops {
  std::vector<std::vector<glm::dvec2>> loops;
  double tolerance = 0.0;

  bool empty() const { return loops.empty(); }
  bool operator==(const TrimLoops&) const = default;
};

// Everything about a surface model except its control points and weights. A built Surface
// (core/surface.h) keeps this beside its patch net, which is the one copy of the points: a 4096²
// net is 400 MB, and keeping it twice was most of a big model's memory.
struct SurfaceShape {
  FamilySpec family;                 // family.order is the u order for BSpline
  int orderV = 0;                    // BSpline only: v order (else equal to family.order)
  bool closedU = false;
  bool closedV = false;
  int rows = 0;                      // u direction (index i)
  int cols = 0;                      // v direction (index j)
  std::vector<double> alpha;         // AlphaEB only: rows * cols values, row-major
  std::vector<double> knotsU;        // BSpline with knot vectors only
  std::vector<double> knotsV;
  TrimLoops trim;                    // BSpline with knot vectors only; empty: the whole domain

  bool operator==(const SurfaceShape&) const = default;
};

struct SurfaceModel : SurfaceShape {
  std::vector<glm::dvec3> points;    // row-major: points[i * cols + j]
  std::vector<double> weights;       // BSpline with knot vectors: rows * cols positive weights,
                                     // row-major (rational, docs/math.md §10.8); empty: all 1

  const glm::dvec3& at(int i, int j) const { return points[static_cast<size_t>(i) * cols + j]; }
  // Every field equal, bit for bit but for the sign of zero and NaN (==).
  bool operator==(const SurfaceModel&) const = default;
};

// A model that breaks a rule of docs/format.md / docs/math.md §11. `field` is a JSON-path-like
// name ("alpha[3]", "points[2][1]"), `value` the offending value as text, `rule` the rule.
class ModelError : public std::invalid_argument {
 public:
  ModelError(std::string field, std::string value, std::string rule);
  const std::string& field() const { return field_; }
  const std::string& value() const { return value_; }
  const std::string& rule() const { return rule_; }

 private:
  std::string field_, value_, rule_;
};

}  // namespace shapespline
