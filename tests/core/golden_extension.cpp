// Golden checkers for the B-spline extension families of paper [EXT] (docs/math.md §10):
// bspline_unclamp, bspline_extend_curve, bspline_extend_surface.
//
// Tolerances. Control points and curve values: kFp64Rel × (bounding-box diagonal of the input net,
// the targets and the computed net) × growth, where growth = ρ^(k−1) is the docs/math.md §14 bound for
// the divisions of Algorithms U and X: ρ = max(1, largest knot distance over divisor) taken over
// every division they make, (t_{i+r+1} − t_i)/(b − t_i) in U and (t_{j+k−1} − t_j)/(u_s − t_j) in
// X. First derivatives multiply by (k−1)/h_min (h_min the shortest non-empty knot span): a
// control-point error δ changes C' by at most 2δ(k−1)/h_min, and the point tolerance already
// carries a factor > 2 of slack. Knots and parameters: kFp64Rel × the largest knot magnitude.
#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <shapespline/core/extension.h>
#include "core/golden_registry.h"
#include <shapespline/io/model_json.h>
#include "support/tolerances.h"

namespace shapespline::test {
namespace {


double boxDiagonal(std::initializer_list<std::span<const glm::dvec3>> sets) {
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& set : sets)
    for (const auto& p : set) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double d = std::sqrt(glm::dot(hi - lo, hi - lo));
  return std::isfinite(d) && d > 0.0 ? d : 1.0;
}

double knotScale(const std::vector<double>& knots) {
  double s = 1.0;
  for (double t : knots) s = std::max(s, std::abs(t));
  return s;
}

double shortestSpan(const std::vector<double>& knots) {
  double h = INFINITY;
  for (size_t i = 0; i + 1 < knots.size(); ++i)
    if (knots[i + 1] > knots[i]) h = std::min(h, knots[i + 1] - knots[i]);
  return h;
}

// ρ^(k−1) of docs/math.md §14 over the divisions of Algorithm U (n + 1 points, end b) and of Algorithm X
// for the points n+1 .. last−1 (the last point is the last target itself), on the final knots.
double inverseGrowth(int order, const std::vector<double>& knots, int n, int lastPoint) {
  const double b = knots[static_cast<size_t>(n + 1)];
  double rho = 1.0;
  for (int r = 1; r <= order - 2; ++r)
    for (int i = n - r + 1; i <= n; ++i)
      rho = std::max(rho, (knots[static_cast<size_t>(i + r + 1)] - knots[static_cast<size_t>(i)]) /
                              (b - knots[static_cast<size_t>(i)]));
  for (int j = n + 1; j < lastPoint; ++j)
    rho = std::max(rho, (knots[static_cast<size_t>(j + order - 1)] - knots[static_cast<size_t>(j)]) /
                            (knots[static_cast<size_t>(j + 1)] - knots[static_cast<size_t>(j)]));
  return std::pow(rho, order - 1);
}

std::vector<glm::dvec3> pointList(const json& j) {
  std::vector<glm::dvec3> out;
  for (const auto& p : j) out.push_back(vec(p));
  return out;
}

std::vector<double> numberList(const json& j) {
  std::vector<double> out;
  for (const auto& v : j) out.push_back(number(v));
  return out;
}

void compareNumbers(CaseReport& r, const std::string& name, const json& expected, const std::vector<double>& actual,
                    double tol) {
  if (expected.size() != actual.size()) {
    r.fail(name + ": expected " + std::to_string(expected.size()) + " values, got " + std::to_string(actual.size()));
    return;
  }
  for (size_t i = 0; i < actual.size(); ++i) r.compare(fieldAt(name, i), expected[i], actual[i], tol);
}

void comparePoints(CaseReport& r, const std::string& name, const json& expected,
                   std::span<const glm::dvec3> actual, double tol) {
  if (expected.size() != actual.size()) {
    r.fail(name + ": expected " + std::to_string(expected.size()) + " points, got " + std::to_string(actual.size()));
    return;
  }
  for (size_t i = 0; i < actual.size(); ++i)
    r.compare(fieldAt(name, i), expected[i], actual[i], static_cast<int>(expected[i].size()), tol);
}

std::optional<std::vector<double>> givenParameters(const json& inputs) {
  const json& p = inputs.at("parametrization");
  if (p.is_string()) {
    if (p.get<std::string>() != "chord") throw std::runtime_error("unknown parametrization " + p.dump());
    return std::nullopt;
  }
  return numberList(p.at("u"));
}

// Samples {t, point, d1} (unclamp) or {t, t_normalized, point, d1} (extension) on `curve`.
void compareCurveSamples(CaseReport& r, const json& samples, const BSplineCurveData& curve, double pointTol,
                         double d1Tol, double a, double end) {
  for (size_t i = 0; i < samples.size(); ++i) {
    const json& s = samples[i];
    const double t = number(s.at("t"));
    const BSplineCurvePoint c = evalBSplineCurve(curve, t);
    const std::string name = fieldAt("samples", i);
    r.compare(name + ".point", s.at("point"), c.point, static_cast<int>(s.at("point").size()), pointTol);
    r.compare(name + ".d1", s.at("d1"), c.d1, static_cast<int>(s.at("d1").size()), d1Tol);
    if (s.contains("t_normalized"))
      r.compare(name + ".t_normalized", s.at("t_normalized"), (t - a) / (end - a), kFp64Rel);
  }
}

const GoldenRegistration kUnclamp("bspline_unclamp", [](CaseReport& r) {
  const BSplineCurveData curve = bsplineCurveFromModel(std::get<CurveModel>(io::parseModel(r.model())));
  const std::vector<double> newKnots = numberList(r.inputs().at("new_right_knots"));
  const BSplineCurveData un = unclampRight(curve, newKnots);
  const int n = static_cast<int>(curve.points.size()) - 1;
  const double growth = inverseGrowth(curve.order, un.knots, n, n + 1);
  const double pointTol = kFp64Rel * boxDiagonal({curve.points, un.points}) * growth;
  const double d1Tol = pointTol * (curve.order - 1) / shortestSpan(un.knots);
  comparePoints(r, "points", r.expected("points"), un.points, pointTol);
  compareNumbers(r, "knots", r.expected("knots"), un.knots, kFp64Rel * knotScale(un.knots));
  compareCurveSamples(r, r.expected("samples"), un, pointTol, d1Tol, 0.0, 1.0);
});

const GoldenRegistration kExtendCurve("bspline_extend_curve", [](CaseReport& r) {
  const BSplineCurveData curve = bsplineCurveFromModel(std::get<CurveModel>(io::parseModel(r.model())));
  const std::vector<glm::dvec3> targets = pointList(r.inputs().at("targets"));
  const ExtensionResult e = extendCurve(curve, targets, givenParameters(r.inputs()));
  const int n = static_cast<int>(curve.points.size()) - 1;
  const int k = curve.order;
  const double growth = inverseGrowth(k, e.curve.knots, n, n + static_cast<int>(targets.size()));
  const double pointTol = kFp64Rel * boxDiagonal({curve.points, targets, e.curve.points}) * growth;
  const double d1Tol = pointTol * (k - 1) / shortestSpan(e.curve.knots);
  const double knotTol = kFp64Rel * knotScale(e.curve.knots);

  compareNumbers(r, "u", r.expected("u"), e.u, knotTol);
  compareNumbers(r, "unclamp_knots", r.expected("unclamp_knots"), e.unclampKnots, knotTol);
  comparePoints(r, "unclamped_points", r.expected("unclamped_points"), e.unclampedPoints, pointTol);
  comparePoints(r, "points", r.expected("points"), e.curve.points, pointTol);
  compareNumbers(r, "knots", r.expected("knots"), e.curve.knots, knotTol);
  compareNumbers(r, "knots_normalized", r.expected("knots_normalized"), e.knotsNormalized, kFp64Rel);
  const double a = e.curve.knots[static_cast<size_t>(k - 1)];
  compareCurveSamples(r, r.expected("samples"), e.curve, pointTol, d1Tol, a, e.u.back());
});

const GoldenRegistration kExtendSurface("bspline_extend_surface", [](CaseReport& r) {
  const BSplineSurfaceData surface = bsplineSurfaceFromModel(std::get<SurfaceModel>(io::parseModel(r.model())));
  if (r.inputs().value("direction", std::string("u")) != "u")
    throw std::runtime_error("only direction u is defined (docs/math.md §10.6)");
  std::vector<std::vector<glm::dvec3>> targetCurves;
  std::vector<glm::dvec3> allTargets;
  for (const auto& c : r.inputs().at("target_curves")) {
    targetCurves.push_back(pointList(c));
    allTargets.insert(allTargets.end(), targetCurves.back().begin(), targetCurves.back().end());
  }
  const SurfaceExtensionResult e = extendSurfaceU(surface, targetCurves, givenParameters(r.inputs()));
  const BSplineSurfaceData& s = e.surface;
  const int k = s.orderU, l = s.orderV;
  const int n = surface.rows - 1;
  const double growth = inverseGrowth(k, s.knotsU, n, n + static_cast<int>(targetCurves.size()));
  const double pointTol = kFp64Rel * boxDiagonal({surface.points, allTargets, s.points}) * growth;
  const double dtTol = pointTol * (k - 1) / shortestSpan(s.knotsU);
  const double dsTol = pointTol * (l - 1) / shortestSpan(s.knotsV);
  const double knotTol = kFp64Rel * std::max(knotScale(s.knotsU), knotScale(s.knotsV));

  compareNumbers(r, "u", r.expected("u"), e.u, knotTol);
  if (r.testCase().at("expected").contains("u_per_column")) {
    const json& per = r.expected("u_per_column");
    // Accept either [column][s] or [s][column]; both name the same numbers.
    const size_t m = e.u.size(), cols = static_cast<size_t>(s.cols);
    if (e.uPerColumn.empty()) {
      r.fail("u_per_column expected but the parametrization gave none");
    } else if (per.size() == cols && per[0].is_array() && per[0].size() == m) {
      for (size_t j = 0; j < cols; ++j) compareNumbers(r, fieldAt("u_per_column", j), per[j], e.uPerColumn[j], knotTol);
    } else if (per.size() == m && per[0].is_array() && per[0].size() == cols) {
      for (size_t q = 0; q < m; ++q)
        for (size_t j = 0; j < cols; ++j)
          r.compare(fieldAt(fieldAt("u_per_column", q), j), per[q][j], e.uPerColumn[j][q], knotTol);
    } else if (m == 1 && per.size() == cols && !per[0].is_array()) {
      for (size_t j = 0; j < cols; ++j) r.compare(fieldAt("u_per_column", j), per[j], e.uPerColumn[j][0], knotTol);
    } else {
      r.fail("u_per_column: unexpected shape " + per.dump());
    }
  }

  const json& points = r.expected("points");
  if (static_cast<int>(points.size()) != s.rows) {
    r.fail("points: expected " + std::to_string(points.size()) + " rows, got " + std::to_string(s.rows));
  } else {
    for (int i = 0; i < s.rows; ++i)
      comparePoints(r, fieldAt("points", static_cast<size_t>(i)), points[static_cast<size_t>(i)],
                    std::span<const glm::dvec3>(s.points).subspan(static_cast<size_t>(i) * s.cols, s.cols), pointTol);
  }
  const json& knots = r.expected("knots");
  compareNumbers(r, "knots[0]", knots.at(0), s.knotsU, knotTol);
  compareNumbers(r, "knots[1]", knots.at(1), s.knotsV, knotTol);
  compareNumbers(r, "knots_normalized_u", r.expected("knots_normalized_u"), e.knotsNormalizedU, kFp64Rel);

  const json& samples = r.expected("samples");
  for (size_t i = 0; i < samples.size(); ++i) {
    const json& q = samples[i];
    const BSplineSurfacePoint p = evalBSplineSurface(s, number(q.at("t")), number(q.at("s")));
    const std::string name = fieldAt("samples", i);
    r.compare(name + ".point", q.at("point"), p.point, 3, pointTol);
    r.compare(name + ".dt", q.at("dt"), p.du, 3, dtTol);
    r.compare(name + ".ds", q.at("ds"), p.dv, 3, dsTol);
  }
});

}  // namespace
}  // namespace shapespline::test
