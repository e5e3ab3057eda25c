// Rational B-splines (docs/math.md §10.8): conics and a torus reproduced exactly by weights, on
// every CPU path (per point, the tabulated grid, chunked and threaded), and the rational quotient
// rule against finite differences. Exact rational references for the derivatives are in
// python/tests/test_nurbs.py (fractions).
#include <gtest/gtest.h>

#include <shapespline/core/curve.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/core/validate.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

namespace shapespline {
namespace {

using glm::dvec3;

// The quadratic NURBS unit circle of 9 control points (The NURBS Book, Ex. 7.2): the corners of
// the square with weight √2/2, knots of multiplicity 2 at the quarters.
const std::vector<dvec3> kCirclePoints = {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}, {-1, 0, 0},
                                         {-1, -1, 0}, {0, -1, 0}, {1, -1, 0}, {1, 0, 0}};
const double kHalfRoot2 = std::sqrt(0.5);
const std::vector<double> kCircleWeights = {1, kHalfRoot2, 1, kHalfRoot2, 1, kHalfRoot2, 1, kHalfRoot2, 1};
const std::vector<double> kCircleKnots = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};

CurveModel circleModel(double radius) {
  CurveModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 3;
  m.dimension = 2;
  for (const dvec3& p : kCirclePoints) m.points.push_back(radius * p);
  m.weights = kCircleWeights;
  m.knots = kCircleKnots;
  return m;
}

// A torus as the surface of revolution of a circle of radius r about z, centred at distance R:
// P_ij = (x_j c_i.x, x_j c_i.y, z_j), w_ij = w_i w_j (The NURBS Book §8.5).
SurfaceModel torusModel(double R, double r) {
  SurfaceModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 3;
  m.orderV = 3;
  m.rows = m.cols = 9;
  m.knotsU = m.knotsV = kCircleKnots;
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) {
      const dvec3 c = kCirclePoints[size_t(i)], d = kCirclePoints[size_t(j)];
      const double x = R + r * d.x;
      m.points.push_back({x * c.x, x * c.y, r * d.y});
      m.weights.push_back(kCircleWeights[size_t(i)] * kCircleWeights[size_t(j)]);
    }
  return m;
}

constexpr double kUlp = 2.220446049250313e-16;

TEST(Nurbs, CircleEveryPointAtTheRadius) {
  for (double radius : {1.0, 3.5e-3, 7e5}) {
    const Curve c = Curve::create(circleModel(radius));
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
  const Surface s = Surface::create(torusModel(R, r));
  const FieldMask all = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv) | fieldBit(Field::Duu) |
                        fieldBit(Field::Duv) | fieldBit(Field::Dvv) | fieldBit(Field::Normal);
  double worst = 0.0, maxDiff = 0.0;
  const auto items = surfaceGridItems(s);
  size_t seen = 0;
  const int S = 9;
  sampleSurfaceGrid(s, {S, S, 0, 0}, all, [&](const GridChunk& ch) {
    for (size_t i = 0; i < ch.pointCount(); ++i, ++seen) {
      auto at = [&](Field f) { return dvec3(ch.coord(f, i, 0), ch.coord(f, i, 1), ch.coord(f, i, 2)); };
      const dvec3 p = at(Field::Point);
      const double ring = std::hypot(p.x, p.y) - R;
      worst = std::max(worst, std::abs(std::hypot(ring, p.z) - r) / r);
      // The grid equals the per-point evaluation (another summation order: a few ulps).
      const size_t item = seen / (S * S), k = seen % (S * S);
      const auto [pi, pj] = items[item];
      const SurfacePoint ref = s.evaluate(pi, pj, double(k / S) / (S - 1), double(k % S) / (S - 1));
      const dvec3 got[7] = {p, at(Field::Du), at(Field::Dv), at(Field::Duu), at(Field::Duv), at(Field::Dvv), at(Field::Normal)};
      const dvec3 want[7] = {ref.point, ref.du, ref.dv, ref.duu, ref.duv, ref.dvv, ref.normal};
      for (int f = 0; f < 7; ++f)
        maxDiff = std::max(maxDiff, glm::length(got[f] - want[f]) / (R + r + glm::length(want[f])));
    }
  }, {2, 50});
  EXPECT_EQ(seen, items.size() * S * S);
  EXPECT_LE(worst, 8 * kUlp);
  EXPECT_LE(maxDiff, 64 * kUlp);
  std::printf("torus: max |dist - r| / r = %.2e, grid vs per point %.2e\n", worst, maxDiff);
}

// The quotient rule against central differences of the point (and of the first derivative).
TEST(Nurbs, DerivativesMatchFiniteDifferences) {
  SurfaceModel m = torusModel(3.0, 1.25);
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
  SurfaceModel m = torusModel(3.0, 1.25);
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
    SurfaceModel m = torusModel(3.0, 1.25);
    m.weights[2 * 9 + 0] = c.w;  // point (0, 4.25, 0): 1e308 w P overflows
    try {
      validateSurface(m);
      ADD_FAILURE() << "weight " << c.w << " accepted";
    } catch (const ModelError& e) {
      EXPECT_EQ(e.field(), "weights[2][0]");
      EXPECT_NE(e.rule().find(c.rule), std::string::npos) << e.rule();
    }
  }
  CurveModel curve = circleModel(1.0);
  curve.weights.pop_back();
  EXPECT_THROW(validateCurve(curve), ModelError);
  curve = circleModel(1.0);
  curve.knots.clear();  // a uniform B-spline without a knot vector takes no weights
  EXPECT_THROW(validateCurve(curve), ModelError);
}

}  // namespace
}  // namespace shapespline
