#pragma once
// Precision warnings for valid models whose values are extreme enough that fp64 evaluation loses
// digits, or may overflow (issue 7). Validation (core/validate.h) decides what is allowed; this
// says what is allowed but numerically risky, so that a tool can print a warning next to its output.
//
// Rules (thresholds are named constants below):
//  * α below kAlphaWarn: V_j = P_j + ((1-α)/α)(P_j - node_j) amplifies rounding errors by 1/α
//    (docs/math.md §14), so about -log10(α) digits are lost.
//  * a coordinate of magnitude above kHugeCoordinate: products of two coordinates (cross products,
//    squared lengths) overflow, derivatives may overflow; normals and lengths lose precision.
//  * a control net whose extent is nonzero and below kTinyExtent: squares of its differences
//    underflow (subnormal or 0), so normals and lengths lose precision.
//  * a control net whose extent is below kRelativeExtent times its largest coordinate: the shape
//    is resolved with only a few digits (cancellation against the offset from the origin).
//  * span knots / knot-vector intervals whose smallest nonzero width is below kKnotRatio times the
//    parameter range or below kTinyKnot: derivatives are scaled by 1/h^r and lose precision (or
//    overflow).
//  * GB λ above kGBLambdaWarn: the basis is within rounding of its λ → ∞ limit (docs/math.md §7.1).
// A model with no warning evaluates (CPU sampler, every field) to finite values: the fuzzer
// (tests/fuzz) checks exactly that.
#include <shapespline/core/model.h>
#include <shapespline/core/surface.h>

#include <string>
#include <vector>

namespace shapespline {

struct Warning {
  std::string field;    // JSON path as in ModelError: "alpha[3]", "points[2][1]", "knots[4]", "lambda"
  std::string message;  // one human-readable sentence naming the value and the consequence
};

inline constexpr double kAlphaWarn = 1e-6;
inline constexpr double kHugeCoordinate = 1e150;
inline constexpr double kTinyExtent = 1e-150;
inline constexpr double kRelativeExtent = 1e-12;
inline constexpr double kKnotRatio = 1e-12;
inline constexpr double kTinyKnot = 1e-50;
inline constexpr double kGBLambdaWarn = 1e12;

// Warnings for a model that passed validateCurve / validateSurface, in field order; empty when
// fp64 evaluation is expected to be accurate to the usual tolerances.
std::vector<Warning> precisionWarnings(const CurveModel& model);
std::vector<Warning> precisionWarnings(const SurfaceModel& model);
std::vector<Warning> precisionWarnings(const Surface& surface);  // the same, on the built net

// The passes the rules make over a model's values, fed in order a run at a time (a net streamed
// from its file is never held): the points' largest coordinate and extent, the smallest α.
struct PointSpread {
  int dims = 3;
  double biggest = 0.0, biggestValue = 0.0;
  size_t where = 0;  // the point (flat index) of the largest coordinate, and its axis
  int axis = 0;
  bool any = false;
  glm::dvec3 lo{0.0}, hi{0.0};
  size_t seen = 0;
  void add(const glm::dvec3& p);
};
struct SmallestAlpha {
  double value = 0.0;
  size_t where = 0;  // the first α of that value
  bool any = false;
  size_t seen = 0;
  void add(const double* alpha, size_t count);
};

// The values of a net seen a run at a time, each kind in order (a stream's warnings): the points'
// largest coordinate and extent, the smallest α. The scans below name what they find.
class ValueScan {
 public:
  explicit ValueScan(int dims) : points_{dims} {}
  void points(const glm::dvec3* p, size_t count) {
    for (size_t k = 0; k < count; ++k) points_.add(p[k]);
  }
  void alphas(const double* alpha, size_t count) { alpha_.add(alpha, count); }
  const PointSpread& spread() const { return points_; }
  const SmallestAlpha& smallestAlpha() const { return alpha_; }

 private:
  PointSpread points_;
  SmallestAlpha alpha_;
};

// precisionWarnings of a curve whose points and α are seen a run at a time: the same warnings
// precisionWarnings(model) gives (which uses it). `shape` (knots, family, dimension) is kept by
// reference; its points and α are not read.
class CurveWarningScan final : public ValueScan {
 public:
  explicit CurveWarningScan(const CurveModel& shape) : ValueScan(shape.dimension), shape_(shape) {}
  std::vector<Warning> warnings() const;

 private:
  const CurveModel& shape_;
};

// precisionWarnings of a surface whose points and α are seen a run at a time, each in order: the
// same warnings the built surface gives.
class SurfaceWarningScan final : public ValueScan {
 public:
  explicit SurfaceWarningScan(const SurfaceShape& shape) : ValueScan(3), shape_(shape) {}
  std::vector<Warning> warnings() const;

 private:
  const SurfaceShape& shape_;
};

// "warning: <field>: <message>"
std::string formatWarning(const Warning& warning);

}  // namespace shapespline
