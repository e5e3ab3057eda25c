#pragma once
// Typed validation of curve and surface models: every rule of docs/math.md §11 (and the matching
// docs/format.md rules) that can be checked on typed data. The JSON reader (io/model_json.h) calls these
// after building the model; code that builds models by hand should call them too. Inner kernels
// assume models that passed.
//
// Rules checked (section numbers are docs/math.md):
//   degree 4..6 for extended_bspline / alpha_eb (§2); lambda finite and inside the family's domain:
//   Xu-Wang [-k(k-2), 1] (§2.2), GB [-8, inf) (§7.1), UBP [lambda_min(k), 1] (§8.2 table);
//   order 3..10 for ubp/gubp, 2..10 for bspline (§8.2, §10.1); mu: floor(k/2)+1 values in [0,1]
//   whose full symmetric vector has even and odd sums 1 within 1e-9 (§9); alpha only for alpha_eb,
//   one value per point, each in (0,1] (§4, §5, R13); minimum point counts per direction (docs/format.md
//   "Minimum sizes", §1, §4.1, §5.1); finite coordinates, curve dimension 2 or 3; span knots only
//   for extended_bspline / gb curves, spans + 1 values, strictly increasing (§1); B-spline knot
//   vectors: N + order values, non-decreasing, t_{k-1} < t_N, multiplicity <= order, open only (§10.1).
//
// Errors are ModelError(field, value, rule) with JSON-path field names as written in a model file:
// "lambda", "mu[1]", "alpha[3]", "alpha[1][2]", "points[2][1]", "knots[4]", "knots[1][0]", "order[0]".
#include <shapespline/core/model.h>

namespace shapespline {

// Throws ModelError for the first rule `model` breaks.
void validateCurve(const CurveModel& model);
// A surface's shape rules (validateSurfaceShape), then its values' (checkSurfaceCoordinates,
// checkSurfaceAlphas, the weights').
void validateSurface(const SurfaceModel& model);

// How many points, α and weights a surface's arrays hold.
struct SurfaceCounts {
  size_t points = 0, alpha = 0, weights = 0;
};
// Every rule of validateSurface but those on the values of the points, α and weights, for arrays
// of `counts` values that need not be read (`model`'s own arrays are not looked at): a net
// streamed from its file is checked by this, then by the value rules below a run at a time.
void validateSurfaceShape(const SurfaceModel& model, const SurfaceCounts& counts);
// Every rule of validateCurve but those on the values of the points, α and weights, for a curve of
// counts.points points (its own points not read) and arrays of `counts` values: a curve streamed
// from its files (io/streamed_bands.h streamCurveSpans checks the values).
void validateCurveShape(const CurveModel& model, const SurfaceCounts& counts);
// The value rules on a run of `count` points or α starting at flat index `first` of a surface
// with `cols` columns (row-major; the error names points[i][j][c] or alpha[i][j]).
void checkSurfaceCoordinates(const glm::dvec3* points, size_t count, size_t first, int cols);
void checkSurfaceAlphas(const double* alpha, size_t count, size_t first, int cols);
// The α rule on a run of a curve's α from index `first` (the error names alpha[i]).
void checkCurveAlphas(const double* alpha, size_t count, size_t first);
// Likewise a run of weights and their points (docs/math.md §10.8: w > 0 finite, w P finite).
void checkSurfaceWeights(const double* weights, const glm::dvec3* points, size_t count, size_t first, int cols);

// The family-only part (degree/order, lambda, mu) shared by curves and surfaces. `orderV` is the
// v order of a bspline surface (0 for curves); a bspline surface reports "order[0]"/"order[1]".
void validateFamily(const FamilySpec& family, int orderV = 0, bool isSurface = false);

// The closed interval a family's lambda must lie in (checkLambda's rule): Xu-Wang [-k(k-2), 1],
// GB [-8, inf), UBP [lambda_min(k), 1]; [0, 0] for families without lambda (familyOf(c).usesLambda).
struct LambdaDomain {
  double lo, hi;
};
LambdaDomain lambdaDomain(const FamilySpec& family);

// lambda_min(k) of docs/math.md §8.2 for UBP order k = 2..10 (exact rationals rounded once).
double ubpLambdaMin(int order);

}  // namespace shapespline
