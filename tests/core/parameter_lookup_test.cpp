// Curve::spanAt / Surface::patchAt, the one global-parameter lookup of evaluateAt and the GPU lists:
// evaluateAt(u) is evaluate() at the looked-up (span, t) bit for bit, joints go to the span to the
// right except at the upper end, and knot-vector lookups skip empty intervals.
#include "support/tolerances.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>

namespace shapespline::test {
namespace {


CurveModel curveOf(Construction c, int n) {
  CurveModel m;
  m.family.construction = c;
  m.family.degree = c == Construction::ExtendedBSpline ? 5 : 0;
  m.family.order = c == Construction::BSpline ? 4 : 0;
  m.dimension = 2;
  for (int i = 0; i < n; ++i) m.points.push_back({double(i), std::sin(1.3 * i), 0.0});
  return m;
}

void expectLookupMatchesEvaluate(const Curve& c, double u) {
  double t = -1.0;
  const int span = c.spanAt(u, t);
  ASSERT_GE(span, c.spans().first);
  ASSERT_LE(span, c.spans().last);
  ASSERT_TRUE(t >= 0.0 && t <= 1.0) << "u " << u;
  // Knot vectors evaluate at u itself, so only the span's parameter range is checked there.
  if (c.usesKnotVector()) {
    EXPECT_LE(c.parameterOf(span, 0.0), u);
    EXPECT_GE(c.parameterOf(span, 1.0), u);
    return;
  }
  EXPECT_TRUE(sameBits(c.evaluateAt(u).point, c.evaluate(span, t).point)) << "u " << u;
}

TEST(ParameterLookup, CurveSpansJointsAndEnds) {
  const Curve uniform = Curve::create(curveOf(Construction::ExtendedBSpline, 9));
  const auto [lo, hi] = uniform.parameterRange();
  double t = 0.0;
  EXPECT_EQ(uniform.spanAt(lo + 2.0, t), uniform.spans().first + 2) << "a joint belongs to the span on its right";
  EXPECT_EQ(t, 0.0);
  EXPECT_EQ(uniform.spanAt(hi, t), uniform.spans().last) << "except the upper end";
  EXPECT_EQ(t, 1.0);
  for (double u = lo; u <= hi; u += 0.37) expectLookupMatchesEvaluate(uniform, u);

  CurveModel withKnots = curveOf(Construction::ExtendedBSpline, 9);
  withKnots.knots = {0.0, 0.5, 1.75, 2.0, 3.5, 4.0, 4.25};
  const Curve spanKnots = Curve::create(withKnots);
  EXPECT_EQ(spanKnots.spanAt(1.75, t), spanKnots.spans().first + 2);
  EXPECT_EQ(t, 0.0);
  for (double u = 0.0; u <= 4.25; u += 0.29) expectLookupMatchesEvaluate(spanKnots, u);

  CurveModel knotVector = curveOf(Construction::BSpline, 6);
  knotVector.knots = {0, 0, 0, 0, 0.4, 0.4, 1, 1, 1, 1};  // interval 4 is empty
  const Curve bspline = Curve::create(knotVector);
  EXPECT_EQ(bspline.spanAt(0.4, t), 5) << "an interior double knot: the next non-empty interval";
  EXPECT_EQ(t, 0.0);
  EXPECT_EQ(bspline.spanAt(1.0, t), 5);
  EXPECT_EQ(t, 1.0);
  for (double u = 0.0; u <= 1.0; u += 0.07) expectLookupMatchesEvaluate(bspline, u);
}

TEST(ParameterLookup, SurfacePatchesMatchEvaluateAt) {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.rows = 4;
  m.cols = 5;
  m.closedV = true;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) m.points.push_back({double(i), std::cos(1.2566 * j), std::sin(1.2566 * j)});
  m.alpha.assign(m.points.size(), 0.5);
  const Surface s = Surface::create(m);
  const auto [ulo, uhi] = s.parameterRangeU();
  const auto [vlo, vhi] = s.parameterRangeV();
  int i = 0, j = 0;
  double u = 0.0, v = 0.0;
  s.patchAt(ulo + 1.0, vhi, i, j, u, v);
  EXPECT_EQ(i, s.patches().u.first + 1);
  EXPECT_EQ(u, 0.0);
  EXPECT_EQ(j, s.patches().v.last);
  EXPECT_EQ(v, 1.0);
  for (double U = ulo; U <= uhi; U += 0.41)
    for (double V = vlo; V <= vhi; V += 0.53) {
      s.patchAt(U, V, i, j, u, v);
      EXPECT_TRUE(sameBits(s.evaluateAt(U, V).point, s.evaluate(i, j, u, v).point)) << "(" << U << ", " << V << ")";
    }
}

}  // namespace
}  // namespace shapespline::test
