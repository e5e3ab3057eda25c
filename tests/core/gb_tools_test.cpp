// Identities of the GB tools (docs/math.md §7): straight λ-paths, λ = 0 is the cubic B-spline, the
// constrained modification recovers a known (t0, λ0), every listed solution is exact, and bad input
// is rejected or reported.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <random>

#include <shapespline/core/bspline.h>
#include <shapespline/core/gb_tools.h>

namespace shapespline {
namespace {

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

CurveModel gbCurve(std::vector<glm::dvec2> pts, bool closed = false) {
  CurveModel m;
  m.family.construction = Construction::GB;
  m.closed = closed;
  m.dimension = 2;
  for (auto p : pts) m.points.emplace_back(p.x, p.y, 0.0);
  return m;
}

CurveModel randomConvexish(std::mt19937& rng, int count) {
  // Points on a noisy arc so every span bends the same way (σ ≠ 0).
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  std::vector<glm::dvec2> p;
  for (int i = 0; i < count; ++i) {
    const double a = 0.4 + 2.2 * i / (count - 1);
    p.emplace_back(4 * std::cos(a) + jitter(rng), 3 * std::sin(a) + jitter(rng));
  }
  return gbCurve(p);
}

TEST(GbTools, LambdaPathsAreStraightLines) {
  const CurveModel m = gbCurve({{0, 0}, {1, 3}, {4, 3}, {5, 0}, {7, 2}, {6, 5}});
  for (int span = 1; span <= 3; ++span)
    for (double t : {0.0, 0.1, 0.375, 0.5, 0.8, 1.0}) {
      const GbLambdaPath path = gbLambdaPath(m, span, t);
      const glm::dvec2 dir = path.c0 - path.e;
      const double len = glm::length(dir);
      ASSERT_GT(len, 1e-3);
      EXPECT_LT(glm::length(path.cMinus8 - gbSpanPoint(m, span, -8.0, t)), 1e-13);
      EXPECT_LT(glm::length(path.c0 - gbSpanPoint(m, span, 0.0, t)), 1e-14);
      for (double lambda : {-8.0, -5.0, -1.0, 0.5, 2.0, 10.0, 100.0, 1e4}) {
        const glm::dvec2 c = gbSpanPoint(m, span, lambda, t);
        // Collinear with C_0 and E, at the blend weight w = 12/(12+λ) (docs/math.md §7.1, C16).
        EXPECT_LT(std::abs(cross(c - path.e, dir)) / len, 2e-14 * 8) << "span " << span << " t " << t << " λ " << lambda;
        const double w = 12.0 / (12.0 + lambda);
        EXPECT_LT(glm::length(c - (w * path.c0 + (1 - w) * path.e)), 1e-13);
      }
      // λ → ∞ tends to E on the leg.
      EXPECT_LT(glm::length(gbSpanPoint(m, span, 1e12, t) - path.e), 1e-10);
    }
}

TEST(GbTools, LambdaZeroIsTheUniformCubicBSpline) {
  const std::vector<glm::dvec2> pts = {{0, 0}, {1, 3}, {4, 3}, {5, 0}, {7, 2}, {6, 5}, {3, 6}};
  const CurveModel m = gbCurve(pts);
  BSplineCurveData b{4, {}, {}, {}};
  for (auto p : pts) b.points.emplace_back(p.x, p.y, 0.0);
  for (int i = 0; i < static_cast<int>(pts.size()) + 4; ++i) b.knots.push_back(i);
  for (int span = 1; span <= static_cast<int>(pts.size()) - 3; ++span)
    for (double t = 0.0; t <= 1.0; t += 0.125) {
      // Span j of docs/math.md §1 uses P_{j−1}..P_{j+2}: the knot span [j+2, j+3) of the uniform knots.
      const glm::dvec3 ref = evalBSplineCurve(b, span + 2 + t).point;
      const glm::dvec2 c = gbSpanPoint(m, span, 0.0, t);
      EXPECT_LT(glm::length(c - glm::dvec2(ref.x, ref.y)), 1e-14) << "span " << span << " t " << t;
    }
}

TEST(GbTools, RoundTripRecoversTargetParameters) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> tDist(0.03, 0.97), lDist(0.0, 40.0);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    CurveModel m = randomConvexish(rng, 6);
    if (trial % 2) std::reverse(m.points.begin(), m.points.end());  // both orientations σ = ±1
    const int span = 1 + trial % 3;
    const double t0 = tDist(rng), lambda0 = lDist(rng);
    const glm::dvec2 x = gbSpanPoint(m, span, lambda0, t0);
    const GbFitResult fit = gbConstrainedModify(m, span, x);
    ASSERT_TRUE(fit.reachable) << fit.reason;
    const double w = 12.0 / (12.0 + lambda0);
    EXPECT_NEAR(fit.bisection.t0, t0, 1e-10) << "trial " << trial;
    EXPECT_NEAR(fit.bisection.w, w, 1e-10) << "trial " << trial;
    EXPECT_NEAR(fit.bisection.lambda0, lambda0, 12.0 / (w * w) * 1e-10) << "trial " << trial;
    const glm::dvec2 back = gbSpanPoint(m, span, fit.bisection.lambda0, fit.bisection.t0);
    EXPECT_LT(glm::length(back - x), 1e-10) << "trial " << trial;
    // λ0 ≥ 0: the solution is unique (docs/math.md §7.2).
    ASSERT_EQ(fit.all.size(), 1u) << "trial " << trial;
    EXPECT_NEAR(fit.all[0].t0, t0, 1e-10);
    ++checked;
  }
  EXPECT_EQ(checked, 200);
}

TEST(GbTools, AllSolutionsAreExactAndContainNegativeLambdaTargets) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> tDist(0.02, 0.98), lDist(-8.0, 0.0);
  int twoOrMore = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const CurveModel m = randomConvexish(rng, 5);
    const int span = 1 + trial % 2;
    const double t0 = tDist(rng), lambda0 = lDist(rng);
    const glm::dvec2 x = gbSpanPoint(m, span, lambda0, t0);
    const GbFitResult fit = gbConstrainedModify(m, span, x);
    bool found = false;
    for (const GbSolution& s : fit.all) {
      EXPECT_GT(s.w, 0.0);
      EXPECT_LE(s.w, 3.0 * (1 + 1e-12));
      EXPECT_LT(glm::length(gbSpanPoint(m, span, s.lambda0, s.t0) - x), 1e-9) << "trial " << trial;
      if (std::abs(s.t0 - t0) < 1e-9 && std::abs(s.lambda0 - lambda0) < 1e-7) found = true;
    }
    EXPECT_TRUE(found) << "trial " << trial << " t0 " << t0 << " λ0 " << lambda0;
    for (size_t i = 1; i < fit.all.size(); ++i) EXPECT_LT(fit.all[i - 1].t0, fit.all[i].t0);
    if (fit.all.size() >= 2) ++twoOrMore;
    if (fit.reachable) {  // the bisection answer is one of the listed solutions
      bool listed = false;
      for (const GbSolution& s : fit.all) listed |= std::abs(s.t0 - fit.bisection.t0) < 1e-9;
      EXPECT_TRUE(listed) << "trial " << trial;
    }
  }
  EXPECT_GT(twoOrMore, 0) << "no target of the λ < 0 region had two solutions";
}

TEST(GbTools, PolynomialRootsIncludeDoubleAndEndRoots) {
  // (t − 0.3)²(t − 0.7)·t·(t − 1) and a root-free one.
  auto mul = [](std::vector<double> p, double r) {
    std::vector<double> q(p.size() + 1, 0.0);
    for (size_t i = 0; i < p.size(); ++i) q[i + 1] += p[i], q[i] -= r * p[i];
    return q;
  };
  std::vector<double> p = {1.0};
  for (double r : {0.3, 0.3, 0.7, 0.0, 1.0, 1.5}) p = mul(p, r);
  const auto roots = polynomialRootsInUnitInterval(p);
  ASSERT_EQ(roots.size(), 4u);
  EXPECT_NEAR(roots[0], 0.0, 1e-14);
  EXPECT_NEAR(roots[1], 0.3, 1e-7);  // a double root is only determined to ~sqrt(eps)
  EXPECT_NEAR(roots[2], 0.7, 1e-14);
  EXPECT_NEAR(roots[3], 1.0, 1e-14);
  EXPECT_TRUE(polynomialRootsInUnitInterval(std::vector<double>{1.0, 0.0, 1.0}).empty());
  // Two roots closer than any sampling grid would resolve. (Closer than ~sqrt(rounding band),
  // about 1e-7 here, they are indistinguishable from a double root and merge into one.)
  std::vector<double> q = mul(mul({1.0}, 0.5), 0.5 + 1e-6);
  const auto close = polynomialRootsInUnitInterval(q);
  ASSERT_EQ(close.size(), 2u);
  // Conditioning: eps·sum|c| / |p'(root)| ≈ 5e-10.
  EXPECT_NEAR(close[0], 0.5, 1e-9);
  EXPECT_NEAR(close[1], 0.5 + 1e-6, 1e-9);
}

TEST(GbTools, FPolynomialMatchesTheCrossProduct) {
  const CurveModel m = gbCurve({{0, 0}, {2, 3}, {5, 4}, {8, 3}, {9, 0}});
  const glm::dvec2 x(4.2, 3.1);
  const auto f = gbPathPolynomial(m, 2, x);
  for (double t = 0; t <= 1.0; t += 0.0625) {
    double v = 0;
    for (int d = 6; d >= 0; --d) v = v * t + f[static_cast<size_t>(d)];
    const GbLambdaPath path = gbLambdaPath(m, 2, t);
    EXPECT_NEAR(v, cross(x - path.e, path.c0 - path.e), 1e-12);
  }
}

TEST(GbTools, UnreachableTargetsAreReported) {
  const CurveModel m = gbCurve({{0, 0}, {1, 3}, {4, 3}, {5, 0}});
  // Outside the region between the paths of t = 0 and t = 1.
  GbFitResult fit = gbConstrainedModify(m, 1, {-3.0, 2.0});
  EXPECT_FALSE(fit.reachable);
  EXPECT_NE(fit.reason.find("not reachable"), std::string::npos) << fit.reason;
  // On the t = 1/2 path but beyond C(−8, 1/2): w > 3.
  const GbLambdaPath path = gbLambdaPath(m, 1, 0.5);
  fit = gbConstrainedModify(m, 1, path.c0 + 5.0 * (path.c0 - path.e));
  EXPECT_FALSE(fit.reachable);
  EXPECT_NE(fit.reason.find("w = "), std::string::npos) << fit.reason;
  EXPECT_NEAR(fit.bisection.t0, 0.5, 1e-12);
  for (const auto& s : fit.all) EXPECT_GT(std::abs(s.t0 - 0.5), 1e-6);  // other path lines may pass through X
  // Exactly at C(−8, t): admissible, λ0 = −8.
  fit = gbConstrainedModify(m, 1, gbLambdaPath(m, 1, 0.25).cMinus8);
  bool atMinus8 = false;
  for (const auto& s : fit.all) atMinus8 |= std::abs(s.t0 - 0.25) < 1e-9 && std::abs(s.lambda0 + 8) < 1e-8;
  EXPECT_TRUE(atMinus8);
}

TEST(GbTools, RejectsInvalidInput) {
  CurveModel m = gbCurve({{0, 0}, {1, 3}, {4, 3}, {5, 0}});
  EXPECT_THROW(gbConstrainedModify(m, 0, {2, 2}), ModelError);  // spans 1..N−3 = 1..1
  EXPECT_THROW(gbConstrainedModify(m, 2, {2, 2}), ModelError);
  CurveModel three = m;
  three.dimension = 3;
  EXPECT_THROW(gbConstrainedModify(three, 1, {2, 2}), ModelError);
  // Collinear polygon: the λ = 0 arc lies on the leg line, σ = 0.
  EXPECT_THROW(gbConstrainedModify(gbCurve({{0, 0}, {1, 0}, {2, 0}, {3, 0}}), 1, {1.5, 1}), ModelError);
  // Closed curves have spans 0..N−1 with wrapped indices.
  const CurveModel closed = gbCurve({{0, 0}, {4, 0}, {5, 3}, {2, 5}, {-1, 3}}, true);
  const glm::dvec2 x = gbSpanPoint(closed, 0, 3.0, 0.4);
  const GbFitResult fit = gbConstrainedModify(closed, 0, x);
  ASSERT_TRUE(fit.reachable) << fit.reason;
  EXPECT_NEAR(fit.bisection.lambda0, 3.0, 1e-8);
  EXPECT_THROW(gbConstrainedModify(closed, 5, x), ModelError);
}

TEST(GbTools, CoarserStopToleranceStopsEarlier) {
  const CurveModel m = gbCurve({{0, 0}, {1, 3}, {4, 3}, {5, 0}});
  const glm::dvec2 x = gbSpanPoint(m, 1, 2.0, 0.3);
  const GbFitResult coarse = gbConstrainedModify(m, 1, x, 0x1p-20);
  EXPECT_NEAR(coarse.bisection.t0, 0.3, 0x1p-20);
  EXPECT_GT(std::abs(coarse.bisection.t0 - 0.3), 1e-13);  // really stopped at the coarser width
}

}  // namespace
}  // namespace shapespline
