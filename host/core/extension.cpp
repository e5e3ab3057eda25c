#include <shapespline/core/extension.h>
#include <shapespline/core/value_text.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <sstream>
#include <string>

namespace shapespline {
namespace {

std::string pointText(const glm::dvec3& p) { return "[" + preciseText(p.x) + ", " + preciseText(p.y) + ", " + preciseText(p.z) + "]"; }

// Shape of a knot-vector curve and right clamping (docs/math.md §10.1, §11). Returns b.
double checkRightClamped(int order, std::span<const double> knots, int count, const std::string& field) {
  if (order < 2 || order > kMaxBasisCount) throw ModelError("order", std::to_string(order), "order must be 2..10");
  if (count < order)
    throw ModelError("points", std::to_string(count) + " points", "an order-k B-spline needs at least k points");
  if (static_cast<int>(knots.size()) != count + order)
    throw ModelError(field, "length " + std::to_string(knots.size()), "knot vector length must be N + order");
  for (size_t i = 1; i < knots.size(); ++i)
    if (!(knots[i] >= knots[i - 1]))
      throw ModelError(field + "[" + std::to_string(i) + "]", preciseText(knots[i]), "knots must be non-decreasing");
  const int n = count - 1;
  const double b = knots[static_cast<size_t>(n + 1)];
  for (int i = n + 2; i <= n + order; ++i)
    if (knots[static_cast<size_t>(i)] != b)
      throw ModelError(field + "[" + std::to_string(i) + "]", preciseText(knots[static_cast<size_t>(i)]),
                       "the curve must be right-clamped: t_{n+1} = ... = t_{n+k} = " + preciseText(b));
  // Algorithm U divides by t_{i+r+1} − t_i and needs t_i < b for i <= n (docs/math.md §10.2).
  if (!(knots[static_cast<size_t>(n)] < b))
    throw ModelError(field + "[" + std::to_string(n) + "]", preciseText(knots[static_cast<size_t>(n)]),
                     "no interior knot may equal the end parameter b = " + preciseText(b) + " (knot multiplicity above the order)");
  if (!(knots[static_cast<size_t>(order - 1)] < b)) throw ModelError(field, "", "the domain must be non-empty");
  return b;
}

void checkFinite(const glm::dvec3& p, const std::string& field) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
    throw ModelError(field, pointText(p), "coordinates must be finite");
}

// Given parameters: m values, strictly increasing, u_1 > b (docs/math.md §10.3, §11).
void checkGivenU(const std::vector<double>& u, size_t m, double b) {
  if (u.size() != m)
    throw ModelError("parametrization.u", std::to_string(u.size()) + " values",
                     "one parameter per target (" + std::to_string(m) + ")");
  for (size_t s = 0; s < u.size(); ++s) {
    const std::string field = "parametrization.u[" + std::to_string(s) + "]";
    if (!std::isfinite(u[s])) throw ModelError(field, preciseText(u[s]), "parameters must be finite");
    const double prev = s == 0 ? b : u[s - 1];
    if (!(u[s] > prev))
      throw ModelError(field, preciseText(u[s]),
                       s == 0 ? "u_1 must be greater than the end parameter b = " + preciseText(b)
                              : "parameters must be strictly increasing");
  }
}

// docs/math.md §10.5 with the parameters already known and checked: K_final, Algorithm U on K_unc,
// Algorithm X for R_1..R_{m−1}, Q_{n+m} = R_m.
ExtensionResult extendWithParameters(const BSplineCurveData& curve, std::span<const glm::dvec3> targets,
                                     std::vector<double> u) {
  const int k = curve.order;
  const int n = static_cast<int>(curve.points.size()) - 1;
  const int m = static_cast<int>(targets.size());
  ExtensionResult out;
  std::vector<double> knots(curve.knots.begin(), curve.knots.begin() + n + 2);  // t_0..t_{n+1}
  for (int s = 0; s < m - 1; ++s) knots.push_back(u[static_cast<size_t>(s)]);
  for (int r = 0; r < k; ++r) knots.push_back(u.back());
  out.unclampKnots.assign(knots.begin(), knots.begin() + n + k + 1);
  const BSplineCurveData unclamped =
      unclampRight(curve, std::span<const double>(out.unclampKnots).subspan(static_cast<size_t>(n + 2)));
  out.unclampedPoints = unclamped.points;

  std::vector<glm::dvec3> q = unclamped.points;
  for (int s = 1; s < m; ++s)
    q.push_back(inverseDeBoor(k, knots, q, n + s, targets[static_cast<size_t>(s - 1)]));
  q.push_back(targets.back());

  const double a = knots[static_cast<size_t>(k - 1)];
  const double span = u.back() - a;
  out.knotsNormalized.reserve(knots.size());
  for (double t : knots) out.knotsNormalized.push_back((t - a) / span);
  out.curve = BSplineCurveData{k, std::move(knots), std::move(q), {}};
  out.u = std::move(u);
  return out;
}

// A rational curve (docs/math.md §10.8) is extended in homogeneous space. Unclamping and inverse de
// Boor are linear in the control points, so the homogeneous points w P and the weights (carried as
// points (w, 0, 0)) are extended apart with the same parameters, and each target R_s is the
// homogeneous point (w_R R_s, w_R). Throws ModelError naming the control point when a new weight
// is not positive (the rational curve would not exist there).
ExtensionResult extendRational(const BSplineCurveData& curve, std::span<const glm::dvec3> targets,
                               std::vector<double> u, double targetWeight) {
  BSplineCurveData homogeneous{curve.order, curve.knots, {}, {}}, weights{curve.order, curve.knots, {}, {}};
  for (size_t i = 0; i < curve.points.size(); ++i) {
    homogeneous.points.push_back(curve.weights[i] * curve.points[i]);
    weights.points.push_back({curve.weights[i], 0.0, 0.0});
  }
  std::vector<glm::dvec3> hTargets, wTargets;
  for (const glm::dvec3& r : targets) hTargets.push_back(targetWeight * r), wTargets.push_back({targetWeight, 0.0, 0.0});
  ExtensionResult out = extendWithParameters(homogeneous, hTargets, u);
  const ExtensionResult w = extendWithParameters(weights, wTargets, std::move(u));
  out.curve.weights.resize(out.curve.points.size());
  for (size_t i = 0; i < out.curve.points.size(); ++i) {
    const double wi = w.curve.points[i].x;
    if (!(wi > 0.0) || !std::isfinite(wi))
      throw ModelError("weights[" + std::to_string(i) + "]", preciseText(wi),
                       "the rational extension gives this control point a weight that is not positive; choose other "
                       "target parameters (--u)");
    out.curve.points[i] /= wi;
    out.curve.weights[i] = wi;
  }
  for (size_t i = 0; i < out.unclampedPoints.size(); ++i) out.unclampedPoints[i] /= w.unclampedPoints[i].x;
  return out;
}

}  // namespace

BSplineCurveData unclampRight(const BSplineCurveData& curve, std::span<const double> newRightKnots) {
  const int k = curve.order;
  const int count = static_cast<int>(curve.points.size());
  const double b = checkRightClamped(k, curve.knots, count, "knots");
  if (static_cast<int>(newRightKnots.size()) != k - 1)
    throw ModelError("new_right_knots", std::to_string(newRightKnots.size()) + " values",
                     "unclamping needs k - 1 = " + std::to_string(k - 1) + " new knots t_{n+2}..t_{n+k}");
  for (size_t l = 0; l < newRightKnots.size(); ++l) {
    const std::string field = "new_right_knots[" + std::to_string(l) + "]";
    if (!std::isfinite(newRightKnots[l]) || !(newRightKnots[l] > b))
      throw ModelError(field, preciseText(newRightKnots[l]), "new knots must be finite and greater than b = " + preciseText(b));
    if (l > 0 && !(newRightKnots[l] >= newRightKnots[l - 1]))
      throw ModelError(field, preciseText(newRightKnots[l]), "new knots must be non-decreasing");
  }
  const int n = count - 1;
  BSplineCurveData out = curve;
  std::vector<double>& t = out.knots;
  for (int l = 1; l <= k - 1; ++l) t[static_cast<size_t>(n + 1 + l)] = newRightKnots[static_cast<size_t>(l - 1)];
  std::vector<glm::dvec3>& q = out.points;
  // In place with increasing i, so Q_{i−1} is the value already updated at this level (C32, R12).
  for (int r = 1; r <= k - 2; ++r) {
    for (int i = n - r + 1; i <= n; ++i) {
      const double ti = t[static_cast<size_t>(i)];
      const double alpha = (b - ti) / (t[static_cast<size_t>(i + r + 1)] - ti);
      q[static_cast<size_t>(i)] = (q[static_cast<size_t>(i)] - (1.0 - alpha) * q[static_cast<size_t>(i - 1)]) / alpha;
    }
  }
  return out;
}

std::vector<double> chordParameters(const BSplineCurveData& curve, std::span<const glm::dvec3> targets) {
  const int k = curve.order;
  const int n = static_cast<int>(curve.points.size()) - 1;
  const double a = curve.knots[static_cast<size_t>(k - 1)];
  const double b = curve.knots[static_cast<size_t>(n + 1)];
  double length = 0.0;
  glm::dvec3 prev = evalBSplineCurve(curve, a).point;
  for (int i = k - 1; i <= n; ++i) {
    const double t1 = curve.knots[static_cast<size_t>(i + 1)];
    if (!(t1 > curve.knots[static_cast<size_t>(i)])) continue;  // empty span: zero chord
    const glm::dvec3 next = evalBSplineCurve(curve, t1).point;
    length += glm::length(next - prev);
    prev = next;
  }
  if (!(length > 0.0))
    throw ModelError("points", "", "chord-length parameters need a curve of non-zero chord length");
  std::vector<double> u;
  glm::dvec3 last = curve.points.back();
  double value = b;
  for (const glm::dvec3& r : targets) {
    value += (b - a) * glm::length(r - last) / length;
    u.push_back(value);
    last = r;
  }
  return u;
}

glm::dvec3 inverseDeBoor(int order, std::span<const double> t, std::span<const glm::dvec3> known, int j,
                         const glm::dvec3& target) {
  const int k = order;
  const double tau = t[static_cast<size_t>(j + 1)];
  const int base = j - k + 1;
  // level[r][i − base] = Q_i^r in the paper's indexing (docs/math.md §10.4).
  glm::dvec3 level[kMaxBasisCount][kMaxBasisCount];
  for (int i = base; i <= j - 1; ++i) level[0][i - base] = known[static_cast<size_t>(i)];
  for (int r = 1; r <= k - 2; ++r)
    for (int i = base; i <= j - r - 1; ++i) {
      const double tk = t[static_cast<size_t>(i + k)], tr = t[static_cast<size_t>(i + r)];
      level[r][i - base] = ((tk - tau) * level[r - 1][i - base] + (tau - tr) * level[r - 1][i + 1 - base]) / (tk - tr);
    }
  level[k - 1][0] = target;
  // Each backward step solves one de Boor step for its unknown right input; the divisor is
  // τ − t_{i+r} = τ − t_j > 0 at every level, which is where the (span ratio)^(k−1) growth of
  // docs/math.md §14 comes from.
  for (int r = k - 2; r >= 0; --r) {
    const int i = j - r;
    const double tk1 = t[static_cast<size_t>(i + k - 1)], tr = t[static_cast<size_t>(i + r)];
    level[r][i - base] = ((tk1 - tr) * level[r + 1][i - 1 - base] - (tk1 - tau) * level[r][i - 1 - base]) / (tau - tr);
  }
  return level[0][k - 1];
}

ExtensionResult extendCurve(const BSplineCurveData& curve, std::span<const glm::dvec3> targets,
                            std::optional<std::vector<double>> givenU) {
  const int count = static_cast<int>(curve.points.size());
  const double b = checkRightClamped(curve.order, curve.knots, count, "knots");
  if (targets.empty()) throw ModelError("targets", "[]", "at least one target point is required");
  const glm::dvec3& end = curve.points.back();
  for (size_t s = 0; s < targets.size(); ++s) {
    const std::string field = "targets[" + std::to_string(s) + "]";
    checkFinite(targets[s], field);
    if (targets[s] == end)
      throw ModelError(field, pointText(targets[s]), "targets must be distinct from the curve's end point P_n");
    for (size_t r = 0; r < s; ++r)
      if (targets[s] == targets[r])
        throw ModelError(field, pointText(targets[s]),
                         "targets must be distinct from each other (equal to targets[" + std::to_string(r) + "])");
  }
  std::vector<double> u;
  if (givenU) {
    checkGivenU(*givenU, targets.size(), b);
    u = std::move(*givenU);
  } else {
    u = chordParameters(curve, targets);
  }
  // A rational curve's targets take the weight of P_n, the end point C(b) interpolates: with every
  // weight 1 this is the non-rational extension.
  if (!curve.weights.empty()) return extendRational(curve, targets, std::move(u), curve.weights.back());
  return extendWithParameters(curve, targets, std::move(u));
}

SurfaceExtensionResult extendSurfaceU(const BSplineSurfaceData& surface,
                                      std::span<const std::vector<glm::dvec3>> targetCurves,
                                      std::optional<std::vector<double>> givenU) {
  const int rows = surface.rows, cols = surface.cols;
  if (static_cast<int>(surface.points.size()) != rows * cols)
    throw ModelError("points", std::to_string(surface.points.size()), "the net must have rows * cols points");
  if (surface.orderV < 2 || surface.orderV > kMaxBasisCount || static_cast<int>(surface.knotsV.size()) != cols + surface.orderV)
    throw ModelError("knots[1]", "length " + std::to_string(surface.knotsV.size()), "V knot vector length must be cols + order_v");
  const double b = checkRightClamped(surface.orderU, surface.knotsU, rows, "knots[0]");
  if (targetCurves.empty()) throw ModelError("target_curves", "[]", "at least one target curve is required");
  const size_t m = targetCurves.size();
  for (size_t s = 0; s < m; ++s) {
    if (static_cast<int>(targetCurves[s].size()) != cols)
      throw ModelError("target_curves[" + std::to_string(s) + "]", std::to_string(targetCurves[s].size()) + " points",
                       "a target curve needs one control point per column (" + std::to_string(cols) +
                           "), on the surface's V knots and order");
    for (int j = 0; j < cols; ++j)
      checkFinite(targetCurves[s][static_cast<size_t>(j)],
                  "target_curves[" + std::to_string(s) + "][" + std::to_string(j) + "]");
  }

  const bool rational = !surface.weights.empty();
  auto column = [&](int j) {
    BSplineCurveData c{surface.orderU, surface.knotsU, {}, {}};
    c.points.reserve(static_cast<size_t>(rows));
    for (int i = 0; i < rows; ++i) {
      c.points.push_back(surface.points[static_cast<size_t>(i) * cols + j]);
      if (rational) c.weights.push_back(surface.weights[static_cast<size_t>(i) * cols + j]);
    }
    return c;
  };
  auto columnTargets = [&](int j) {
    std::vector<glm::dvec3> r;
    for (size_t s = 0; s < m; ++s) r.push_back(targetCurves[s][static_cast<size_t>(j)]);
    return r;
  };

  SurfaceExtensionResult out;
  if (givenU) {
    checkGivenU(*givenU, m, b);
    out.u = std::move(*givenU);
  } else {
    out.u.assign(m, 0.0);
    for (int j = 0; j < cols; ++j) {
      const auto targets = columnTargets(j);
      std::vector<double> uj = chordParameters(column(j), targets);
      for (size_t s = 0; s < m; ++s) out.u[s] += uj[s];
      out.uPerColumn.push_back(std::move(uj));
    }
    for (double& v : out.u) v /= cols;
    // Averaging keeps them increasing unless every column has a repeated target at the same s.
    checkGivenU(out.u, m, b);
  }

  BSplineSurfaceData& ext = out.surface;
  ext.orderU = surface.orderU;
  ext.orderV = surface.orderV;
  ext.knotsV = surface.knotsV;
  ext.rows = rows + static_cast<int>(m);
  ext.cols = cols;
  ext.points.assign(static_cast<size_t>(ext.rows) * cols, glm::dvec3(0.0));
  if (rational) ext.weights.assign(ext.points.size(), 0.0);
  for (int j = 0; j < cols; ++j) {
    // Columns share K_final; a column whose target equals its end point (a collapsed edge) is
    // still well defined with common parameters, so no per-column distinctness check here. A
    // rational column's targets take the weight of its last control point, so the surface at u_s
    // is the rational curve of target curve s with the weights of the net's last row.
    const auto targets = columnTargets(j);
    const BSplineCurveData c = column(j);
    ExtensionResult e = rational ? extendRational(c, targets, out.u, c.weights.back())
                                 : extendWithParameters(c, targets, out.u);
    for (int i = 0; i < ext.rows; ++i) {
      ext.points[static_cast<size_t>(i) * cols + j] = e.curve.points[static_cast<size_t>(i)];
      if (rational) ext.weights[static_cast<size_t>(i) * cols + j] = e.curve.weights[static_cast<size_t>(i)];
    }
    if (j == 0) {
      ext.knotsU = e.curve.knots;
      out.knotsNormalizedU = e.knotsNormalized;
    }
  }
  return out;
}

CurveModel extendedModel(CurveModel model, const ExtensionResult& result) {
  model.points = result.curve.points;
  model.knots = result.curve.knots;
  model.weights = result.curve.weights;
  return model;
}

SurfaceModel extendedModel(SurfaceModel model, const SurfaceExtensionResult& result) {
  model.rows = result.surface.rows;
  model.cols = result.surface.cols;
  model.points = result.surface.points;
  model.knotsU = result.surface.knotsU;
  model.knotsV = result.surface.knotsV;
  model.weights = result.surface.weights;
  return model;
}

}  // namespace shapespline
