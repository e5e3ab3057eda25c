#include <shapespline/core/bspline.h>

#include <shapespline/core/point_math.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace shapespline {

int findKnotSpan(int order, std::span<const double> knots, int pointCount, double t) {
  const int n = pointCount - 1;
  const int lo = order - 1;
  const double a = knots[lo], b = knots[n + 1];
  if (!(t > a)) t = a;  // also maps NaN to the left end rather than reading out of range
  if (t >= b) {
    // Right end: the last non-empty span, so that C(b) is the limit from the left.
    int j = n;
    while (j > lo && !(knots[j] < knots[j + 1])) --j;
    return j;
  }
  // Largest j in [k-1, n] with t_j <= t; then t < t_{j+1} because t < b = t_{n+1}.
  int left = lo, right = n + 1;  // invariant: t_left <= t < t_right
  while (right - left > 1) {
    const int mid = (left + right) / 2;
    if (t < knots[mid]) right = mid;
    else left = mid;
  }
  return left;
}

static_assert(pm::kMaxBasis == kMaxBasisCount);

namespace {

// Below this width of the knots a span's basis reads, they are scaled (bsplineBasisDerivsScaled).
constexpr int kMinKnotWidthExponent = -500;

glm::dvec3 ldexp3(const glm::dvec3& v, int e) { return {std::ldexp(v.x, e), std::ldexp(v.y, e), std::ldexp(v.z, e)}; }

}  // namespace

namespace {

// bsplineBasisDerivsScaled for degree P known at compile time: point_math.h's loops unroll, the
// arithmetic and its order stay the same (so do the bits), and the list kernel's per-point basis
// costs about half.
template <int P>
[[gnu::flatten]] int basisDerivsScaled(std::span<const double> knots, int span, double t, int derivs,
                      double out[kMaxBasisCount][kMaxBasisCount]) {
  // The NURBS Book A2.3 with p = order-1. Every divisor is a difference of knots that brackets the
  // non-empty span [t_span, t_{span+1}], so it is positive.
  const double width = knots[span + P] - knots[span + 1 - P];
  // ilogb(width) < kMinKnotWidthExponent, without the call for ordinary widths.
  static_assert(kMinKnotWidthExponent == -500);
  const int e = width > 0.0 && width < 0x1p-500 ? -std::ilogb(width) : 0;
  double ndu[kMaxBasisCount][kMaxBasisCount];
  double left[kMaxBasisCount], right[kMaxBasisCount];
  for (int j = 1; j <= P; ++j) {
    left[j] = t - knots[span + 1 - j];  // exact: differences of nearby knots, then 2^e
    right[j] = knots[span + j] - t;
  }
  if (e != 0)  // ldexp by 0 changes no bit, and costs a call per knot
    for (int j = 1; j <= P; ++j) left[j] = std::ldexp(left[j], e), right[j] = std::ldexp(right[j], e);
  pm::bsplineTriangle(P, left, right, ndu);
  const int n = std::min(derivs, P);
  if (n == 0) {
    for (int r = 0; r <= P; ++r) out[0][r] = ndu[r][P];  // bsplineDerivatives' row 0
  } else if (n == 1) {
    pm::bsplineDerivatives(P, 1, ndu, out);
  } else {
    pm::bsplineDerivatives(P, n, ndu, out);
  }
  for (int k = n + 1; k <= derivs; ++k)
    for (int j = 0; j <= P; ++j) out[k][j] = 0.0;  // degree p: higher derivatives vanish
  return e;
}

}  // namespace

int bsplineBasisDerivsScaled(int order, std::span<const double> knots, int span, double t, int derivs,
                             double out[kMaxBasisCount][kMaxBasisCount]) {
  static_assert(kMaxBasisCount == 10, "one case per degree 0..9");
  switch (order - 1) {
    case 0: return basisDerivsScaled<0>(knots, span, t, derivs, out);
    case 1: return basisDerivsScaled<1>(knots, span, t, derivs, out);
    case 2: return basisDerivsScaled<2>(knots, span, t, derivs, out);
    case 3: return basisDerivsScaled<3>(knots, span, t, derivs, out);
    case 4: return basisDerivsScaled<4>(knots, span, t, derivs, out);
    case 5: return basisDerivsScaled<5>(knots, span, t, derivs, out);
    case 6: return basisDerivsScaled<6>(knots, span, t, derivs, out);
    case 7: return basisDerivsScaled<7>(knots, span, t, derivs, out);
    case 8: return basisDerivsScaled<8>(knots, span, t, derivs, out);
    case 9: return basisDerivsScaled<9>(knots, span, t, derivs, out);
    default: throw std::invalid_argument("B-spline order must be 1..10, got " + std::to_string(order));
  }
}

void bsplineBasisAllDerivs(int order, std::span<const double> knots, int span, double t, int derivs,
                           double out[kMaxBasisCount][kMaxBasisCount]) {
  const int e = bsplineBasisDerivsScaled(order, knots, span, t, derivs, out);
  if (e == 0) return;
  for (int k = 1; k <= derivs; ++k)
    for (int j = 0; j < order; ++j) out[k][j] = std::ldexp(out[k][j], k * e);
}

void bsplineBasisDerivs(int order, std::span<const double> knots, int span, double t, int derivs,
                        double out[3][kMaxBasisCount]) {
  double all[kMaxBasisCount][kMaxBasisCount];
  bsplineBasisAllDerivs(order, knots, span, t, derivs, all);
  for (int d = 0; d <= derivs; ++d)
    for (int r = 0; r < order; ++r) out[d][r] = all[d][r];
}

void evalBSplineCurveOnSpan(const BSplineCurveData& curve, int span, double t, int derivs, glm::dvec3* out) {
  double basis[kMaxBasisCount][kMaxBasisCount];
  // Sums of scaled basis derivatives, scaled back once: a derivative that fits fp64 stays finite
  // even where single basis derivatives do not.
  const int e = bsplineBasisDerivsScaled(curve.order, curve.knots, span, t, derivs, basis);
  const int first = span - curve.order + 1;
  for (int d = 0; d <= derivs; ++d) {
    glm::dvec3 sum(0.0);
    for (int r = 0; r < curve.order; ++r) sum += basis[d][r] * curve.points[first + r];
    out[d] = e == 0 ? sum : ldexp3(sum, d * e);
  }
}

BSplineCurvePoint evalBSplineCurve(const BSplineCurveData& curve, double t) {
  const int count = static_cast<int>(curve.points.size());
  const int span = findKnotSpan(curve.order, curve.knots, count, t);
  const double a = curve.knots[curve.order - 1], b = curve.knots[count];
  t = std::clamp(t, a, b);
  const int derivs = std::min(2, curve.order - 1);
  double basis[kMaxBasisCount][kMaxBasisCount] = {};
  const int e = bsplineBasisDerivsScaled(curve.order, curve.knots, span, t, derivs, basis);
  BSplineCurvePoint result;
  const int first = span - curve.order + 1;
  const bool rational = !curve.weights.empty();
  double w[3] = {0.0, 0.0, 0.0};  // W, W', W'' of a rational curve
  for (int r = 0; r < curve.order; ++r) {
    const double wr = rational ? curve.weights[static_cast<size_t>(first + r)] : 1.0;
    const glm::dvec3 p = rational ? wr * curve.points[first + r] : curve.points[first + r];
    result.point += basis[0][r] * p;
    result.d1 += basis[1][r] * p;
    result.d2 += basis[2][r] * p;
    for (int d = 0; d < 3; ++d) w[d] += basis[d][r] * wr;
  }
  // On the scaled derivatives: every term of the quotient rule scales alike.
  if (rational) pm::rationalCurve(result.point, result.d1, result.d2, w[0], w[1], w[2]);
  if (e != 0) result.d1 = ldexp3(result.d1, e), result.d2 = ldexp3(result.d2, 2 * e);
  return result;
}

BSplineSurfacePoint evalBSplineSurface(const BSplineSurfaceData& surface, double u, double v) {
  const int ku = surface.orderU, kv = surface.orderV;
  const int spanU = findKnotSpan(ku, surface.knotsU, surface.rows, u);
  const int spanV = findKnotSpan(kv, surface.knotsV, surface.cols, v);
  u = std::clamp(u, surface.knotsU[ku - 1], surface.knotsU[surface.rows]);
  v = std::clamp(v, surface.knotsV[kv - 1], surface.knotsV[surface.cols]);
  double bu[kMaxBasisCount][kMaxBasisCount] = {}, bv[kMaxBasisCount][kMaxBasisCount] = {};
  const int eu = bsplineBasisDerivsScaled(ku, surface.knotsU, spanU, u, std::min(2, ku - 1), bu);
  const int ev = bsplineBasisDerivsScaled(kv, surface.knotsV, spanV, v, std::min(2, kv - 1), bv);
  const int firstU = spanU - ku + 1, firstV = spanV - kv + 1;
  const bool rational = !surface.weights.empty();
  BSplineSurfacePoint result;
  double w[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};  // W, W_u, W_v, W_uu, W_uv, W_vv of a rational surface
  for (int r = 0; r < ku; ++r) {
    // Contract in v first: one row of the local net gives the row curve and its v-derivatives.
    glm::dvec3 row0(0.0), row1(0.0), row2(0.0);
    double w0 = 0.0, w1 = 0.0, w2 = 0.0;
    const size_t rowStart = static_cast<size_t>(firstU + r) * surface.cols + firstV;
    const glm::dvec3* rowPoints = &surface.points[rowStart];
    for (int s = 0; s < kv; ++s) {
      const double ws = rational ? surface.weights[rowStart + s] : 1.0;
      const glm::dvec3 p = rational ? ws * rowPoints[s] : rowPoints[s];
      row0 += bv[0][s] * p;
      row1 += bv[1][s] * p;
      row2 += bv[2][s] * p;
      w0 += bv[0][s] * ws, w1 += bv[1][s] * ws, w2 += bv[2][s] * ws;
    }
    result.point += bu[0][r] * row0;
    result.du += bu[1][r] * row0;
    result.duu += bu[2][r] * row0;
    result.dv += bu[0][r] * row1;
    result.duv += bu[1][r] * row1;
    result.dvv += bu[0][r] * row2;
    w[0] += bu[0][r] * w0, w[1] += bu[1][r] * w0, w[3] += bu[2][r] * w0;
    w[2] += bu[0][r] * w1, w[4] += bu[1][r] * w1, w[5] += bu[0][r] * w2;
  }
  // On the scaled derivatives: every term of the quotient rule scales alike.
  if (rational)
    pm::rationalSurface(result.point, result.du, result.dv, result.duu, result.duv, result.dvv, w[0], w[1], w[2], w[3],
                        w[4], w[5]);
  result.duDir = result.du, result.dvDir = result.dv;
  if (eu != 0 || ev != 0) {
    result.du = ldexp3(result.du, eu), result.dv = ldexp3(result.dv, ev);
    result.duu = ldexp3(result.duu, 2 * eu), result.duv = ldexp3(result.duv, eu + ev);
    result.dvv = ldexp3(result.dvv, 2 * ev);
  }
  return result;
}

// ---- The list kernel's pieces ------------------------------------------------------------------

int findKnotSpanFrom(int hint, int order, std::span<const double> knots, int pointCount, double t) {
  // Strictly inside the domain, the span is the largest j with t_j <= t; a hint with
  // t_hint <= t < t_{hint+1} is that j. The ends keep findKnotSpan's own rules.
  if (hint >= order - 1 && hint < pointCount && t > knots[order - 1] && t < knots[pointCount] && knots[hint] <= t &&
      t < knots[hint + 1])
    return hint;
  return findKnotSpan(order, knots, pointCount, t);
}

namespace {

// The basis of (span, t) with derivatives 0..derivs (derivs <= 1), from the cache when it holds it.
const KnotBasisCache& cachedBasis(KnotBasisCache& c, int order, std::span<const double> knots, int span, double t,
                                  int derivs) {
  if (c.span == span && c.t == t && c.derivs == derivs) return c;
  double all[kMaxBasisCount][kMaxBasisCount];
  c.exponent = bsplineBasisDerivsScaled(order, knots, span, t, derivs, all);
  for (int d = 0; d <= derivs; ++d)
    for (int r = 0; r < order; ++r) c.basis[d][r] = all[d][r];
  c.span = span, c.t = t, c.derivs = derivs;
  return c;
}

// evalBSplineSurface's sums, in its order, for the point (and with D its first partials).
// Flattened (its basis, lookups and quotient inlined): a fifth more points a second on low-order faces.
template <bool D>
[[gnu::flatten]] BSplineSurfaceFirst surfaceFirst(const BSplineSurfaceData& surface, double u, double v, KnotBasisCache& cacheU,
                                 KnotBasisCache& cacheV) {
  const int ku = surface.orderU, kv = surface.orderV;
  const int spanU = findKnotSpanFrom(cacheU.span, ku, surface.knotsU, surface.rows, u);
  const int spanV = findKnotSpanFrom(cacheV.span, kv, surface.knotsV, surface.cols, v);
  u = std::clamp(u, surface.knotsU[ku - 1], surface.knotsU[surface.rows]);
  v = std::clamp(v, surface.knotsV[kv - 1], surface.knotsV[surface.cols]);
  const KnotBasisCache& bu = cachedBasis(cacheU, ku, surface.knotsU, spanU, u, D ? 1 : 0);
  const KnotBasisCache& bv = cachedBasis(cacheV, kv, surface.knotsV, spanV, v, D ? 1 : 0);
  const int firstU = spanU - ku + 1, firstV = spanV - kv + 1;
  const bool rational = !surface.weights.empty();
  BSplineSurfaceFirst result;
  double w0 = 0.0, wu = 0.0, wv = 0.0;
  for (int r = 0; r < ku; ++r) {
    glm::dvec3 row0(0.0), row1(0.0);
    double rw0 = 0.0, rw1 = 0.0;
    const size_t rowStart = static_cast<size_t>(firstU + r) * surface.cols + firstV;
    const glm::dvec3* rowPoints = &surface.points[rowStart];
    if (rational) {
      for (int s = 0; s < kv; ++s) {
        const double ws = surface.weights[rowStart + s];
        const glm::dvec3 p = ws * rowPoints[s];
        row0 += bv.basis[0][s] * p;
        rw0 += bv.basis[0][s] * ws;
        if constexpr (D) row1 += bv.basis[1][s] * p, rw1 += bv.basis[1][s] * ws;
      }
      w0 += bu.basis[0][r] * rw0;
      if constexpr (D) wu += bu.basis[1][r] * rw0, wv += bu.basis[0][r] * rw1;
    } else {
      for (int s = 0; s < kv; ++s) {
        row0 += bv.basis[0][s] * rowPoints[s];
        if constexpr (D) row1 += bv.basis[1][s] * rowPoints[s];
      }
    }
    if constexpr (D) pm::accumulateTensorRowFirst(result.point, result.du, result.dv, bu.basis[0][r], bu.basis[1][r], row0, row1);
    else result.point += bu.basis[0][r] * row0;
  }
  if constexpr (D) {
    if (rational) pm::rationalSurfaceFirst(result.point, result.du, result.dv, w0, wu, wv);
    if (bu.exponent != 0) result.du = ldexp3(result.du, bu.exponent);
    if (bv.exponent != 0) result.dv = ldexp3(result.dv, bv.exponent);
  } else if (rational) {
    pm::rationalPoint(result.point, w0);
  }
  return result;
}

}  // namespace

BSplineCurveFirst evalBSplineCurveFirst(const BSplineCurveData& curve, double t, bool derivatives,
                                        KnotBasisCache& cache) {
  const int count = static_cast<int>(curve.points.size());
  const int span = findKnotSpanFrom(cache.span, curve.order, curve.knots, count, t);
  t = std::clamp(t, curve.knots[curve.order - 1], curve.knots[count]);
  const int derivs = derivatives ? 1 : 0;
  const KnotBasisCache& b = cachedBasis(cache, curve.order, curve.knots, span, t, derivs);
  BSplineCurveFirst result;
  const int first = span - curve.order + 1;
  const bool rational = !curve.weights.empty();
  double w0 = 0.0, w1 = 0.0;
  for (int r = 0; r < curve.order; ++r) {
    const double wr = rational ? curve.weights[static_cast<size_t>(first + r)] : 1.0;
    const glm::dvec3 p = rational ? wr * curve.points[first + r] : curve.points[first + r];
    result.point += b.basis[0][r] * p;
    w0 += b.basis[0][r] * wr;
    if (derivatives) result.d1 += b.basis[1][r] * p, w1 += b.basis[1][r] * wr;
  }
  if (!derivatives) {
    if (rational) pm::rationalPoint(result.point, w0);
    return result;
  }
  if (rational) pm::rationalCurveFirst(result.point, result.d1, w0, w1);
  if (b.exponent != 0) result.d1 = ldexp3(result.d1, b.exponent);
  return result;
}

BSplineSurfaceFirst evalBSplineSurfaceFirst(const BSplineSurfaceData& surface, double u, double v, bool derivatives,
                                            KnotBasisCache& cacheU, KnotBasisCache& cacheV) {
  return derivatives ? surfaceFirst<true>(surface, u, v, cacheU, cacheV)
                     : surfaceFirst<false>(surface, u, v, cacheU, cacheV);
}

namespace {

void checkKnotVector(const std::string& field, const std::vector<double>& knots, int order, int count) {
  if (static_cast<int>(knots.size()) != count + order)
    throw ModelError(field, "length " + std::to_string(knots.size()),
                     "a B-spline knot vector has N + order = " + std::to_string(count + order) + " values");
  for (size_t i = 1; i < knots.size(); ++i)
    if (!(knots[i] >= knots[i - 1]))
      throw ModelError(field + "[" + std::to_string(i) + "]", std::to_string(knots[i]), "knots must be non-decreasing");
  for (size_t i = 0, run = 1; i + 1 < knots.size(); ++i) {
    run = knots[i + 1] == knots[i] ? run + 1 : 1;
    if (static_cast<int>(run) > order)
      throw ModelError(field + "[" + std::to_string(i + 1) + "]", std::to_string(knots[i + 1]),
                       "no knot may be repeated more than order times");
  }
  if (!(knots[order - 1] < knots[count]))
    throw ModelError(field, "", "the domain [t_{k-1}, t_N] must be non-empty");
}

}  // namespace

BSplineCurveData bsplineCurveFromModel(const CurveModel& model) {
  if (model.family.construction != Construction::BSpline)
    throw ModelError("construction", std::string(constructionName(model.family.construction)),
                     "a knot-vector B-spline is required");
  if (model.closed) throw ModelError("closed", "true", "a B-spline with a knot vector must be open");
  const int order = model.family.order;
  if (order < 2 || order > kMaxBasisCount)
    throw ModelError("order", std::to_string(order), "B-spline order must be 2..10");
  const int count = static_cast<int>(model.points.size());
  if (count < order) throw ModelError("points", std::to_string(count), "an order-k B-spline needs N >= k points");
  checkKnotVector("knots", model.knots, order, count);
  return BSplineCurveData{order, model.knots, model.points, model.weights};
}

BSplineSurfaceData bsplineSurfaceFromModel(const SurfaceModel& model) {
  if (model.family.construction != Construction::BSpline)
    throw ModelError("construction", std::string(constructionName(model.family.construction)),
                     "a knot-vector B-spline surface is required");
  if (model.closedU || model.closedV) throw ModelError("closed", "", "a B-spline with knot vectors must be open");
  BSplineSurfaceData s;
  s.orderU = model.family.order;
  s.orderV = model.orderV;
  for (auto [name, k] : {std::pair{"order[0]", s.orderU}, std::pair{"order[1]", s.orderV}})
    if (k < 2 || k > kMaxBasisCount) throw ModelError(name, std::to_string(k), "B-spline order must be 2..10");
  s.rows = model.rows;
  s.cols = model.cols;
  if (s.rows < s.orderU || s.cols < s.orderV)
    throw ModelError("points", std::to_string(s.rows) + "x" + std::to_string(s.cols),
                     "an order k x l B-spline surface needs at least k rows and l columns");
  checkKnotVector("knots[0]", model.knotsU, s.orderU, s.rows);
  checkKnotVector("knots[1]", model.knotsV, s.orderV, s.cols);
  s.knotsU = model.knotsU;
  s.knotsV = model.knotsV;
  s.points = model.points;
  s.weights = model.weights;
  return s;
}

std::vector<glm::dvec4> homogeneousPoints(std::span<const glm::dvec3> points, std::span<const double> weights) {
  std::vector<glm::dvec4> out(points.size());
  for (size_t i = 0; i < points.size(); ++i) out[i] = glm::dvec4(weights[i] * points[i], weights[i]);
  return out;
}

SpanBasis knotIntervalBasis(int order, std::span<const double> knots, int span) {
  double out[kMaxBasisCount][kMaxBasisCount];
  const int e = bsplineBasisDerivsScaled(order, knots, span, knots[span], order - 1, out);
  // out[d] are derivatives with respect to 2^e t: times (2^e h)^d / d! (2^e h is moderate even where
  // h underflows its d-th power).
  const double scaledH = std::ldexp(knots[span + 1] - knots[span], e);
  SpanBasis b;
  b.count = order;
  b.degree = order - 1;
  b.centre = (order - 1) / 2;
  double factor = 1.0;  // (2^e h)^d / d!
  for (int d = 0; d < order; ++d) {
    for (int r = 0; r < order; ++r) b.coef[r][d] = out[d][r] * factor;
    factor *= scaledH / double(d + 1);
  }
  return b;
}

}  // namespace shapespline
