#pragma once
// Extending B-splines to target points by unclamping and inverse de Boor (docs/math.md §10.2–§10.6,
// [EXT] Hu, Tai & Zhang, with the corrections C32/C33 and the generalisations R11/R12).
#include <shapespline/core/bspline.h>

#include <optional>
#include <span>
#include <vector>

namespace shapespline {

// Algorithm U (docs/math.md §10.2, Piegl–Tiller in-place order, R12): the right-clamped curve rewritten on
// the knots t_0..t_{n+1}, newRightKnots (= t_{n+2}..t_{n+k}, k−1 values, non-decreasing, all > b).
// The result equals the input on [t_{k−1}, b]. Throws ModelError when the input is not right-clamped,
// an interior knot equals b, or the new knots break their rule.
BSplineCurveData unclampRight(const BSplineCurveData& curve, std::span<const double> newRightKnots);

// Chord-length parameters u_1..u_m of the targets (docs/math.md §10.3, [EXT] eq. 7/10 scaled by b − a):
// u_s = u_{s−1} + (b − a)|R_s − R_{s−1}|/L, u_0 = b, R_0 = P_n, L = sum over spans of |C(t_{i+1}) − C(t_i)|.
std::vector<double> chordParameters(const BSplineCurveData& curve, std::span<const glm::dvec3> targets);

// Algorithm X (docs/math.md §10.4, corrected inverse de Boor): Q_j such that the curve with control
// points Q_0..Q_j on `knots` passes through `target` at τ = t_{j+1}. Needs t_j < t_{j+1}.
glm::dvec3 inverseDeBoor(int order, std::span<const double> knots, std::span<const glm::dvec3> known, int j,
                         const glm::dvec3& target);

struct ExtensionResult {
  std::vector<double> u;                    // target parameters u_1..u_m
  std::vector<double> unclampKnots;         // K_unc (n + k + 1 values)
  std::vector<glm::dvec3> unclampedPoints;  // Algorithm U output Q_0..Q_n
  BSplineCurveData curve;                   // final curve: Q_0..Q_{n+m} on K_final (n + m + k + 1 knots)
  std::vector<double> knotsNormalized;      // (t − a)/(u_m − a): the same curve on [0,1]
};

// Extension of a right-clamped order-k curve to m ≥ 1 targets (docs/math.md §10.5): Algorithm U on K_unc,
// Algorithm X for R_1..R_{m−1}, Q_{n+m} = R_m. `givenU` (strictly increasing, > b) replaces the chord
// parameters. The result equals the input on [a, b], passes through R_s at u_s and is C^{k−2} at b
// and at every u_s, s < m. Validation per docs/math.md §11 (ModelError).
ExtensionResult extendCurve(const BSplineCurveData& curve, std::span<const glm::dvec3> targets,
                            std::optional<std::vector<double>> givenU = std::nullopt);

struct SurfaceExtensionResult {
  std::vector<double> u;                     // common target parameters u_1..u_m
  std::vector<std::vector<double>> uPerColumn;  // chord only: uPerColumn[j][s−1] of column j; else empty
  BSplineSurfaceData surface;                // rows + m rows on U_final, V unchanged
  std::vector<double> knotsNormalizedU;      // (t − a)/(u_m − a)
};

// Surface extension in u (docs/math.md §10.6, [EXT] §4): every column j is extended with the targets
// targetCurves[s][j] (each target curve has `cols` control points on the surface's V knots and v
// order) at common parameters: `givenU`, or the per-column chord parameters averaged over the columns.
// The surface at u_s equals target curve s.
SurfaceExtensionResult extendSurfaceU(const BSplineSurfaceData& surface,
                                      std::span<const std::vector<glm::dvec3>> targetCurves,
                                      std::optional<std::vector<double>> givenU = std::nullopt);

// `model` (the extended one) with the result's control points, knots and weights (rational
// models), ready for validate / Curve::create.
CurveModel extendedModel(CurveModel model, const ExtensionResult& result);
SurfaceModel extendedModel(SurfaceModel model, const SurfaceExtensionResult& result);

}  // namespace shapespline
