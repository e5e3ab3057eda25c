#pragma once
// General B-splines on an arbitrary non-decreasing knot vector (docs/math.md §10.1), de Boor–Cox.
// Order k (degree k-1), control points P_0..P_n, knots t_0..t_{n+k}; domain [t_{k-1}, t_{n+1}].
#include <shapespline/core/span_basis.h>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <span>
#include <vector>

namespace shapespline {

struct BSplineCurveData {
  int order = 0;
  std::vector<double> knots;          // n + 1 + order values
  std::vector<glm::dvec3> points;     // n + 1 points
  std::vector<double> weights;        // rational: one per point (docs/math.md §10.8); empty: all 1
};

// Index j of the non-empty knot span [t_j, t_{j+1}) containing t, k-1 <= j <= n; at the right end
// of the domain the last non-empty span. t is clamped to the domain.
int findKnotSpan(int order, std::span<const double> knots, int pointCount, double t);

// Non-zero basis functions N_{j-k+1+r}(t), r = 0..k-1, and their first `derivs` (<= 2) derivatives:
// out[d][r]. `span` from findKnotSpan.
void bsplineBasisDerivs(int order, std::span<const double> knots, int span, double t, int derivs,
                        double out[3][kMaxBasisCount]);

struct BSplineCurvePoint {
  glm::dvec3 point{0.0}, d1{0.0}, d2{0.0};  // derivatives with respect to t (the knot parameter)
};
BSplineCurvePoint evalBSplineCurve(const BSplineCurveData& curve, double t);

struct BSplineSurfaceData {
  int orderU = 0, orderV = 0;
  std::vector<double> knotsU, knotsV;
  int rows = 0, cols = 0;              // rows along u (i), columns along v (j)
  std::vector<glm::dvec3> points;      // row-major points[i * cols + j]
  std::vector<double> weights;         // rational: one per point, row-major (§10.8); empty: all 1
};
struct BSplineSurfacePoint {
  glm::dvec3 point{0.0}, du{0.0}, dv{0.0}, duu{0.0}, duv{0.0}, dvv{0.0};
  // du and dv divided by powers of two (exact; equal to du, dv unless knot intervals are below
  // about 1e-150): finite where du, dv overflow fp64 (intervals near 1e-310), with the same normal.
  glm::dvec3 duDir{0.0}, dvDir{0.0};
};
BSplineSurfacePoint evalBSplineSurface(const BSplineSurfaceData& surface, double u, double v);

// ---- The list kernel's pieces (core/list_eval.h): only the point, or the point and first
// derivatives, bit for bit those of evalBSplineCurve / evalBSplineSurface -------------------------

// findKnotSpan, trying `hint` first (the span of the list's previous parameter in this direction):
// a list sorted or grouped by parameter finds its span without the binary search. The same result
// as findKnotSpan for every hint (-1: none).
int findKnotSpanFrom(int hint, int order, std::span<const double> knots, int pointCount, double t);

// One direction's basis (values, and first derivatives when derivs is 1) at the last parameter a
// list asked for, reused when the next asks for the same span and parameter: on a list laid out in
// rows of one u, the u basis is computed once a row.
struct KnotBasisCache {
  int span = -1, derivs = -1, exponent = 0;
  double t = 0.0;
  double basis[2][kMaxBasisCount] = {};
};

struct BSplineCurveFirst {
  glm::dvec3 point{0.0}, d1{0.0};
};
struct BSplineSurfaceFirst {
  glm::dvec3 point{0.0}, du{0.0}, dv{0.0};
};
// evalBSplineCurve's point and d1 (derivatives false: the point alone, d1 left 0), the same bits.
BSplineCurveFirst evalBSplineCurveFirst(const BSplineCurveData& curve, double t, bool derivatives,
                                        KnotBasisCache& cache);
// evalBSplineSurface's point, du and dv (derivatives false: the point alone), the same bits.
BSplineSurfaceFirst evalBSplineSurfaceFirst(const BSplineSurfaceData& surface, double u, double v, bool derivatives,
                                            KnotBasisCache& cacheU, KnotBasisCache& cacheV);

// Additions (extension module and its tests).

// bsplineBasisAllDerivs on knot differences scaled by 2^e, returning e (0 unless the knots the span
// reads are narrower than 2^-500, as near 1e-310): out[k] are derivatives with respect to 2^e t, so
// d^k/dt^k = 2^(k e) out[k]. The quotients N / (t_i - t_j) of the recurrence then stay finite.
int bsplineBasisDerivsScaled(int order, std::span<const double> knots, int span, double t, int derivs,
                             double out[kMaxBasisCount][kMaxBasisCount]);
// General form of bsplineBasisDerivs: derivatives 0..derivs (<= order-1) of the non-zero basis
// functions at t on the given span, out[d][r] (Piegl & Tiller, The NURBS Book, A2.3). The span's
// polynomial is used even when t lies outside [t_span, t_{span+1}] (one-sided limits at knots).
void bsplineBasisAllDerivs(int order, std::span<const double> knots, int span, double t, int derivs,
                           double out[kMaxBasisCount][kMaxBasisCount]);

// Derivatives 0..derivs (<= order-1) with respect to t of the polynomial piece of `span`, written to
// out[0..derivs]. With span = findKnotSpan(t) this is the ordinary evaluation; with the span to the
// left of a knot it gives the left-sided limits there (used to test continuity, docs/math.md §10.5).
void evalBSplineCurveOnSpan(const BSplineCurveData& curve, int span, double t, int derivs, glm::dvec3* out);

// The homogeneous control points (w P, w) of a rational B-spline (docs/math.md §10.8), which the
// CPU grid sampler and the GPU kernels (NET) contract in place of P; `weights` one per point.
std::vector<glm::dvec4> homogeneousPoints(std::span<const glm::dvec3> points, std::span<const double> weights);

// The `order` basis functions N_{span-order+1+r} on the non-empty interval [t_span, t_span+1] as
// polynomials in the local parameter s = (t - t_span) / h, h = t_span+1 - t_span, in the power basis
// of a uniform family's SpanBasis (coef[r][d], Taylor coefficients at s = 0: N^(d)(t_span) h^d / d!),
// so that the uniform patch kernels can evaluate the interval as a patch (derivatives with respect
// to s: divide by h^k for the knot parameter's). Knots narrower than 2^-500 stay finite (the
// scaled recurrence).
SpanBasis knotIntervalBasis(int order, std::span<const double> knots, int span);

// The knot-vector B-spline of a `bspline` model with `knots` (docs/math.md §10.1). Throws ModelError when
// the model is not a knot-vector B-spline (construction, closed, knot count).
BSplineCurveData bsplineCurveFromModel(const CurveModel& model);
BSplineSurfaceData bsplineSurfaceFromModel(const SurfaceModel& model);

}  // namespace shapespline
