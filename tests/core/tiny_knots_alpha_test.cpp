// Issue 12, extreme values in core: knot vectors whose intervals are near 1e-310 (1/h overflows
// fp64) evaluate like the same knots scaled by a power of two (the parametrisation is affine in the
// knots), with derivatives scaled by 2^(k e) and surface normals unchanged; knot differences
// beyond fp64 are refused naming the knot; an α whose V_j exceeds fp64 is refused naming α.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <shapespline/core/bspline.h>
#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>
#include <shapespline/core/validate.h>

namespace shapespline {
namespace {

constexpr int kE = 1030;  // tiny knots are the unit knots times 2^-kE (subnormal: 2^-1030 ~ 8.7e-311)

std::vector<double> scaledKnots(const std::vector<double>& unit, int e) {
  std::vector<double> k;
  for (double x : unit) k.push_back(std::ldexp(x, e));
  return k;
}

TEST(TinyKnots, BasisOfSubnormalKnotIntervalsEqualsTheUnitBasisEveryOrder) {
  for (int order = 2; order <= 10; ++order) {
    std::vector<double> unit;
    const int count = order + 3;
    for (int i = 0; i < count + order; ++i) unit.push_back(i < order ? 0.0 : i >= count ? count - order + 1.0 : i - order + 1.0);
    const std::vector<double> tiny = scaledKnots(unit, -kE);
    for (int span = order - 1; span < count; ++span) {
      for (double s : {0.0, 0.25, 0.5, 1.0}) {  // exact at 2^-kE
        const double t = unit[span] + s * (unit[span + 1] - unit[span]);
        double a[kMaxBasisCount][kMaxBasisCount] = {}, b[kMaxBasisCount][kMaxBasisCount] = {};
        bsplineBasisAllDerivs(order, unit, span, t, 0, a);
        bsplineBasisAllDerivs(order, tiny, span, std::ldexp(t, -kE), 0, b);
        double sum = 0.0;
        for (int r = 0; r < order; ++r) {
          ASSERT_TRUE(std::isfinite(b[0][r])) << "order " << order << " span " << span << " s " << s << " r " << r;
          EXPECT_NEAR(b[0][r], a[0][r], 1e-13) << "order " << order << " span " << span << " s " << s << " r " << r;
          sum += b[0][r];
        }
        EXPECT_NEAR(sum, 1.0, 1e-13) << "order " << order;
      }
    }
  }
}

TEST(TinyKnots, CurveDerivativesThatFitFp64AreFiniteAndScaled) {
  // Points 2^-1000 apart and knots 2^-1030 apart: d1 ~ 2^30 is representable, although 1/h alone
  // (2^1030) is not; d2 ~ 2^1060 is not, and comes out as inf (beyond fp64), never NaN.
  BSplineCurveData unit{4, {0, 0, 0, 0, 1, 2, 3, 3, 3, 3}, {}, {}};
  const double p[6][2] = {{0, 0}, {1, 2}, {3, 3}, {5, 1}, {6, 4}, {8, 3}};
  for (const auto& q : p) unit.points.emplace_back(q[0], q[1], 0.0);
  BSplineCurveData tiny = unit;
  tiny.knots = scaledKnots(unit.knots, -kE);
  for (auto& q : tiny.points) q = {std::ldexp(q.x, -1000), std::ldexp(q.y, -1000), 0.0};
  for (double t : {0.0, 0.375, 1.5, 2.875, 3.0}) {  // exact at 2^-kE
    const BSplineCurvePoint a = evalBSplineCurve(unit, t), b = evalBSplineCurve(tiny, std::ldexp(t, -kE));
    for (int c = 0; c < 2; ++c) {
      EXPECT_NEAR(std::ldexp(b.point[c], 1000), a.point[c], 1e-12) << "t " << t;
      EXPECT_NEAR(std::ldexp(b.d1[c], 1000 - kE), a.d1[c], 1e-11) << "t " << t;
      EXPECT_TRUE(a.d2[c] == 0.0 ? b.d2[c] == 0.0 : std::isinf(b.d2[c]) && (b.d2[c] > 0) == (a.d2[c] > 0))
          << "t " << t << ": d2 " << b.d2[c] << " for " << a.d2[c];
    }
  }
}

TEST(TinyKnots, SurfaceNormalsSurviveDerivativesBeyondFp64) {
  auto model = [](std::vector<double> ku) {
    SurfaceModel m;
    m.family.construction = Construction::BSpline;
    m.family.order = 3;
    m.orderV = 3;
    m.rows = m.cols = 4;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) m.points.emplace_back(i, j, std::sin(0.9 * i + 0.3) * std::cos(0.7 * j));
    m.knotsU = std::move(ku);
    m.knotsV = {0, 0, 0, 0.5, 1, 1, 1};
    return Surface::create(std::move(m));
  };
  const std::vector<double> unit = {0, 0, 0, 1, 2, 2, 2};
  const Surface a = model(unit), b = model(scaledKnots(unit, -kE));
  for (int i = 2; i <= 3; ++i)
    for (int j = 2; j <= 3; ++j)
      for (double u : {0.0, 0.5, 1.0})
        for (double v : {0.0, 0.25, 1.0}) {
          const SurfacePoint pa = a.evaluate(i, j, u, v), pb = b.evaluate(i, j, u, v);
          EXPECT_FALSE(std::isfinite(pb.du.x) && std::isfinite(pb.du.y) && std::isfinite(pb.du.z) && pb.du != glm::dvec3(0.0))
              << "du should exceed fp64 here; the test is not testing what it claims";
          for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(pb.point[c], pa.point[c], 1e-12) << i << "," << j << " " << u << "," << v;
            EXPECT_NEAR(pb.normal[c], pa.normal[c], 1e-12) << i << "," << j << " " << u << "," << v;
          }
          EXPECT_EQ(pb.normalRule, pa.normalRule);
        }
}

TEST(TinyKnots, KnotDifferencesBeyondFp64AreRefusedNamingTheKnot) {
  CurveModel m;
  m.family.construction = Construction::GB;
  m.dimension = 2;
  for (int i = 0; i < 6; ++i) m.points.emplace_back(i, i % 2, 0.0);
  m.knots = {-1.7e308, -1e308, 1e308, 1.7e308};
  try {
    validateCurve(m);
    ADD_FAILURE() << "accepted knots whose differences overflow";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "knots[2]");
    EXPECT_NE(e.rule().find("knot differences must be finite"), std::string::npos) << e.rule();
  }
  m.knots = {-1e308, -0.5e308, 0.5e308, 0.7e308};  // t_3 - t_0 = 1.7e308: finite
  EXPECT_NO_THROW(validateCurve(m));
}

TEST(TinyAlpha, AVertexBeyondFp64IsRefusedNamingAlphaAndPEqualNodeStaysFinite) {
  const glm::dvec3 p(1, 2, 0), node(0.5, 1.5, 0);
  try {
    alphaEBVertex(p, node, 1e-310, [] { return std::string("alpha[3]"); });
    ADD_FAILURE() << "accepted V beyond fp64";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "alpha[3]");
    EXPECT_EQ(e.value(), "1e-310");
    EXPECT_NE(e.rule().find("exceeds the fp64 range"), std::string::npos) << e.rule();
  }
  // (1 - α)/α overflows, but P = node makes V = P (it was 0 * inf = NaN).
  const glm::dvec3 v = alphaEBVertex(p, p, 1e-310, [] { return std::string("alpha[0]"); });
  EXPECT_EQ(v, p);
  // Tiny but with a finite V: the unchanged formula, bit for bit.
  EXPECT_EQ(alphaEBVertex(p, node, 1e-300, [] { return std::string("alpha[0]"); }), p + ((1.0 - 1e-300) / 1e-300) * (p - node));
}

}  // namespace
}  // namespace shapespline
