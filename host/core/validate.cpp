#include <shapespline/core/validate.h>
#include <shapespline/core/value_scan.h>
#include <shapespline/core/value_text.h>

#include <charconv>
#include <cmath>
#include <string>

namespace shapespline {

namespace {

std::string idx(const std::string& base, size_t i) { return base + "[" + std::to_string(i) + "]"; }

[[noreturn]] void fail(std::string field, std::string value, std::string rule) {
  throw ModelError(std::move(field), std::move(value), std::move(rule));
}

std::string cname(Construction c) { return std::string(constructionName(c)); }

void checkOrder(int order, Construction c, const std::string& field) {
  const int lo = familyOf(c).minOrder;
  if (order < lo || order > 10) {
    std::string rule = cname(c) + " order must be an integer in " + std::to_string(lo) + "..10";
    if (lo > 2) rule += " (order 2 is only the seed function)";
    fail(field, std::to_string(order), rule);
  }
}

void checkLambda(const FamilySpec& f) {
  const double l = f.lambda;
  if (!std::isfinite(l)) fail("lambda", shortestText(l), "lambda must be a finite number");
  const double lo = lambdaDomain(f).lo;
  switch (f.construction) {
    case Construction::ExtendedBSpline:
    case Construction::AlphaEB: {
      const int k = f.degree;
      if (l < lo || l > 1.0)
        fail("lambda", shortestText(l),
             "Xu-Wang degree-" + std::to_string(k) + " lambda must lie in [" + shortestText(lo) + ", 1] (docs/math.md §2.2)");
      return;
    }
    case Construction::GB:
      // -12 is a pole and (-12,-8) gives negative weights (docs/math.md §7.1); no upper bound.
      if (l < lo) fail("lambda", shortestText(l), "GB lambda must be >= -8 (docs/math.md §7.1)");
      return;
    case Construction::UBP: {
      if (l < lo || l > 1.0)
        fail("lambda", shortestText(l),
             "UBP order-" + std::to_string(f.order) + " lambda must lie in [lambda_min = " + shortestText(lo) +
                 ", 1] (docs/math.md §8.2)");
      return;
    }
    case Construction::GUBP:
    case Construction::BSpline:
      // These families have no lambda; a non-zero one means the caller meant another family.
      if (l != 0.0) fail("lambda", shortestText(l), "lambda is not used by construction " + cname(f.construction));
      return;
  }
}

// docs/math.md §9: the model carries mu_0..mu_{floor(k/2)}; the full vector mu_0..mu_k is symmetric and
// its even-index and odd-index sums must both be 1.
void checkMu(const FamilySpec& f) {
  const int k = f.order;
  const size_t want = static_cast<size_t>(k / 2 + 1);
  if (f.mu.size() != want)
    fail("mu", std::to_string(f.mu.size()) + " values",
         "GUBP order " + std::to_string(k) + " needs exactly floor(k/2)+1 = " + std::to_string(want) + " mu values");
  for (size_t i = 0; i < f.mu.size(); ++i) {
    const double m = f.mu[i];
    if (!std::isfinite(m) || m < 0.0 || m > 1.0) fail(idx("mu", i), shortestText(m), "each mu must lie in [0, 1]");
  }
  double even = 0.0, odd = 0.0;
  for (int i = 0; i <= k; ++i) {
    const double m = f.mu[static_cast<size_t>(i <= k / 2 ? i : k - i)];
    (i % 2 == 0 ? even : odd) += m;
  }
  constexpr double kSumTol = 1e-9;
  if (std::abs(even - 1.0) > kSumTol || std::abs(odd - 1.0) > kSumTol)
    fail("mu", "even sum " + shortestText(even) + ", odd sum " + shortestText(odd),
         "GUBP parity sums of the full symmetric mu vector must both equal 1 (docs/math.md §9)");
}

// Fewest points an open/closed direction needs (docs/format.md "Minimum sizes").
int minPoints(Construction c, int order, bool closed) {
  if (closed) return 3;
  const int fixed = familyOf(c).minOpenPoints;
  return fixed > 0 ? fixed : order;
}

std::string minRule(Construction c, int order, bool closed, const std::string& what, const std::string& unit) {
  const int m = minPoints(c, order, closed);
  std::string s = closed ? "a closed " : "an open ";
  s += cname(c) + " " + what + " needs at least " + std::to_string(m) + " " + unit;
  if (!closed && familyOf(c).usesOrder) s += " (order " + std::to_string(order) + ")";
  return s;
}

// Knot differences (interval widths, the parameter range, texture coordinates u - t_0) must be
// finite: knots of opposite sign near 1.7e308 are finite each, but their difference overflows, and
// every parameter derived from it (global u, CSV/PLY/OBJ texture coordinates) would be NaN. The
// knots are sorted, so t_i - t_0 is the largest difference involving t_i.
void checkKnotRange(const std::vector<double>& t, const std::string& field) {
  for (size_t i = 1; i < t.size(); ++i)
    if (!std::isfinite(t[i] - t[0]))
      fail(idx(field, i), shortestText(t[i]),
           "knot differences must be finite in fp64 (t_" + std::to_string(i) + " - t_0 = " + shortestText(t[i]) + " - (" +
               shortestText(t[0]) + ") overflows)");
}

// Full B-spline knot vector of n control points and order k (docs/math.md §10.1). `field` is the JSON path
// of the vector ("knots" or "knots[0]").
void checkKnotVector(const std::vector<double>& t, size_t n, int k, const std::string& field) {
  const size_t want = n + static_cast<size_t>(k);
  if (t.size() != want)
    fail(field, std::to_string(t.size()) + " knots",
         "knot vector length must be N + order = " + std::to_string(n) + " + " + std::to_string(k) + " = " +
             std::to_string(want));
  for (size_t i = 0; i < t.size(); ++i)
    if (!std::isfinite(t[i])) fail(idx(field, i), shortestText(t[i]), "knots must be finite numbers");
  for (size_t i = 1; i < t.size(); ++i)
    if (t[i] < t[i - 1])
      fail(idx(field, i), shortestText(t[i]), "knots must be non-decreasing (previous knot " + shortestText(t[i - 1]) + ")");
  for (size_t i = 0; i < t.size();) {
    size_t j = i;
    while (j < t.size() && t[j] == t[i]) ++j;
    if (j - i > static_cast<size_t>(k))
      fail(idx(field, i), shortestText(t[i]),
           "knot multiplicity " + std::to_string(j - i) + " exceeds the order " + std::to_string(k));
    i = j;
  }
  const double a = t[static_cast<size_t>(k - 1)], b = t[n];
  if (!(a < b))
    fail(field, "t_{k-1} = " + shortestText(a) + ", t_N = " + shortestText(b), "the domain must be non-empty: t_{k-1} < t_N");
  checkKnotRange(t, field);
}

// The field names of the per-point checks are built only for a value that fails: a 4096^2 net
// would otherwise format 16 million names it never shows.
template <class FieldName>
void checkAlphaValue(double a, FieldName field) {
  if (!std::isfinite(a) || a <= 0.0 || a > 1.0)
    fail(field(), shortestText(a), a == 0.0 ? "alpha must be in (0,1]: alpha = 0 makes V_j undefined" : "alpha must be in (0,1]");
}

// Every α finite and in (0,1]: two vectorised passes, so that only a net that breaks the rule is
// checked value by value (to name the first one that does).
bool alphaValuesInRange(const double* alpha, size_t count) {
  if (count == 0 || firstNonFinite(alpha, count) < count) return false;
  const ValueRange r = valueRange(alpha, count);
  return r.min > 0.0 && r.max <= 1.0;
}

}  // namespace

LambdaDomain lambdaDomain(const FamilySpec& f) {
  switch (f.construction) {
    case Construction::ExtendedBSpline:
    case Construction::AlphaEB: return {-static_cast<double>(f.degree * (f.degree - 2)), 1.0};
    case Construction::GB: return {-8.0, INFINITY};
    case Construction::UBP: return {ubpLambdaMin(f.order), 1.0};
    case Construction::GUBP:
    case Construction::BSpline: break;
  }
  return {0.0, 0.0};
}

double ubpLambdaMin(int order) {
  // docs/math.md §8.2: exact minimum of N_{0,k} at x = k/2, as rationals rounded once to double.
  switch (order) {
    case 2: return -2.0;
    case 3: return -6.0;
    case 4: return -8.0;
    case 5: return -1150.0 / 107.0;
    case 6: return -66.0 / 5.0;
    case 7: return -82418.0 / 5239.0;
    case 8: return -4832.0 / 265.0;
    case 9: return -14025042.0 / 676177.0;
    case 10: return -156190.0 / 6719.0;
    default: return NAN;
  }
}

void validateFamily(const FamilySpec& f, int orderV, bool isSurface) {
  const Construction c = f.construction;
  const FamilyTraits& traits = familyOf(c);
  if (traits.usesDegree && (f.degree < 4 || f.degree > 6))
    fail("degree", std::to_string(f.degree), "degree must be 4, 5 or 6");
  if (traits.usesOrder) {
    const bool twoOrders = isSurface && traits.twoOrders;
    checkOrder(f.order, c, twoOrders ? "order[0]" : "order");
    if (twoOrders) {
      checkOrder(orderV, c, "order[1]");
    } else if (isSurface && orderV != 0 && orderV != f.order) {
      fail("order", std::to_string(f.order) + " / " + std::to_string(orderV),
           cname(c) + " surfaces use one order for both directions");
    }
  }
  checkLambda(f);
  if (traits.usesMu) {
    checkMu(f);
  } else if (!f.mu.empty()) {
    fail("mu", std::to_string(f.mu.size()) + " values", "mu is only used by gubp, not by " + cname(c));
  }
}

namespace {

// docs/math.md §10.8: a positive finite weight, and w P finite (the homogeneous point the
// evaluation sums).
template <class FieldName>
void checkWeight(double w, const glm::dvec3& p, FieldName field) {
  if (!std::isfinite(w) || !(w > 0.0)) fail(field(), shortestText(w), "a weight must be a positive finite number");
  const glm::dvec3 h = w * p;
  if (!std::isfinite(h.x) || !std::isfinite(h.y) || !std::isfinite(h.z))
    fail(field(), shortestText(w), "weight times point overflows fp64 (the homogeneous point w P must be finite)");
}

// Weights belong to knot-vector B-splines only, one per point.
void checkWeightsAllowed(size_t weights, size_t points, Construction c, bool knotVector, const std::string& shape) {
  if (weights == 0) return;
  if (c != Construction::BSpline || !knotVector)
    fail("weights", std::to_string(weights) + " values",
         "weights are only allowed for bspline models with a knot vector (a rational B-spline)");
  if (weights != points)
    fail("weights", std::to_string(weights) + " values", "weights must have one value per point (" + shape + ")");
}

}  // namespace

namespace {

// validateCurve's rules in its order, for a curve of `counts` points, α and weights; the values of
// the points, α and weights only when `values` (an outline's are streamed and checked later).
void checkCurve(const CurveModel& m, const SurfaceCounts& counts, bool values) {
  const FamilySpec& f = m.family;
  const Construction c = f.construction;
  validateFamily(f);

  if (m.dimension != 2 && m.dimension != 3)
    fail("points", "dimension " + std::to_string(m.dimension), "curve points must have 2 or 3 coordinates");
  const size_t n = counts.points;
  if (n < static_cast<size_t>(minPoints(c, f.order, m.closed)))
    fail("points", std::to_string(n) + " points", minRule(c, f.order, m.closed, "curve", "points"));
  for (size_t i = 0; values && i < n; ++i) {
    for (int d = 0; d < m.dimension; ++d)
      if (!std::isfinite(m.points[i][d]))
        fail(idx(idx("points", i), static_cast<size_t>(d)), shortestText(m.points[i][d]), "coordinates must be finite numbers");
    if (m.dimension == 2 && m.points[i].z != 0.0)
      fail(idx("points", i), "z = " + shortestText(m.points[i].z), "points of a 2-D curve must carry z = 0");
  }

  if (c == Construction::AlphaEB) {
    if (counts.alpha == 0) fail("alpha", "missing", "alpha is required for alpha_eb");
    if (counts.alpha != n)
      fail("alpha", std::to_string(counts.alpha) + " values",
           "alpha array length must equal the number of points (" + std::to_string(n) + ")");
    if (values) checkCurveAlphas(m.alpha.data(), n, 0);
  } else if (counts.alpha != 0) {
    fail("alpha", std::to_string(counts.alpha) + " values", "alpha is only allowed for alpha_eb, not " + cname(c));
  }

  checkWeightsAllowed(counts.weights, n, c, !m.knots.empty(), std::to_string(n));
  for (size_t i = 0; values && i < m.weights.size(); ++i)
    checkWeight(m.weights[i], m.points[i], [&] { return idx("weights", i); });

  if (m.knots.empty()) return;
  if (c == Construction::ExtendedBSpline || c == Construction::GB) {
    // docs/math.md §1 / R3: one boundary per span plus one; open 4-function curves have N-3 spans.
    const size_t spans = m.closed ? n : n - 3;
    if (m.knots.size() != spans + 1)
      fail("knots", std::to_string(m.knots.size()) + " knots",
           "span knots must number spans + 1 = " + std::to_string(spans + 1));
    for (size_t i = 0; i < m.knots.size(); ++i)
      if (!std::isfinite(m.knots[i])) fail(idx("knots", i), shortestText(m.knots[i]), "knots must be finite numbers");
    for (size_t i = 1; i < m.knots.size(); ++i)
      if (!(m.knots[i] > m.knots[i - 1]))
        fail(idx("knots", i), shortestText(m.knots[i]),
             "span knots must be strictly increasing (previous knot " + shortestText(m.knots[i - 1]) + ")");
    checkKnotRange(m.knots, "knots");
  } else if (c == Construction::BSpline) {
    if (m.closed) fail("closed", "true", "a bspline with a knot vector must be open (closed = false)");
    checkKnotVector(m.knots, n, f.order, "knots");
  } else {
    fail("knots", std::to_string(m.knots.size()) + " knots", "knots are not used by construction " + cname(c));
  }
}

}  // namespace

void validateCurve(const CurveModel& m) { checkCurve(m, {m.points.size(), m.alpha.size(), m.weights.size()}, true); }

void validateCurveShape(const CurveModel& m, const SurfaceCounts& counts) { checkCurve(m, counts, false); }

// docs/format.md "Trim": closed loops of at least 3 finite (U,V) points inside the knot domain
// (widened by the tolerance), and a finite tolerance >= 0.
void checkTrim(const SurfaceModel& m, int orderU, int orderV) {
  const TrimLoops& t = m.trim;
  if (!std::isfinite(t.tolerance) || t.tolerance < 0.0)
    fail("trim.tolerance", shortestText(t.tolerance), "the trim tolerance must be a finite number >= 0");
  const double u0 = m.knotsU[static_cast<size_t>(orderU - 1)], u1 = m.knotsU[static_cast<size_t>(m.rows)];
  const double v0 = m.knotsV[static_cast<size_t>(orderV - 1)], v1 = m.knotsV[static_cast<size_t>(m.cols)];
  for (size_t l = 0; l < t.loops.size(); ++l) {
    const std::string loop = idx("trim.loops", l);
    if (t.loops[l].size() < 3)
      fail(loop, std::to_string(t.loops[l].size()) + " points", "a trim loop needs at least 3 points");
    for (size_t p = 0; p < t.loops[l].size(); ++p) {
      const glm::dvec2 q = t.loops[l][p];
      if (!std::isfinite(q.x) || !std::isfinite(q.y))
        fail(idx(loop, p), shortestText(q.x) + ", " + shortestText(q.y), "trim points must be finite numbers");
      if (q.x < u0 - t.tolerance || q.x > u1 + t.tolerance || q.y < v0 - t.tolerance || q.y > v1 + t.tolerance)
        fail(idx(loop, p), shortestText(q.x) + ", " + shortestText(q.y),
             "trim points must lie in the knot domain [" + shortestText(u0) + ", " + shortestText(u1) + "] x [" + shortestText(v0) + ", " +
                 shortestText(v1) + "] (within the tolerance)");
    }
  }
}

void validateSurfaceShape(const SurfaceModel& m, const SurfaceCounts& counts) {
  const FamilySpec& f = m.family;
  const Construction c = f.construction;
  validateFamily(f, m.orderV, true);
  const int orderU = f.order;
  const int orderV = c == Construction::BSpline ? m.orderV : f.order;

  if (m.rows < 0 || m.cols < 0 || counts.points != static_cast<size_t>(m.rows) * static_cast<size_t>(m.cols))
    fail("points", std::to_string(counts.points) + " points",
         "rows x cols = " + std::to_string(m.rows) + " x " + std::to_string(m.cols) + " must match the point count");
  if (m.rows < minPoints(c, orderU, m.closedU))
    fail("points", std::to_string(m.rows) + " rows", minRule(c, orderU, m.closedU, "surface", "rows (u direction)"));
  if (m.cols < minPoints(c, orderV, m.closedV))
    fail("points[0]", std::to_string(m.cols) + " columns",
         minRule(c, orderV, m.closedV, "surface", "columns (v direction)"));

  if (c == Construction::AlphaEB) {
    if (counts.alpha == 0) fail("alpha", "missing", "alpha is required for alpha_eb");
    if (counts.alpha != counts.points)
      fail("alpha", std::to_string(counts.alpha) + " values",
           "alpha must have one value per point (" + std::to_string(m.rows) + " x " + std::to_string(m.cols) + ")");
  } else if (counts.alpha != 0) {
    fail("alpha", std::to_string(counts.alpha) + " values", "alpha is only allowed for alpha_eb, not " + cname(c));
  }

  const bool hasKnots = !m.knotsU.empty() || !m.knotsV.empty();
  checkWeightsAllowed(counts.weights, counts.points, c, hasKnots,
                      std::to_string(m.rows) + " x " + std::to_string(m.cols));
  if (!m.trim.empty() && (c != Construction::BSpline || !hasKnots))
    fail("trim", std::to_string(m.trim.loops.size()) + " loops", "trim is only allowed on a bspline surface with knot vectors");
  if (!hasKnots) return;
  if (c != Construction::BSpline)
    fail("knots", "present", "surfaces take knots only for bspline (span knots are for curves only)");
  if (m.knotsU.empty() || m.knotsV.empty())
    fail("knots", m.knotsU.empty() ? "U missing" : "V missing", "a bspline surface takes both knot vectors [U, V]");
  if (m.closedU || m.closedV)
    fail("closed", std::string("[") + (m.closedU ? "true" : "false") + ", " + (m.closedV ? "true" : "false") + "]",
         "a bspline surface with knot vectors must be open in both directions");
  checkKnotVector(m.knotsU, static_cast<size_t>(m.rows), orderU, "knots[0]");
  checkKnotVector(m.knotsV, static_cast<size_t>(m.cols), orderV, "knots[1]");
  checkTrim(m, orderU, orderV);
}

void checkSurfaceCoordinates(const glm::dvec3* points, size_t count, size_t first, int cols) {
  const size_t coords = 3 * count;
  if (const size_t k = firstNonFinite(reinterpret_cast<const double*>(points), coords); k < coords) {
    const size_t point = first + k / 3, c = static_cast<size_t>(cols);
    fail(idx(idx(idx("points", point / c), point % c), k % 3), shortestText(points[k / 3][int(k % 3)]),
         "coordinates must be finite numbers");
  }
}

void checkSurfaceAlphas(const double* alpha, size_t count, size_t first, int cols) {
  if (alphaValuesInRange(alpha, count)) return;
  const size_t c = static_cast<size_t>(cols);
  for (size_t k = 0; k < count; ++k)
    checkAlphaValue(alpha[k], [&] { return idx(idx("alpha", (first + k) / c), (first + k) % c); });
}

void checkCurveAlphas(const double* alpha, size_t count, size_t first) {
  if (alphaValuesInRange(alpha, count)) return;
  for (size_t k = 0; k < count; ++k) checkAlphaValue(alpha[k], [&] { return idx("alpha", first + k); });
}

void checkSurfaceWeights(const double* weights, const glm::dvec3* points, size_t count, size_t first, int cols) {
  const size_t c = static_cast<size_t>(cols);
  for (size_t k = 0; k < count; ++k)
    checkWeight(weights[k], points[k], [&] { return idx(idx("weights", (first + k) / c), (first + k) % c); });
}

void validateSurface(const SurfaceModel& m) {
  // The shape first, then the values (which a streamed net checks a run at a time, in this order).
  validateSurfaceShape(m, {m.points.size(), m.alpha.size(), m.weights.size()});
  checkSurfaceCoordinates(m.points.data(), m.points.size(), 0, m.cols);
  if (!m.alpha.empty()) checkSurfaceAlphas(m.alpha.data(), m.alpha.size(), 0, m.cols);
  if (!m.weights.empty()) checkSurfaceWeights(m.weights.data(), m.points.data(), m.weights.size(), 0, m.cols);
}

}  // namespace shapespline
