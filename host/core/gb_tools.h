#pragma once
// GB-spline tools (docs/math.md §7, [GB] Li, Hoffmann & Wang §2–3): λ-paths and the constrained
// modification that makes a span pass through a 2-D target point (§7.2).
#include <shapespline/core/model.h>

#include <glm/vec2.hpp>

#include <array>
#include <span>
#include <string>
#include <vector>

namespace shapespline {

// The straight λ-path of span j at local parameter t (docs/math.md §7.1, C16): every C_j(λ,t), λ ≥ −8,
// lies on the segment from cMinus8 (λ = −8) through c0 (λ = 0) towards e (λ → ∞), and
// C_j(λ,t) = w·c0 + (1−w)·e with w = 12/(12+λ).
struct GbLambdaPath {
  glm::dvec2 c0{0.0};       // C_0(t): the uniform cubic B-spline span (λ = 0)
  glm::dvec2 e{0.0};        // E(t) = (1−h)P_j + h P_{j+1}, h = 3t² − 2t³ (λ → ∞, on the leg)
  glm::dvec2 cMinus8{0.0};  // C(−8,t) = 3C_0 − 2E
};

// Path end points of span `span` of a 2-D gb curve at t ∈ [0,1]. The model's own lambda is ignored.
// Throws ModelError for non-2-D data or a span that does not exist (open: 1..N−3, closed: 0..N−1).
GbLambdaPath gbLambdaPath(const CurveModel& gbCurve, int span, double t);

// C_j(λ,t) of the span, from the GB basis of docs/math.md §7.1 (gbSpanBasis), for any admissible λ.
glm::dvec2 gbSpanPoint(const CurveModel& gbCurve, int span, double lambda, double t);

// Power-basis coefficients f[0..6] of F(t) = cross(X − E(t), C_0(t) − E(t)) (docs/math.md §7.2): X lies on
// the λ-path line of parameter t iff F(t) = 0.
std::array<double, 7> gbPathPolynomial(const CurveModel& gbCurve, int span, glm::dvec2 target);

// Real roots in [0,1] of the polynomial sum_d coef[d] t^d, ascending, double roots included once.
// Isolation by the derivative sequence (the roots of p' split [0,1] into intervals on which p is
// monotone), then bisection to full precision; a critical point where |p| is at rounding level is
// reported as a (double) root. An identically zero polynomial returns no roots.
std::vector<double> polynomialRootsInUnitInterval(std::span<const double> coef);

struct GbSolution {
  double t0 = 0.0;       // local parameter of the span where the curve passes through the target
  double lambda0 = 0.0;  // global shape parameter λ0 = 12(1−w)/w
  double w = 0.0;        // 12/(12+λ0), in (0, 3]
};

struct GbFitResult {
  bool reachable = false;
  std::string reason;             // why not reachable (empty when reachable)
  GbSolution bisection;           // the §7.2 bisection answer (filled when the bisection ran)
  std::vector<GbSolution> all;    // every admissible solution (t0 ∈ [0,1], 0 < w ≤ 3), by t0
};

// Constrained modification of docs/math.md §7.2: orientation σ, reachability σF(0) ≥ 0 ≥ σF(1), bisection
// on σF until last − first ≤ tolT (or 64 rounds), w by projection, λ0 = 12(1−w)/w, admissible iff
// 0 < w ≤ 3. `all` lists every root of F in [0,1] with admissible w. Throws ModelError for non-2-D
// data, a span that does not exist, or σ = 0 (degenerate span); an unreachable target is reported
// with reachable = false and a reason.
GbFitResult gbConstrainedModify(const CurveModel& gbCurve, int span, glm::dvec2 target, double tolT = 0x1p-40);

}  // namespace shapespline
