// Identities of the knot-vector B-spline kernels (docs/math.md §10.1): an independent Cox–de Boor
// reference, partition of unity, derivatives against finite differences and against the derivative
// curve, end interpolation of clamped curves, and the tensor-product structure of surfaces.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <random>
#include <vector>

#include <shapespline/core/bspline.h>

namespace shapespline {
namespace {

// Random non-decreasing knot vector for `count` points of order k on [a, b] with the end knots
// clamped (when `clamped`) or spread below a / above b; interior knots may repeat up to k−1 times.
std::vector<double> randomKnots(std::mt19937& rng, int order, int count, bool clamped, bool allowRepeats) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double a = -0.75, b = 2.5;
  std::vector<double> interior;
  for (int i = 0; i < count - order; ++i) interior.push_back(a + (b - a) * (0.05 + 0.9 * unit(rng)));
  std::sort(interior.begin(), interior.end());
  if (allowRepeats && interior.size() >= 2) {
    for (size_t i = 1; i < interior.size() && static_cast<int>(i) < order - 1; ++i) interior[i] = interior[0];
  }
  std::vector<double> knots;
  for (int i = 0; i < order; ++i) knots.push_back(clamped ? a : a - 0.3 * (order - 1 - i));
  knots.insert(knots.end(), interior.begin(), interior.end());
  for (int i = 0; i < order; ++i) knots.push_back(clamped ? b : b + 0.25 * i);
  return knots;
}

std::vector<glm::dvec3> randomPoints(std::mt19937& rng, int count) {
  std::uniform_real_distribution<double> coord(-3.0, 3.0);
  std::vector<glm::dvec3> p;
  for (int i = 0; i < count; ++i) p.emplace_back(coord(rng), coord(rng), coord(rng));
  return p;
}

// Textbook recursive Cox–de Boor with 0/0 := 0 and half-open spans; the right end of the domain
// is treated as the limit from the left by the caller.
double coxDeBoor(const std::vector<double>& t, int i, int order, double x) {
  if (order == 1) return (t[i] <= x && x < t[i + 1]) ? 1.0 : 0.0;
  double v = 0.0;
  const double d1 = t[i + order - 1] - t[i], d2 = t[i + order] - t[i + 1];
  if (d1 > 0) v += (x - t[i]) / d1 * coxDeBoor(t, i, order - 1, x);
  if (d2 > 0) v += (t[i + order] - x) / d2 * coxDeBoor(t, i + 1, order - 1, x);
  return v;
}

TEST(BSplineBasis, MatchesRecursiveCoxDeBoorAndSumsToOne) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int order = 2; order <= kMaxBasisCount; ++order) {
    for (int trial = 0; trial < 4; ++trial) {
      const int count = order + 2 + trial;
      const auto knots = randomKnots(rng, order, count, trial % 2 == 0, trial >= 2);
      const double a = knots[order - 1], b = knots[count];
      for (int q = 0; q < 50; ++q) {
        const double x = a + (b - a) * unit(rng);
        const int span = findKnotSpan(order, knots, count, x);
        ASSERT_LE(knots[span], x);
        ASSERT_LT(x, knots[span + 1]);
        double out[3][kMaxBasisCount];
        bsplineBasisDerivs(order, knots, span, x, std::min(2, order - 1), out);
        double sum = 0, sum1 = 0, sum2 = 0;
        for (int r = 0; r < order; ++r) {
          EXPECT_NEAR(out[0][r], coxDeBoor(knots, span - order + 1 + r, order, x), 1e-14)
              << "order " << order << " x " << x << " r " << r;
          EXPECT_GE(out[0][r], -1e-15);
          sum += out[0][r];
          sum1 += out[1][r];
          if (order > 2) sum2 += out[2][r];
        }
        EXPECT_NEAR(sum, 1.0, 1e-14) << "order " << order;
        // sum N' = sum N'' = 0; their terms are of size (k−1)/h and (k−1)(k−2)/h^2.
        EXPECT_NEAR(sum1, 0.0, 1e-10) << "order " << order;
        EXPECT_NEAR(sum2, 0.0, 1e-7) << "order " << order;
      }
    }
  }
}

// knotIntervalBasis: the interval's basis in the power basis of its local parameter, against the
// independent Cox–de Boor values inside the interval and at both ends (the right end as the limit
// from the left), and its derivative against bsplineBasisDerivs' times h.
TEST(BSplineBasis, IntervalPowerBasisIsTheSpansPolynomial) {
  std::mt19937 rng(23);
  for (int order = 2; order <= kMaxBasisCount; ++order) {
    for (int trial = 0; trial < 4; ++trial) {
      const int count = order + 3 + trial;
      const auto knots = randomKnots(rng, order, count, trial % 2 == 0, trial >= 2);
      for (int span = order - 1; span < count; ++span) {
        const double t0 = knots[span], h = knots[span + 1] - t0;
        if (!(h > 0)) continue;
        const SpanBasis b = knotIntervalBasis(order, knots, span);
        ASSERT_EQ(b.count, order);
        ASSERT_EQ(b.degree, order - 1);
        for (double s : {0.0, 0.125, 0.5, 0.8, 1.0}) {
          double value[kMaxBasisCount], d1[kMaxBasisCount];
          evalSpanBasis(b, s, value, d1, nullptr);
          double out[3][kMaxBasisCount];
          bsplineBasisDerivs(order, knots, span, t0 + s * h, 1, out);
          for (int r = 0; r < order; ++r) {
            const double x = s < 1.0 ? t0 + s * h : std::nextafter(knots[span + 1], t0);
            EXPECT_NEAR(value[r], coxDeBoor(knots, span - order + 1 + r, order, x), 1e-12)
                << "order " << order << " span " << span << " s " << s << " r " << r;
            EXPECT_NEAR(d1[r], out[1][r] * h, 1e-11 * order) << "order " << order << " span " << span << " s " << s;
          }
        }
      }
    }
  }
}

TEST(BSplineBasis, FindKnotSpanAtKnotsAndEnds) {
  const std::vector<double> knots = {0, 0, 0, 0, 0.25, 0.5, 0.5, 1, 1, 1, 1};
  const int order = 4, count = 7;
  EXPECT_EQ(findKnotSpan(order, knots, count, 0.0), 3);
  EXPECT_EQ(findKnotSpan(order, knots, count, -1.0), 3);  // clamped to the domain
  EXPECT_EQ(findKnotSpan(order, knots, count, 0.25), 4);
  EXPECT_EQ(findKnotSpan(order, knots, count, 0.3), 4);
  EXPECT_EQ(findKnotSpan(order, knots, count, 0.5), 6);   // [0.5,0.5) is empty: the next one
  EXPECT_EQ(findKnotSpan(order, knots, count, 1.0), 6);   // right end: last non-empty span
  EXPECT_EQ(findKnotSpan(order, knots, count, 7.0), 6);
}

TEST(BSplineCurve, ClampedEndsInterpolateAndEndTangents) {
  std::mt19937 rng(5);
  for (int order = 2; order <= kMaxBasisCount; ++order) {
    const int count = order + 3;
    BSplineCurveData c{order, randomKnots(rng, order, count, true, false), randomPoints(rng, count), {}};
    const double a = c.knots[order - 1], b = c.knots[count];
    const auto s = evalBSplineCurve(c, a), e = evalBSplineCurve(c, b);
    EXPECT_LT(glm::length(s.point - c.points.front()), 1e-14);
    EXPECT_LT(glm::length(e.point - c.points.back()), 1e-14);
    const glm::dvec3 d0 = (order - 1.0) * (c.points[1] - c.points[0]) / (c.knots[order] - c.knots[1]);
    const glm::dvec3 dn = (order - 1.0) * (c.points[count - 1] - c.points[count - 2]) /
                          (c.knots[count + order - 2] - c.knots[count - 1]);
    EXPECT_LT(glm::length(s.d1 - d0), 1e-12 * glm::length(d0)) << "order " << order;
    EXPECT_LT(glm::length(e.d1 - dn), 1e-12 * glm::length(dn)) << "order " << order;
  }
}

TEST(BSplineCurve, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int order = 2; order <= 8; ++order) {
    const int count = order + 4;
    BSplineCurveData c{order, randomKnots(rng, order, count, order % 2 == 0, false), randomPoints(rng, count), {}};
    const double a = c.knots[order - 1], b = c.knots[count];
    for (int q = 0; q < 30; ++q) {
      const double x = a + (b - a) * (0.02 + 0.96 * unit(rng));
      const int span = findKnotSpan(order, c.knots, count, x);
      // Five-point differences (truncation O(h^4)) inside one knot span.
      const double h = std::min(1e-3 * (b - a), std::min(x - c.knots[span], c.knots[span + 1] - x) / 3);
      if (!(h > 1e-6)) continue;  // too close to a knot for a one-span difference
      const auto p = evalBSplineCurve(c, x);
      const auto f = [&](double dx) { return evalBSplineCurve(c, x + dx); };
      const auto m2 = f(-2 * h), m1 = f(-h), p1 = f(h), p2 = f(2 * h);
      const glm::dvec3 fd1 = (m2.point - 8.0 * m1.point + 8.0 * p1.point - p2.point) / (12 * h);
      const glm::dvec3 fd2 = (m2.d1 - 8.0 * m1.d1 + 8.0 * p1.d1 - p2.d1) / (12 * h);
      EXPECT_LT(glm::length(p.d1 - fd1), 1e-6 * (1 + glm::length(p.d1))) << "order " << order << " x " << x;
      if (order > 2) {
        EXPECT_LT(glm::length(p.d2 - fd2), 1e-6 * (1 + glm::length(p.d2))) << "order " << order;
      } else {
        EXPECT_EQ(glm::length(p.d2), 0.0);
      }
    }
  }
}

// All derivatives of the span polynomial against the derivative curve of docs/math.md §10.1 applied
// repeatedly (control points (k−1)(P_{i+1}−P_i)/(t_{i+k}−t_{i+1}), knots t_1..t_{n+k−1}).
TEST(BSplineCurve, HigherDerivativesMatchDerivativeCurves) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int order = 2; order <= kMaxBasisCount; ++order) {
    const int count = order + 3;
    BSplineCurveData c{order, randomKnots(rng, order, count, true, false), randomPoints(rng, count), {}};
    std::vector<BSplineCurveData> chain = {c};
    for (int d = 1; d < order; ++d) {
      const auto& prev = chain.back();
      BSplineCurveData next;
      next.order = prev.order - 1;
      next.knots.assign(prev.knots.begin() + 1, prev.knots.end() - 1);
      for (size_t i = 0; i + 1 < prev.points.size(); ++i) {
        const double den = prev.knots[i + prev.order] - prev.knots[i + 1];
        next.points.push_back(den > 0 ? (prev.order - 1.0) * (prev.points[i + 1] - prev.points[i]) / den
                                      : glm::dvec3(0.0));
      }
      chain.push_back(std::move(next));
    }
    const double a = c.knots[order - 1], b = c.knots[count];
    for (int q = 0; q < 10; ++q) {
      const double x = a + (b - a) * unit(rng);
      const int span = findKnotSpan(order, c.knots, count, x);
      glm::dvec3 d[kMaxBasisCount];
      evalBSplineCurveOnSpan(c, span, x, order - 1, d);
      for (int r = 0; r < order; ++r) {
        // The order-(k−r) derivative curve's span index is span − r (its knots start at t_r).
        const auto& dc = chain[static_cast<size_t>(r)];
        glm::dvec3 ref[kMaxBasisCount];
        evalBSplineCurveOnSpan(dc, span - r, x, 0, ref);
        EXPECT_LT(glm::length(d[r] - ref[0]), 1e-11 * (1 + glm::length(ref[0])))
            << "order " << order << " derivative " << r;
      }
    }
  }
}

TEST(BSplineSurface, IsTheTensorProductOfCurves) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int ku = 2; ku <= 5; ++ku)
    for (int kv = 2; kv <= 5; ++kv) {
      BSplineSurfaceData s;
      s.orderU = ku, s.orderV = kv;
      s.rows = ku + 2, s.cols = kv + 3;
      s.knotsU = randomKnots(rng, ku, s.rows, true, false);
      s.knotsV = randomKnots(rng, kv, s.cols, false, false);
      s.points = randomPoints(rng, s.rows * s.cols);
      for (int q = 0; q < 10; ++q) {
        const double u = s.knotsU[ku - 1] + (s.knotsU[s.rows] - s.knotsU[ku - 1]) * unit(rng);
        const double v = s.knotsV[kv - 1] + (s.knotsV[s.cols] - s.knotsV[kv - 1]) * unit(rng);
        // Rows evaluated in v give a u-curve (and its v-derivative curves).
        BSplineCurveData c0{ku, s.knotsU, {}, {}}, c1{ku, s.knotsU, {}, {}}, c2{ku, s.knotsU, {}, {}};
        for (int i = 0; i < s.rows; ++i) {
          BSplineCurveData row{kv, s.knotsV, {s.points.begin() + i * s.cols, s.points.begin() + (i + 1) * s.cols}, {}};
          const auto p = evalBSplineCurve(row, v);
          c0.points.push_back(p.point), c1.points.push_back(p.d1), c2.points.push_back(p.d2);
        }
        const auto p = evalBSplineSurface(s, u, v);
        const auto e0 = evalBSplineCurve(c0, u), e1 = evalBSplineCurve(c1, u), e2 = evalBSplineCurve(c2, u);
        const auto near = [](glm::dvec3 x, glm::dvec3 y) { return glm::length(x - y) <= 1e-11 * (1 + glm::length(y)); };
        EXPECT_TRUE(near(p.point, e0.point));
        EXPECT_TRUE(near(p.du, e0.d1));
        EXPECT_TRUE(near(p.duu, e0.d2));
        EXPECT_TRUE(near(p.dv, e1.point));
        EXPECT_TRUE(near(p.duv, e1.d1));
        EXPECT_TRUE(near(p.dvv, e2.point));
      }
    }
}

TEST(BSplineModel, ConvertsAndRejects) {
  CurveModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 4;
  m.points = {{0, 0, 0}, {1, 2, 0}, {3, 3, 0}, {5, 1, 0}, {6, 4, 0}, {8, 3, 0}};
  m.knots = {0, 0, 0, 0, 0.25, 0.5, 1, 1, 1, 1};
  const BSplineCurveData c = bsplineCurveFromModel(m);
  EXPECT_EQ(c.order, 4);
  EXPECT_EQ(c.knots.size(), 10u);
  m.knots.pop_back();
  EXPECT_THROW(bsplineCurveFromModel(m), ModelError);
  m.knots = {0, 0, 0, 0, 0.5, 0.25, 1, 1, 1, 1};
  EXPECT_THROW(bsplineCurveFromModel(m), ModelError);
  m.knots = {0, 0, 0, 0, 0, 0.5, 1, 1, 1, 1};  // multiplicity 5 > order
  EXPECT_THROW(bsplineCurveFromModel(m), ModelError);
}

}  // namespace
}  // namespace shapespline
