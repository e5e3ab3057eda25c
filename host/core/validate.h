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
void validateSurface(const SurfaceModel& model);

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
