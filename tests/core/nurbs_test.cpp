// Rational B-splines (docs/math.md §10.8): conics and a torus reproduced exactly by weights, on
// every CPU path (per point, the tabulated grid, chunked and threaded), and the rational quotient
// rule against finite differences. Exact rational references for the derivatives are in
// python/tests/test_nurbs.py (fractions).
#include <gtest/gtest.h>

#include <shapespline/core/curve.h>
#include <shapespline/core/extension.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/core/validate.h>

#include <glm/geometric.hpp>

#include "support/test_models.h"

#include <cmath>
#include <vector>

namespace shapespline {
namespace {

using glm::dvec3;

using test::nurbsCircle;
using test::nurbsTorus;

const std::vector<dvec3> kCirclePoints = {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}, {-1, 0, 0},
                                          {-1, -1, 0}, {0, -1, 0}, {1, -1, 0}, {1, 0, 0}};
const std::vector<double> kCircleKnots = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};

constexpr double kUlp = 2.220446049250313e-16;

TEST(Nurbs, CircleEveryPointAtTheRadius) {
  for (double radius : {1.0, 3.5e-3, 7e5}) {
    const Curve c = Curve::create(nurbsCircle(radius));
    double worst = 0.0;
    for (int k = 0; k <= 1000; ++k) {
      const CurvePoint p = c.evaluateAt(k / 1000.0);
      worst = std::max(worst, std::abs(glm::length(p.point) - radius) / radius);
      // The tangent is perpendicular to the radius everywhere.
      EXPECT_LE(std::abs(glm::dot(p.point, p.d1)), 64 * kUlp * radius * glm::length(p.d1)) << k;
    }
    // The grid path (tabulated bases) as well, in chunks of one point on two threads.
    double gridWorst = 0.0;
    sampleCurveGrid(c, {33, 1, 0, 0}, fieldBit(Field::Point) | fieldBit(Field::D1) | fieldBit(Field::D2),
                    [&](const GridChunk& ch) {
                      for (size_t i = 0; i < ch.pointCount(); ++i) {
                        const dvec3 p(ch.coord(Field::Point, i, 0), ch.coord(Field::Point, i, 1), ch.coord(Field::Point, i, 2));
                        gridWorst = std::max(gridWorst, std::abs(glm::length(p) - radius) / radius);
                      }
                    },
                    {2, 1});
    EXPECT_LE(worst, 4 * kUlp) << radius;
    EXPECT_LE(gridWorst, 4 * kUlp) << radius;
    std::printf("circle r = %g: max | |P| - r | / r = %.2e (per point), %.2e (grid)\n", radius, worst, gridWorst);
  }
}

TEST(Nurbs, TorusEveryPointOnTheTorus) {
  const double R = 3.0, r = 1.25;
  const Surface s = Surface::create(nurbsTorus(R, r));
  const Field order[7] = {Field::Point, Field::Du, Field::Dv, Field::Duu, Field::Duv, Field::Dvv, Field::Normal};
  FieldMask all = 0;
  for (Field f : order) all |= fieldBit(f);
  // Every field, the point alone and a second partial without the other first one: the rational
  // rows compute the partials each request needs, and only those.
  for (FieldMask fields : {all, fieldBit(Field::Point), fieldBit(Field::Point) | fieldBit(Field::Duu)}) {
    double worst = 0.0, maxDiff = 0.0;
    const auto items = surfaceGridItems(s);
    size_t seen = 0;
    const int S = 9;
    sampleSurfaceGrid(s, {S, S, 0, 0}, fields, [&](const GridChunk& ch) {
      for (size_t i = 0; i < ch.pointCount(); ++i, ++seen) {
        auto at = [&](Field f) { return dvec3(ch.coord(f, i, 0), ch.coord(f, i, 1), ch.coord(f, i, 2)); };
        const dvec3 p = at(Field::Point);
        const double ring = std::hypot(p.x, p.y) - R;
        worst = std::max(worst, std::abs(std::hypot(ring, p.z) - r) / r);
        // The grid equals the per-point evaluation (another summation order: a few ulps).
        const size_t item = seen / (S * S), k = seen % (S * S);
        const auto [pi, pj] = items[item];
        const SurfacePoint ref = s.evaluate(pi, pj, double(k / S) / (S - 1), double(k % S) / (S - 1));
        const dvec3 want[7] = {ref.point, ref.du, ref.dv, ref.duu, ref.duv, ref.dvv, ref.normal};
        for (int f = 0; f < 7; ++f)
          if (fields & fieldBit(order[f]))
            maxDiff = std::max(maxDiff, glm::length(at(order[f]) - want[f]) / (R + r + glm::length(want[f])));
      }
    }, {2, 50});
    EXPECT_EQ(seen, items.size() * S * S);
    EXPECT_LE(worst, 8 * kUlp);
    EXPECT_LE(maxDiff, 64 * kUlp) << "fields " << fields;
    std::printf("torus (fields %#x): max |dist - r| / r = %.2e, grid vs per point %.2e\n", unsigned(fields), worst,
                maxDiff);
  }
}

// The quotient rule against central differences of the point (and of the first derivative).
TEST(Nurbs, DerivativesMatchFiniteDifferences) {
  SurfaceModel m = nurbsTorus(3.0, 1.25);
  m.weights[40] = 2.5;  // not a torus any more: a general rational surface
  // Parameters away from the knots at the quarters, where the quadratic is only C0.
  const Surface s = Surface::create(m);
  const double h = 1e-6;
  for (auto [u, v] : {std::pair{0.13, 0.61}, std::pair{0.4, 0.27}, std::pair{0.88, 0.55}}) {
    const SurfacePoint p = s.evaluateAt(u, v);
    const SurfacePoint pu0 = s.evaluateAt(u - h, v), pu1 = s.evaluateAt(u + h, v);
    const SurfacePoint pv0 = s.evaluateAt(u, v - h), pv1 = s.evaluateAt(u, v + h);
    const double tol1 = 1e-6 * glm::length(p.du), tol2 = 1e-5 * (glm::length(p.duu) + glm::length(p.dvv) + 1.0);
    EXPECT_LE(glm::length((pu1.point - pu0.point) / (2 * h) - p.du), tol1);
    EXPECT_LE(glm::length((pv1.point - pv0.point) / (2 * h) - p.dv), tol1);
    EXPECT_LE(glm::length((pu1.du - pu0.du) / (2 * h) - p.duu), tol2);
    EXPECT_LE(glm::length((pv1.du - pv0.du) / (2 * h) - p.duv), tol2);
    EXPECT_LE(glm::length((pv1.dv - pv0.dv) / (2 * h) - p.dvv), tol2);
  }
}

TEST(Nurbs, AllOnesWeightsAreTheNonRationalSpline) {
  SurfaceModel m = nurbsTorus(3.0, 1.25);
  const SurfaceModel plain = [&] { SurfaceModel p = m; p.weights.clear(); return p; }();
  m.weights.assign(m.weights.size(), 1.0);
  const Surface a = Surface::create(m), b = Surface::create(plain);
  const SurfacePoint pa = a.evaluateAt(0.3, 0.7), pb = b.evaluateAt(0.3, 0.7);
  EXPECT_LE(glm::length(pa.point - pb.point), 8 * kUlp * 5);
  EXPECT_LE(glm::length(pa.duv - pb.duv), 1e-12 * glm::length(pb.duv));
}

TEST(Nurbs, BadWeightsAreRefusedNamingTheEntry) {
  struct Case {
    double w;
    const char* rule;
  };
  for (const Case& c : {Case{0.0, "positive finite"}, Case{-1.0, "positive finite"}, Case{1e308, "overflows fp64"}}) {
    SurfaceModel m = nurbsTorus(3.0, 1.25);
    m.weights[2 * 9 + 0] = c.w;  // point (0, 4.25, 0): 1e308 w P overflows
    try {
      validateSurface(m);
      ADD_FAILURE() << "weight " << c.w << " accepted";
    } catch (const ModelError& e) {
      EXPECT_EQ(e.field(), "weights[2][0]");
      EXPECT_NE(e.rule().find(c.rule), std::string::npos) << e.rule();
    }
  }
  CurveModel curve = nurbsCircle(1.0);
  curve.weights.pop_back();
  EXPECT_THROW(validateCurve(curve), ModelError);
  curve = nurbsCircle(1.0);
  curve.knots.clear();  // a uniform B-spline without a knot vector takes no weights
  EXPECT_THROW(validateCurve(curve), ModelError);
}

}  // namespace
}  // namespace shapespline

namespace shapespline {
namespace {

// Rational extension (docs/math.md §10.8): in homogeneous space, the targets weighted like P_n.
TEST(NurbsExtension, CurveKeepsItsDomainAndReachesTheTargets) {
  CurveModel m = nurbsCircle(2.0);  // the whole circle: clamped at both ends
  const Curve before = Curve::create(m);
  const std::vector<dvec3> targets = {{3.0, -0.5, 0.0}, {3.5, 1.0, 0.0}};
  const ExtensionResult r = extendCurve(bsplineCurveFromModel(m), targets);
  const CurveModel extended = extendedModel(m, r);
  validateCurve(extended);
  ASSERT_EQ(extended.weights.size(), extended.points.size());
  for (double w : extended.weights) EXPECT_GT(w, 0.0);
  const Curve after = Curve::create(extended);
  double worst = 0.0;
  for (int k = 0; k <= 200; ++k) {
    const double u = k / 200.0;
    worst = std::max(worst, glm::length(after.evaluateAt(u).point - before.evaluateAt(u).point));
    EXPECT_LE(std::abs(glm::length(after.evaluateAt(u).point) - 2.0), 8 * kUlp * 2.0) << u;  // still the circle
  }
  EXPECT_LE(worst, 1e-14 * 2.0);
  for (size_t s = 0; s < targets.size(); ++s)
    EXPECT_LE(glm::length(after.evaluateAt(r.u[s]).point - targets[s]), 1e-13 * 4.0) << s;
  // All weights 1: exactly the non-rational extension.
  CurveModel plain = nurbsCircle(2.0);
  plain.weights.clear();
  CurveModel ones = plain;
  ones.weights.assign(ones.points.size(), 1.0);
  const ExtensionResult a = extendCurve(bsplineCurveFromModel(plain), targets);
  const ExtensionResult b = extendCurve(bsplineCurveFromModel(ones), targets);
  ASSERT_EQ(a.curve.points.size(), b.curve.points.size());
  for (size_t i = 0; i < a.curve.points.size(); ++i)
    EXPECT_LE(glm::length(a.curve.points[i] - b.curve.points[i]), 1e-14 * 4.0) << i;
}

TEST(NurbsExtension, SurfaceReachesTheRationalTargetCurve) {
  const SurfaceModel m = nurbsTorus(3.0, 1.25);
  const Surface before = Surface::create(m);
  std::vector<dvec3> target;
  for (int j = 0; j < 9; ++j) target.push_back(dvec3(4.0 + 0.5 * kCirclePoints[size_t(j)].x, -1.5, kCirclePoints[size_t(j)].y));
  const std::vector<std::vector<dvec3>> targets = {target};
  const SurfaceExtensionResult r = extendSurfaceU(bsplineSurfaceFromModel(m), targets);
  const SurfaceModel extended = extendedModel(m, r);
  validateSurface(extended);
  const Surface after = Surface::create(extended);
  double worst = 0.0;
  for (int a = 0; a <= 20; ++a)
    for (int b = 0; b <= 20; ++b)
      worst = std::max(worst, glm::length(after.evaluateAt(a / 20.0, b / 20.0).point -
                                          before.evaluateAt(a / 20.0, b / 20.0).point));
  EXPECT_LE(worst, 1e-13);
  // At u_1 the surface is the rational curve of the target's points with the last row's weights.
  CurveModel rowCurve;
  rowCurve.family = {Construction::BSpline, 0, 3, 0.0, {}};
  rowCurve.dimension = 3;
  rowCurve.points = target;
  rowCurve.knots = kCircleKnots;
  for (int j = 0; j < 9; ++j) rowCurve.weights.push_back(m.weights[size_t(8 * 9 + j)]);
  const Curve expected = Curve::create(rowCurve);
  for (int b = 0; b <= 20; ++b)
    EXPECT_LE(glm::length(after.evaluateAt(r.u[0], b / 20.0).point - expected.evaluateAt(b / 20.0).point), 1e-12) << b;
}

}  // namespace
}  // namespace shapespline
