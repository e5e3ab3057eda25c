// Identities of B-spline unclamping and extension (docs/math.md §10.2–§10.7): the worked example, the
// extended curve keeps the original on [a, b], passes through every target at u_s, is C^{k−2} at b
// and at the interior u_s, and surface extension reaches the target curves; invalid input throws.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <random>
#include <vector>

#include <shapespline/core/extension.h>

namespace shapespline {
namespace {

BSplineCurveData workedExample() {
  return {4, {0, 0, 0, 0, 0.25, 0.5, 1, 1, 1, 1}, {{0, 0, 0}, {1, 2, 0}, {3, 3, 0}, {5, 1, 0}, {6, 4, 0}, {8, 3, 0}}, {}};
}

void expectPoint(const glm::dvec3& actual, glm::dvec3 expected, double tol, const std::string& what) {
  EXPECT_LT(glm::length(actual - expected), tol) << what << ": got (" << actual.x << ", " << actual.y << ", "
                                                 << actual.z << ")";
}

// docs/math.md §10.7, exact rationals from the specification.
TEST(Extension, WorkedExampleOneTarget) {
  const BSplineCurveData c = workedExample();
  const std::vector<glm::dvec3> targets = {{10, 5, 0}};
  const ExtensionResult e = extendCurve(c, targets, std::vector<double>{1.5});
  const std::vector<double> kFinal = {0, 0, 0, 0, 0.25, 0.5, 1, 1.5, 1.5, 1.5, 1.5};
  EXPECT_EQ(e.curve.knots, kFinal);
  EXPECT_EQ(e.unclampKnots, std::vector<double>(kFinal.begin(), kFinal.end() - 1));
  const std::vector<glm::dvec3> unclamped = {{0, 0, 0}, {1, 2, 0}, {3, 3, 0}, {5, 1, 0}, {20.0 / 3, 6, 0}, {40.0 / 3, -2, 0}};
  ASSERT_EQ(e.unclampedPoints.size(), unclamped.size());
  for (size_t i = 0; i < unclamped.size(); ++i) expectPoint(e.unclampedPoints[i], unclamped[i], 1e-14, "Q" + std::to_string(i));
  ASSERT_EQ(e.curve.points.size(), 7u);
  EXPECT_EQ(e.curve.points[6], glm::dvec3(10, 5, 0));
  const auto at1 = evalBSplineCurve(e.curve, 1.0);
  expectPoint(at1.point, {8, 3, 0}, 1e-14, "C(1)");
  expectPoint(at1.d1, {12, -6, 0}, 1e-13, "C'(1)");
  expectPoint(evalBSplineCurve(e.curve, 1.25).point, {11, 1, 0}, 1e-14, "C(5/4)");
  expectPoint(evalBSplineCurve(e.curve, 1.5).point, {10, 5, 0}, 1e-14, "C(3/2)");
  EXPECT_NEAR(e.knotsNormalized[4], 1.0 / 6, 1e-16);
}

TEST(Extension, WorkedExampleTwoTargets) {
  const BSplineCurveData c = workedExample();
  const std::vector<glm::dvec3> targets = {{10, 5, 0}, {12, 3, 0}};
  const ExtensionResult e = extendCurve(c, targets, std::vector<double>{1.5, 2.0});
  EXPECT_EQ(e.curve.knots, (std::vector<double>{0, 0, 0, 0, 0.25, 0.5, 1, 1.5, 2, 2, 2, 2}));
  EXPECT_EQ(e.unclampKnots, (std::vector<double>{0, 0, 0, 0, 0.25, 0.5, 1, 1.5, 2, 2}));
  expectPoint(e.unclampedPoints[4], {20.0 / 3, 6, 0}, 1e-14, "Q4");
  expectPoint(e.unclampedPoints[5], {50.0 / 3, -6, 0}, 1e-13, "Q5");
  expectPoint(e.curve.points[6], {-10.0 / 3, 30, 0}, 1e-12, "Q6");
  EXPECT_EQ(e.curve.points[7], glm::dvec3(12, 3, 0));
  expectPoint(evalBSplineCurve(e.curve, 1.5).point, {10, 5, 0}, 1e-13, "C(3/2)");
  expectPoint(evalBSplineCurve(e.curve, 2.0).point, {12, 3, 0}, 1e-13, "C(2)");
}

// Right-clamped random curve of order k on [a, b] with well-separated knots (so the §14 growth of
// the inverse steps stays moderate); the left end is clamped or not.
BSplineCurveData randomCurve(std::mt19937& rng, int order, int count, bool leftClamped) {
  std::uniform_real_distribution<double> unit(0.0, 1.0), coord(-2.0, 2.0);
  const double a = 0.5, b = 2.0;
  BSplineCurveData c{order, {}, {}, {}};
  for (int i = 0; i < order; ++i) c.knots.push_back(leftClamped ? a : a - 0.2 * (order - 1 - i));
  const int interior = count - order;
  for (int i = 1; i <= interior; ++i) c.knots.push_back(a + (b - a) * (i + 0.4 * (unit(rng) - 0.5)) / (interior + 1));
  for (int i = 0; i < order; ++i) c.knots.push_back(b);
  for (int i = 0; i < count; ++i) c.points.emplace_back(coord(rng), coord(rng), coord(rng));
  return c;
}

std::vector<glm::dvec3> randomTargets(std::mt19937& rng, const BSplineCurveData& c, int m) {
  std::uniform_real_distribution<double> step(-1.0, 1.0);
  std::vector<glm::dvec3> t;
  glm::dvec3 p = c.points.back();
  for (int s = 0; s < m; ++s) {
    p += glm::dvec3(1.0 + 0.5 * step(rng), step(rng), step(rng));
    t.push_back(p);
  }
  return t;
}

struct Sweep {
  int order;
  int targets;
  bool chord;
};

class ExtensionSweep : public ::testing::TestWithParam<Sweep> {};

TEST_P(ExtensionSweep, KeepsCurveHitsTargetsAndIsSmooth) {
  const auto [k, m, chord] = GetParam();
  std::mt19937 rng(static_cast<unsigned>(100 * k + 10 * m + chord));
  for (int trial = 0; trial < 3; ++trial) {
    const BSplineCurveData c = randomCurve(rng, k, k + 2 + trial, trial != 1);
    const auto targets = randomTargets(rng, c, m);
    std::optional<std::vector<double>> given;
    if (!chord) {
      given.emplace();
      for (int s = 1; s <= m; ++s) given->push_back(2.0 + 0.3 * s + 0.05 * trial);
    }
    const ExtensionResult e = extendCurve(c, targets, given);
    const BSplineCurveData& x = e.curve;
    const int n = static_cast<int>(c.points.size()) - 1;
    const double a = c.knots[static_cast<size_t>(k - 1)], b = c.knots[static_cast<size_t>(n + 1)];
    ASSERT_EQ(x.points.size(), static_cast<size_t>(n + m + 1));
    ASSERT_EQ(x.knots.size(), static_cast<size_t>(n + m + k + 1));
    ASSERT_EQ(e.u.size(), static_cast<size_t>(m));
    // Points not touched by unclamping (docs/math.md §10.2).
    for (int i = 0; i <= n - k + 2; ++i) EXPECT_EQ(e.unclampedPoints[static_cast<size_t>(i)], c.points[static_cast<size_t>(i)]);
    if (chord) {
      EXPECT_EQ(e.u, chordParameters(c, targets));
      EXPECT_GT(e.u[0], b);
    }
    // Unchanged on [a, b]; the tolerance carries the 1/α growth of Algorithm U (≤ ~10 here).
    for (int q = 0; q <= 200; ++q) {
      const double t = a + (b - a) * q / 200.0;
      const auto p0 = evalBSplineCurve(c, t), p1 = evalBSplineCurve(x, t);
      ASSERT_LT(glm::length(p0.point - p1.point), 1e-11) << "k " << k << " m " << m << " t " << t;
      // At t = b the original is evaluated from the left; for k = 2 the extension is only C^0 there.
      if (k > 2 || t < b) {
        ASSERT_LT(glm::length(p0.d1 - p1.d1), 1e-9 * (1 + glm::length(p0.d1))) << "k " << k << " t " << t;
      }
    }
    // Through every target at u_s, clamped at the last one.
    for (int s = 0; s < m; ++s)
      EXPECT_LT(glm::length(evalBSplineCurve(x, e.u[static_cast<size_t>(s)]).point - targets[static_cast<size_t>(s)]), 1e-9)
          << "k " << k << " m " << m << " s " << s;
    EXPECT_EQ(x.points.back(), targets.back());
    // C^{k−2} at b and at u_1..u_{m−1}: the pieces on both sides agree in derivatives 0..k−2.
    for (int s = 0; s < m; ++s) {
      const double knot = s == 0 ? b : e.u[static_cast<size_t>(s - 1)];
      const int right = n + s + 1;  // knot index of the junction: t_{n+1} = b, t_{n+1+s} = u_s
      ASSERT_EQ(x.knots[static_cast<size_t>(right)], knot);
      glm::dvec3 l[kMaxBasisCount], r[kMaxBasisCount];
      evalBSplineCurveOnSpan(x, right - 1, knot, k - 1, l);
      evalBSplineCurveOnSpan(x, right, knot, k - 1, r);
      double mag = 1.0;
      for (int d = 0; d <= k - 2; ++d) {
        mag = std::max(mag, glm::length(l[d]));
        EXPECT_LT(glm::length(l[d] - r[d]), 1e-8 * mag * (1 + glm::length(l[d])))
            << "k " << k << " m " << m << " junction " << s << " derivative " << d;
      }
      // Not C^{k−1} in general: the jump exists (guards against comparing a piece with itself).
      EXPECT_GT(glm::length(l[k - 1] - r[k - 1]), 0.0) << "k " << k << " junction " << s;
    }
    for (size_t i = 0; i < x.knots.size(); ++i)
      EXPECT_NEAR(e.knotsNormalized[i], (x.knots[i] - a) / (e.u.back() - a), 1e-15);
  }
}

std::vector<Sweep> sweepCases() {
  std::vector<Sweep> v;
  for (int k = 2; k <= 6; ++k)
    for (int m = 1; m <= 4; ++m)
      for (bool chord : {false, true}) v.push_back({k, m, chord});
  return v;
}

INSTANTIATE_TEST_SUITE_P(OrdersTargets, ExtensionSweep, ::testing::ValuesIn(sweepCases()),
                         [](const ::testing::TestParamInfo<Sweep>& info) {
                           return "k" + std::to_string(info.param.order) + "_m" + std::to_string(info.param.targets) +
                                  (info.param.chord ? "_chord" : "_given");
                         });

TEST(Extension, UnclampKeepsTheCurveForOrdersTwoToTen) {
  std::mt19937 rng(21);
  for (int k = 2; k <= kMaxBasisCount; ++k) {
    const BSplineCurveData c = randomCurve(rng, k, k + 3, true);
    std::vector<double> newKnots;
    for (int l = 0; l < k - 1; ++l) newKnots.push_back(2.2 + 0.15 * l);
    const BSplineCurveData u = unclampRight(c, newKnots);
    for (int q = 0; q <= 100; ++q) {
      const double t = 0.5 + 1.5 * q / 100.0;
      EXPECT_LT(glm::length(evalBSplineCurve(c, t).point - evalBSplineCurve(u, t).point), 1e-9) << "k " << k;
    }
    if (k >= 3) {
      EXPECT_GT(glm::length(u.points.back() - c.points.back()), 1e-6);  // really unclamped
    }
  }
}

TEST(Extension, ChordParametersFollowTheChordRule) {
  const BSplineCurveData c = workedExample();
  const std::vector<glm::dvec3> targets = {{10, 5, 0}, {12, 3, 0}};
  double length = 0;  // the non-empty knot spans are [0, 1/4], [1/4, 1/2], [1/2, 1]
  for (auto [t0, t1] : {std::pair{0.0, 0.25}, std::pair{0.25, 0.5}, std::pair{0.5, 1.0}})
    length += glm::length(evalBSplineCurve(c, t1).point - evalBSplineCurve(c, t0).point);
  const auto u = chordParameters(c, targets);
  ASSERT_EQ(u.size(), 2u);
  EXPECT_NEAR(u[0], 1 + std::sqrt(8.0) / length, 1e-15);
  EXPECT_NEAR(u[1], u[0] + std::sqrt(8.0) / length, 1e-15);
  // Golden pub.extend.k4.two.chord: u_1 = 1.3082184259827728662.
  EXPECT_NEAR(u[0], 1.3082184259827728662, 1e-15);
}

TEST(Extension, RejectsInvalidInput) {
  const BSplineCurveData c = workedExample();
  const std::vector<glm::dvec3> ok = {{10, 5, 0}};
  BSplineCurveData unclamped = c;
  unclamped.knots.back() = 1.5;
  EXPECT_THROW(extendCurve(unclamped, ok), ModelError);
  EXPECT_THROW(extendCurve(c, std::vector<glm::dvec3>{}), ModelError);
  EXPECT_THROW(extendCurve(c, std::vector<glm::dvec3>{{8, 3, 0}}), ModelError);             // = end point
  EXPECT_THROW(extendCurve(c, std::vector<glm::dvec3>{{10, 5, 0}, {10, 5, 0}}), ModelError);  // repeated
  EXPECT_THROW(extendCurve(c, ok, std::vector<double>{1.0}), ModelError);                    // not > b
  EXPECT_THROW(extendCurve(c, ok, std::vector<double>{1.5, 2.0}), ModelError);               // wrong count
  const std::vector<glm::dvec3> two = {{10, 5, 0}, {12, 3, 0}};
  EXPECT_THROW(extendCurve(c, two, std::vector<double>{2.0, 1.5}), ModelError);  // decreasing
  EXPECT_THROW(extendCurve(c, two, std::vector<double>{1.5, 1.5}), ModelError);  // equal
  EXPECT_THROW(unclampRight(c, std::vector<double>{1.0, 1.5, 2.0}), ModelError);  // not > b
  EXPECT_THROW(unclampRight(c, std::vector<double>{1.5, 1.25, 2.0}), ModelError);  // decreasing
  EXPECT_THROW(unclampRight(c, std::vector<double>{1.5, 2.0}), ModelError);       // k − 1 values
  try {
    extendCurve(c, std::vector<glm::dvec3>{{8, 3, 0}});
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "targets[0]");
    EXPECT_FALSE(e.rule().empty());
  }
}

BSplineSurfaceData randomSurface(std::mt19937& rng, int ku, int kv, int rows, int cols) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  BSplineSurfaceData s;
  s.orderU = ku, s.orderV = kv, s.rows = rows, s.cols = cols;
  s.knotsU = randomCurve(rng, ku, rows, true).knots;
  for (int i = 0; i < kv; ++i) s.knotsV.push_back(0.0);
  for (int i = 1; i <= cols - kv; ++i) s.knotsV.push_back(static_cast<double>(i) / (cols - kv + 1));
  for (int i = 0; i < kv; ++i) s.knotsV.push_back(1.0);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) s.points.emplace_back(j + 0.3 * unit(rng), i + 0.3 * unit(rng), unit(rng));
  return s;
}

TEST(Extension, SurfaceReachesTargetCurvesAndKeepsTheSurface) {
  std::mt19937 rng(31);
  for (int ku = 2; ku <= 5; ++ku)
    for (int kv : {2, 3, 4})
      for (int m = 1; m <= 3; ++m)
        for (bool chord : {false, true}) {
          const BSplineSurfaceData s = randomSurface(rng, ku, kv, ku + 2, kv + 2);
          std::vector<std::vector<glm::dvec3>> targets;
          for (int q = 1; q <= m; ++q) {
            std::vector<glm::dvec3> row;
            for (int j = 0; j < s.cols; ++j) row.emplace_back(j + 0.2 * q, s.rows - 1 + 1.2 * q, 0.1 * q);
            targets.push_back(row);
          }
          std::optional<std::vector<double>> given;
          if (!chord) given = std::vector<double>{2.4, 2.9, 3.3};
          if (given) given->resize(static_cast<size_t>(m));
          const SurfaceExtensionResult e = extendSurfaceU(s, targets, given);
          ASSERT_EQ(e.surface.rows, s.rows + m);
          if (chord) {
            ASSERT_EQ(e.uPerColumn.size(), static_cast<size_t>(s.cols));
            for (int q = 0; q < m; ++q) {
              double avg = 0;
              for (const auto& col : e.uPerColumn) avg += col[static_cast<size_t>(q)];
              EXPECT_NEAR(e.u[static_cast<size_t>(q)], avg / s.cols, 1e-14);
            }
          }
          for (int q = 0; q < m; ++q) {
            const BSplineCurveData target{kv, s.knotsV, targets[static_cast<size_t>(q)], {}};
            for (double v = 0; v <= 1.0; v += 0.125) {
              const auto p = evalBSplineSurface(e.surface, e.u[static_cast<size_t>(q)], v);
              EXPECT_LT(glm::length(p.point - evalBSplineCurve(target, v).point), 1e-9)
                  << "ku " << ku << " kv " << kv << " m " << m << " s " << q << " v " << v;
            }
          }
          for (double u = 0.5; u <= 2.0; u += 0.125)
            for (double v = 0; v <= 1.0; v += 0.25)
              EXPECT_LT(glm::length(evalBSplineSurface(s, u, v).point - evalBSplineSurface(e.surface, u, v).point), 1e-10);
        }
}

TEST(Extension, SurfaceRejectsMismatchedTargetCurves) {
  std::mt19937 rng(41);
  const BSplineSurfaceData s = randomSurface(rng, 3, 3, 4, 4);
  std::vector<std::vector<glm::dvec3>> targets = {{{0, 9, 0}, {1, 9, 0}, {2, 9, 0}}};  // 3 points, 4 columns
  EXPECT_THROW(extendSurfaceU(s, targets), ModelError);
  EXPECT_THROW(extendSurfaceU(s, std::vector<std::vector<glm::dvec3>>{}), ModelError);
}

}  // namespace
}  // namespace shapespline
