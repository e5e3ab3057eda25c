// Identity tests of core/curve.h: every family × degree/order × λ × open/closed. Each test checks a
// property that follows from docs/math.md independently of the implementation, so it fails if the
// evaluation, the span rule, the phantom/wrap rule or the derivative scaling breaks.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include <shapespline/core/curve.h>
#include <shapespline/core/singular_blend.h>
#include <shapespline/core/span_basis.h>
#include <shapespline/core/validate.h>
#include "support/tolerances.h"

namespace shapespline {
namespace {

using glm::dvec3;
using test::kFp64Rel;

using test::kFdRel;  // finite differences (support/tolerances.h)
using test::kFdStep;
// Interior local parameters (avoid the S breakpoints 1/3, 2/3 and the span ends).
const double kInteriorT[] = {0.1, 0.3, 0.5, 0.71, 0.93};
// Local parameters including the ends.
const double kAllT[] = {0.0, 0.125, 0.3, 0.5, 0.75, 1.0};

std::vector<dvec3> randomPoints(int n, unsigned seed, bool planar = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-4.0, 4.0);
  std::vector<dvec3> p(n);
  for (auto& x : p) x = dvec3(d(rng), d(rng), planar ? 0.0 : d(rng));
  return p;
}

double bboxDiagonal(const std::vector<dvec3>& pts) {
  dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

::testing::AssertionResult near(const dvec3& a, const dvec3& b, double tol, const std::string& what) {
  const double e = glm::length(a - b);
  if (e <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << what << ": |" << a.x << "," << a.y << "," << a.z << " - " << b.x << ","
                                       << b.y << "," << b.z << "| = " << e << " > " << tol;
}

// ---- Families -----------------------------------------------------------------------------------

struct FamilyCase {
  std::string name;
  FamilySpec family;
  bool c2 = true;            // C^2 at joints (uniform spans)
  bool linearPrecision = false;  // equally spaced collinear points give C(u) = P_0 + (u - 0) d
};

FamilySpec xuWang(int degree, double lambda) {
  FamilySpec f;
  f.construction = Construction::ExtendedBSpline;
  f.degree = degree;
  f.lambda = lambda;
  return f;
}

// An admissible GUBP half vector that is not a UBP vector for k >= 5: equal values inside each
// parity class, solving the parity sums of docs/math.md §9.
std::vector<double> gubpMu(int k) {
  const int h = k / 2;
  std::vector<double> mu(h + 1);
  if (k % 2 == 1) {
    std::fill(mu.begin(), mu.end(), 1.0 / (h + 1));
    return mu;
  }
  // Weights of the half entries in their parity sums (1, or 1/2 for the centre entry mu_h).
  double wEven = 0.0, wOdd = 0.0;
  for (int i = 0; i <= h; ++i) (i % 2 == 0 ? wEven : wOdd) += (i == h) ? 0.5 : 1.0;
  for (int i = 0; i <= h; ++i) mu[i] = 0.5 / (i % 2 == 0 ? wEven : wOdd);
  return mu;
}

std::vector<FamilyCase> plainFamilies() {
  std::vector<FamilyCase> out;
  for (int k = 4; k <= 6; ++k) {
    const double lmin = -k * (k - 2.0);
    for (double lambda : {lmin, lmin / 2, 0.0, 1.0})
      out.push_back({"ext" + std::to_string(k) + "_l" + std::to_string(static_cast<int>(lambda)), xuWang(k, lambda),
                     true, true});
  }
  for (double lambda : {-8.0, -3.0, 0.0, 2.5, 40.0}) {
    FamilySpec f;
    f.construction = Construction::GB;
    f.lambda = lambda;
    out.push_back({"gb_l" + std::to_string(static_cast<int>(lambda)), f, lambda == 0.0, lambda == 0.0});
  }
  for (int k = 3; k <= 10; ++k) {
    for (double lambda : {ubpLambdaMin(k), -1.0, 0.0, 1.0}) {
      FamilySpec f;
      f.construction = Construction::UBP;
      f.order = k;
      f.lambda = lambda;
      // Linear precision: order 3 has Σ_r r B_r(t) = 1/2 + (1+λ/2)t - (3λ/2)t² + λt³ (Appendix A),
      // linear only at λ = 0; higher orders keep it for every λ.
      out.push_back({"ubp" + std::to_string(k) + "_l" + std::to_string(static_cast<int>(lambda)), f, k > 3,
                     k > 3 || lambda == 0.0});
    }
    FamilySpec g;
    g.construction = Construction::GUBP;
    g.order = k;
    g.mu = gubpMu(k);
    out.push_back({"gubp" + std::to_string(k), g, k > 3, false});  // linear precision depends on μ
  }
  for (int k = 2; k <= 10; ++k) {
    FamilySpec f;
    f.construction = Construction::BSpline;
    f.order = k;
    out.push_back({"bspline" + std::to_string(k), f, k > 3, true});
  }
  return out;
}

CurveModel makeCurve(const FamilySpec& f, std::vector<dvec3> pts, bool closed) {
  CurveModel m;
  m.family = f;
  m.closed = closed;
  m.dimension = 3;
  m.points = std::move(pts);
  return m;
}

int minimumCount(const FamilySpec& f) {
  if (f.construction == Construction::ExtendedBSpline || f.construction == Construction::GB) return 4;
  return f.order;
}

// ---- Plain curves -------------------------------------------------------------------------------

struct PlainParam {
  FamilyCase fc;
  bool closed;
  friend void PrintTo(const PlainParam& p, std::ostream* os) { *os << p.fc.name << (p.closed ? " closed" : " open"); }
};

class PlainCurve : public ::testing::TestWithParam<PlainParam> {
 protected:
  Curve make(unsigned seed, int extra = 3) const {
    const auto& p = GetParam();
    const int n = std::max(minimumCount(p.fc.family), 3) + extra;
    return Curve::create(makeCurve(p.fc.family, randomPoints(n, seed), p.closed));
  }
};

TEST_P(PlainCurve, DerivativesMatchFiniteDifferences) {
  const Curve c = make(11);
  const double scale = bboxDiagonal(c.model().points);
  for (int j = c.spans().first; j <= c.spans().last; ++j) {
    for (double t : kInteriorT) {
      const CurvePoint p = c.evaluate(j, t);
      const CurvePoint a = c.evaluate(j, t - kFdStep), b = c.evaluate(j, t + kFdStep);
      const dvec3 fd1 = (b.point - a.point) / (2 * kFdStep), fd2 = (b.d1 - a.d1) / (2 * kFdStep);
      EXPECT_TRUE(near(p.d1, fd1, kFdRel * (scale + glm::length(p.d2)), "d1 span " + std::to_string(j)));
      EXPECT_TRUE(near(p.d2, fd2, kFdRel * (scale + glm::length(p.d2)) * 10, "d2 span " + std::to_string(j)));
    }
  }
}

TEST_P(PlainCurve, JointsAreContinuousToTheFamilysOrder) {
  const Curve c = make(12);
  const double tol = kFp64Rel * bboxDiagonal(c.model().points) * 100;
  const auto& fc = GetParam().fc;
  const int last = GetParam().closed ? c.spans().last : c.spans().last - 1;
  for (int j = c.spans().first; j <= last; ++j) {
    const int next = j == c.spans().last ? c.spans().first : j + 1;
    const CurvePoint l = c.evaluate(j, 1.0), r = c.evaluate(next, 0.0);
    EXPECT_TRUE(near(l.point, r.point, tol, "C0 at joint " + std::to_string(j)));
    if (fc.family.order == 2) continue;  // order-2 B-spline: polyline, C0 only
    EXPECT_TRUE(near(l.d1, r.d1, tol * 10, "C1 at joint " + std::to_string(j)));
    if (fc.c2) {
      EXPECT_TRUE(near(l.d2, r.d2, tol * 100, "C2 at joint " + std::to_string(j)));
    }
  }
}

TEST_P(PlainCurve, GlobalParameterAgreesWithSpans) {
  const Curve c = make(13);
  const auto [u0, u1] = c.parameterRange();
  EXPECT_EQ(u0, c.spans().first);
  EXPECT_EQ(u1, c.spans().last + 1);
  for (int j = c.spans().first; j <= c.spans().last; ++j) {
    for (double t : {0.0, 0.25, 0.5}) {
      const CurvePoint a = c.evaluate(j, t), b = c.evaluateAt(j + t);
      EXPECT_TRUE(near(a.point, b.point, 1e-15 * (1 + glm::length(a.point)) * 8, "point"));
      EXPECT_TRUE(near(a.d2, b.d2, 1e-13 * (1 + glm::length(a.d2)), "d2"));
    }
  }
  // The last point of the range is the end of the last span.
  EXPECT_TRUE(near(c.evaluateAt(u1).point, c.evaluate(c.spans().last, 1.0).point, 1e-14, "u max"));
}

TEST_P(PlainCurve, ClosedCurvesArePeriodic) {
  if (!GetParam().closed) return;  // property of closed curves only
  const Curve c = make(14);
  const auto [u0, u1] = c.parameterRange();
  EXPECT_EQ(u1 - u0, static_cast<double>(c.model().points.size()));
  const double tol = kFp64Rel * bboxDiagonal(c.model().points) * 100;
  const CurvePoint a = c.evaluateAt(u0), b = c.evaluateAt(u1);
  EXPECT_TRUE(near(a.point, b.point, tol, "point"));
  if (GetParam().fc.family.order != 2) {
    EXPECT_TRUE(near(a.d1, b.d1, tol * 10, "d1"));
  }
  if (GetParam().fc.c2) {
    EXPECT_TRUE(near(a.d2, b.d2, tol * 100, "d2"));
  }
  // A closed curve of N points is the open curve of the wrapped polygon: compare one span.
  std::vector<dvec3> wrapped = c.model().points;
  const int n = static_cast<int>(wrapped.size());
  for (int i = 0; i < c.basis().count; ++i) wrapped.push_back(c.model().points[i % n]);
  const Curve open = Curve::create(makeCurve(GetParam().fc.family, wrapped, false));
  for (double t : kAllT) {
    const int j = c.spans().last;  // span N-1 of the closed curve reads P_{N-1-c..} wrapped
    const int jOpen = j;           // same indices in the unwrapped polygon P_0..P_{N+m-1}
    if (jOpen < open.spans().first || jOpen > open.spans().last) continue;
    EXPECT_TRUE(near(c.evaluate(j, t).point, open.evaluate(jOpen, t).point, tol, "wrap"));
  }
}

TEST_P(PlainCurve, AffineInvariance) {
  const Curve c = make(15);
  const glm::dmat3 a(1.5, 0.25, -0.5, 0.1, 0.9, 0.3, -0.7, 0.2, 1.1);
  const dvec3 shift(3.0, -2.0, 0.5);
  std::vector<dvec3> moved = c.model().points;
  for (auto& p : moved) p = a * p + shift;
  const Curve m = Curve::create(makeCurve(GetParam().fc.family, moved, GetParam().closed));
  const double tol = kFp64Rel * bboxDiagonal(moved) * 100;
  for (int j = c.spans().first; j <= c.spans().last; ++j) {
    for (double t : kAllT) {
      const CurvePoint p = c.evaluate(j, t), q = m.evaluate(j, t);
      EXPECT_TRUE(near(q.point, a * p.point + shift, tol, "point"));
      EXPECT_TRUE(near(q.d1, a * p.d1, tol * 10, "d1"));
    }
  }
}

TEST_P(PlainCurve, CollinearPointsGiveTheLine) {
  // Equally spaced points on a line: every family keeps the curve on the line (partition of unity);
  // those with linear precision give C(u) = P_0 + (u - shift) d, where shift = 1 + c - m/2 puts the
  // centre of P_i's bell (N symmetric about m/2, docs/math.md §1) at u = i + shift: 0 for even m and
  // 1/2 for odd m.
  const auto& p = GetParam();
  const int n = minimumCount(p.fc.family) + 3;
  const dvec3 origin(1.0, -2.0, 0.5), dir(0.75, 0.5, -0.25);
  std::vector<dvec3> pts(n);
  for (int i = 0; i < n; ++i) pts[i] = origin + static_cast<double>(i) * dir;
  const Curve c = Curve::create(makeCurve(p.fc.family, pts, false));
  const double tol = kFp64Rel * bboxDiagonal(pts) * 10;
  const double shift = 1.0 + c.basis().centre - c.basis().count / 2.0;
  for (int j = c.spans().first; j <= c.spans().last; ++j) {
    for (double t : kAllT) {
      const CurvePoint q = c.evaluate(j, t);
      const dvec3 rel = q.point - origin;
      EXPECT_LE(glm::length(glm::cross(rel, dir)) / glm::length(dir), tol) << "off the line at span " << j;
      EXPECT_LE(glm::length(glm::cross(q.d1, dir)), tol * 10) << "tangent off the line";
      if (p.fc.linearPrecision) {
        EXPECT_TRUE(near(q.point, origin + (j + t - shift) * dir, tol, "linear precision"));
        EXPECT_TRUE(near(q.d1, dir, tol * 10, "linear precision d1"));
      }
    }
  }
}

TEST_P(PlainCurve, RejectsOutOfRange) {
  const Curve c = make(16);
  EXPECT_THROW(c.evaluate(c.spans().first - 1, 0.5), std::out_of_range);
  EXPECT_THROW(c.evaluate(c.spans().last + 1, 0.5), std::out_of_range);
  EXPECT_THROW(c.evaluate(c.spans().first, 1.5), std::out_of_range);
  EXPECT_THROW(c.evaluate(c.spans().first, -1e-9), std::out_of_range);
  EXPECT_THROW(c.evaluate(c.spans().first, std::numeric_limits<double>::quiet_NaN()), std::out_of_range);
  EXPECT_THROW(c.evaluateAt(c.parameterRange().second + 1e-9), std::out_of_range);
  EXPECT_THROW(c.evaluateAt(c.parameterRange().first - 1e-9), std::out_of_range);
  try {
    c.evaluate(c.spans().last + 1, 0.0);
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("[" + std::to_string(c.spans().first)), std::string::npos) << e.what();
  }
}

std::vector<PlainParam> plainParams() {
  std::vector<PlainParam> out;
  for (const auto& f : plainFamilies())
    for (bool closed : {false, true}) out.push_back({f, closed});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Families, PlainCurve, ::testing::ValuesIn(plainParams()),
                         [](const ::testing::TestParamInfo<PlainParam>& info) {
                           std::string s = info.param.fc.name + (info.param.closed ? "_closed" : "_open");
                           std::replace(s.begin(), s.end(), '-', 'm');
                           return s;
                         });

// ---- Spans of the C^1 families: the d2 jump -----------------------------------------------------

TEST(CurveJoints, GbSecondDerivativeJumpIsMinusLambdaTimesTangent) {
  // docs/math.md §7.1: C''(left) - C''(right) = -λ C' and C'(joint) = 6(P_{j+1} - P_{j-1})/(12+λ).
  for (double lambda : {-8.0, -3.0, 0.0, 2.5, 40.0}) {
    for (bool closed : {false, true}) {
      FamilySpec f;
      f.construction = Construction::GB;
      f.lambda = lambda;
      const Curve c = Curve::create(makeCurve(f, randomPoints(7, 21), closed));
      const auto& P = c.model().points;
      const int n = static_cast<int>(P.size());
      const double tol = kFp64Rel * bboxDiagonal(P) * 100;
      for (int j = c.spans().first; j < c.spans().last + (closed ? 1 : 0); ++j) {
        const int next = (j + 1) % n, joint = j + 1;  // joint at vertex j+1
        const CurvePoint l = c.evaluate(j, 1.0), r = c.evaluate(closed ? next : j + 1, 0.0);
        const dvec3 tangent = 6.0 * (P[(joint + 1) % n] - P[(joint - 1 + n) % n]) / (12.0 + lambda);
        EXPECT_TRUE(near(l.d1, tangent, tol, "C' at joint"));
        EXPECT_TRUE(near(r.d1, tangent, tol, "C' at joint"));
        EXPECT_TRUE(near(l.d2 - r.d2, -lambda * l.d1, tol * 10, "d2 jump λ=" + std::to_string(lambda)));
      }
    }
  }
}

TEST(CurveJoints, Order3UbpAndGubpSecondDerivativeJump) {
  // Order-3 UBP (docs/math.md §8.1, Appendix A): N'' jumps by (1-λ, -3(1+λ), 3(1+λ), -(1-λ)) at
  // x = 0..3, so at the joint u = J (vertex J): C''(right) - C''(left) =
  // (1-λ)(P_{J+1} - P_{J-2}) - 3(1+λ)(P_J - P_{J-1}). GUBP order 3 with half vector (μ0, 1-μ0) is
  // UBP with λ = 1 - 6 μ0 (λ_{0,3} = (1-λ)/6). The first derivative is continuous (C^1).
  for (double mu0 : {0.0, 1.0 / 6, 0.3, 0.5}) {
    for (bool gubp : {false, true}) {
      FamilySpec f;
      f.order = 3;
      const double lambda = 1.0 - 6.0 * mu0;
      if (gubp) {
        f.construction = Construction::GUBP;
        f.mu = {mu0, 1.0 - mu0};
      } else {
        f.construction = Construction::UBP;
        f.lambda = lambda;
      }
      const Curve c = Curve::create(makeCurve(f, randomPoints(8, 22), false));
      const auto& P = c.model().points;
      const double tol = kFp64Rel * bboxDiagonal(P) * 100;
      for (int j = c.spans().first; j < c.spans().last; ++j) {
        const int J = j + 1;
        const CurvePoint l = c.evaluate(j, 1.0), r = c.evaluate(j + 1, 0.0);
        EXPECT_TRUE(near(l.d1, r.d1, tol, "C1"));
        const dvec3 jump = (1 - lambda) * (P[J + 1] - P[J - 2]) - 3 * (1 + lambda) * (P[J] - P[J - 1]);
        EXPECT_TRUE(near(r.d2 - l.d2, jump, tol * 10, "d2 jump"));
        EXPECT_GT(glm::length(jump), 1e-3) << "test data must make the jump visible";
      }
    }
  }
}

// ---- Span knots ---------------------------------------------------------------------------------

TEST(CurveSpanKnots, DerivativesAreWithRespectToGlobalU) {
  for (Construction kind : {Construction::ExtendedBSpline, Construction::GB}) {
    for (bool closed : {false, true}) {
      FamilySpec f = kind == Construction::GB ? FamilySpec{Construction::GB, 0, 0, 3.5, {}} : xuWang(5, -4.0);
      CurveModel m = makeCurve(f, randomPoints(7, 31), closed);
      const int spans = closed ? 7 : 4;
      double k = -1.0;
      for (int s = 0; s <= spans; ++s) m.knots.push_back(k), k += 0.5 + 0.37 * s;  // non-uniform h
      const Curve c = Curve::create(m);
      const Curve uniform = Curve::create(makeCurve(f, m.points, closed));
      const double scale = bboxDiagonal(m.points);
      EXPECT_EQ(c.parameterRange().first, m.knots.front());
      EXPECT_EQ(c.parameterRange().second, m.knots.back());
      for (int j = c.spans().first; j <= c.spans().last; ++j) {
        const int s = j - c.spans().first;
        const double h = m.knots[s + 1] - m.knots[s];
        for (double t : kAllT) {
          // Same shape as the uniform curve; derivatives divided by h^r (docs/math.md §1).
          const CurvePoint a = c.evaluate(j, t), b = uniform.evaluate(j, t);
          EXPECT_TRUE(near(a.point, b.point, 1e-14 * scale * 10, "shape"));
          EXPECT_TRUE(near(a.d1 * h, b.d1, 1e-13 * scale * 10, "d1 h"));
          EXPECT_TRUE(near(a.d2 * h * h, b.d2, 1e-12 * scale * 10, "d2 h^2"));
          const CurvePoint g = c.evaluateAt(m.knots[s] + t * h);
          EXPECT_TRUE(near(g.point, a.point, 1e-13 * scale, "evaluateAt"));
          EXPECT_DOUBLE_EQ(c.parameterOf(j, t), m.knots[s] + t * h);
        }
        // Finite differences in u.
        const double u = m.knots[s] + 0.4 * h, du = kFdStep * h;
        const CurvePoint p = c.evaluateAt(u), l = c.evaluateAt(u - du), r = c.evaluateAt(u + du);
        EXPECT_TRUE(near(p.d1, (r.point - l.point) / (2 * du), kFdRel * (scale + glm::length(p.d1)), "fd d1"));
        EXPECT_TRUE(near(p.d2, (r.d1 - l.d1) / (2 * du), kFdRel * 10 * (scale + glm::length(p.d2)), "fd d2"));
      }
    }
  }
}

// ---- Knot-vector B-splines ----------------------------------------------------------------------

TEST(CurveKnotVector, EvaluatesOnTheKnotParameter) {
  for (int k = 2; k <= 6; ++k) {
    FamilySpec f;
    f.construction = Construction::BSpline;
    f.order = k;
    CurveModel m = makeCurve(f, randomPoints(k + 4, 41), false);
    const int n = static_cast<int>(m.points.size());
    for (int i = 0; i < k; ++i) m.knots.push_back(0.0);                  // clamped left
    for (int i = 1; i < n - k + 1; ++i) m.knots.push_back(0.2 * i + 0.05 * i * i);
    const double end = m.knots.back() + 0.5;
    for (int i = 0; i < k; ++i) m.knots.push_back(end);                  // clamped right
    ASSERT_EQ(static_cast<int>(m.knots.size()), n + k);
    const Curve c = Curve::create(m);
    ASSERT_TRUE(c.usesKnotVector());
    EXPECT_EQ(c.parameterRange().first, 0.0);
    EXPECT_EQ(c.parameterRange().second, end);
    const double scale = bboxDiagonal(m.points);
    // Clamped ends interpolate the end points.
    EXPECT_TRUE(near(c.evaluateAt(0.0).point, m.points.front(), 1e-14 * scale * 10, "start"));
    EXPECT_TRUE(near(c.evaluateAt(end).point, m.points.back(), 1e-14 * scale * 10, "end"));
    for (int j = c.spans().first; j <= c.spans().last; ++j) {
      const double a = m.knots[j], b = m.knots[j + 1];
      if (!(b > a)) {
        EXPECT_THROW(c.evaluate(j, 0.5), std::out_of_range);
        continue;
      }
      const double u = a + 0.45 * (b - a), du = kFdStep * (b - a);
      const CurvePoint p = c.evaluate(j, 0.45), q = c.evaluateAt(u);
      EXPECT_TRUE(near(p.point, q.point, 1e-14 * scale * 10, "evaluate vs evaluateAt"));
      const CurvePoint l = c.evaluateAt(u - du), r = c.evaluateAt(u + du);
      EXPECT_TRUE(near(p.d1, (r.point - l.point) / (2 * du), kFdRel * (scale + glm::length(p.d2)), "fd d1"));
      if (k > 2) {
        EXPECT_TRUE(near(p.d2, (r.d1 - l.d1) / (2 * du), kFdRel * 10 * (scale + glm::length(p.d2) * 10), "fd d2"));
      }
    }
    EXPECT_THROW(c.evaluateAt(end + 1e-9), std::out_of_range);
  }
}

// ---- α-EB curves --------------------------------------------------------------------------------

struct AlphaParam {
  int degree;
  double lambda;
  bool closed;
  int count;
  friend void PrintTo(const AlphaParam& p, std::ostream* os) {
    *os << "k=" << p.degree << " λ=" << p.lambda << (p.closed ? " closed" : " open") << " N=" << p.count;
  }
};

class AlphaCurve : public ::testing::TestWithParam<AlphaParam> {
 protected:
  // Random α in (0,1] with some vertices at exactly 1 (zero velocity) and one small value.
  Curve make(unsigned seed) {
    const auto& p = GetParam();
    CurveModel m = makeCurve(xuWang(p.degree, p.lambda), randomPoints(p.count, seed), p.closed);
    m.family.construction = Construction::AlphaEB;
    std::mt19937 rng(seed + 1000);
    std::uniform_real_distribution<double> d(0.05, 1.0);
    for (int i = 0; i < p.count; ++i) m.alpha.push_back(i % 4 == 2 ? 1.0 : i % 5 == 1 ? 1.0 / 32 : d(rng));
    alphaMin_ = *std::min_element(m.alpha.begin(), m.alpha.end());
    scale_ = bboxDiagonal(m.points);
    return Curve::create(m);
  }
  double tol() const { return kFp64Rel * scale_ / alphaMin_ * 10; }
  double alphaMin_ = 1.0, scale_ = 1.0;
};

TEST_P(AlphaCurve, InterpolatesEveryVertex) {
  const Curve c = make(51);
  const auto& P = c.model().points;
  const int n = static_cast<int>(P.size());
  EXPECT_EQ(c.spans().first, 0);
  EXPECT_EQ(c.spans().last, GetParam().closed ? n - 1 : n - 2);
  for (int j = c.spans().first; j <= c.spans().last; ++j) {
    EXPECT_TRUE(near(c.evaluate(j, 0.0).point, P[j], tol(), "Q_j(0) = P_j, j=" + std::to_string(j)));
    EXPECT_TRUE(near(c.evaluate(j, 1.0).point, P[(j + 1) % n], tol(), "Q_j(1) = P_j+1"));
    EXPECT_TRUE(near(c.evaluateAt(j).point, P[j], tol(), "C(j) = P_j"));
  }
  if (!GetParam().closed) {
    EXPECT_TRUE(near(c.alphaV().front(), P.front(), tol(), "V_0 = P_0"));
    EXPECT_TRUE(near(c.alphaV().back(), P.back(), tol(), "V_N-1 = P_N-1"));
  }
}

TEST_P(AlphaCurve, JointsAreC2AndMatchTheClosedForms) {
  // docs/math.md §4.3: at vertex j, Q' = (1-α_j)(P_{j+1} - P_{j-1})/2 and
  // Q'' = (1-α_j)((k+λ-2)/2)(P_{j-1} - 2P_j + P_{j+1}) from both sides (extended polygon).
  const Curve c = make(52);
  const auto& E = c.extendedPoints();  // E[i] = P_{i-1}
  const int n = static_cast<int>(c.model().points.size());
  const double k = GetParam().degree, lambda = GetParam().lambda;
  for (int j = 0; j < n; ++j) {
    const double a = c.alphas()[j];
    const dvec3 pm = E[j], p0 = E[j + 1], pp = E[j + 2];
    const dvec3 d1 = (1 - a) * (pp - pm) / 2.0;
    const dvec3 d2 = (1 - a) * ((k + lambda - 2) / 2) * (pm - 2.0 * p0 + pp);
    const double d2Scale = std::max(1.0, std::abs(k + lambda - 2));
    const bool hasRight = j <= c.spans().last, hasLeft = GetParam().closed || j >= 1;
    if (hasRight) {
      const CurvePoint r = c.evaluate(j, 0.0);
      EXPECT_TRUE(near(r.d1, d1, tol(), "right d1 at " + std::to_string(j)));
      EXPECT_TRUE(near(r.d2, d2, tol() * 10 * d2Scale, "right d2 at " + std::to_string(j)));
    }
    if (hasLeft) {
      const int left = (j - 1 + n) % n;
      const CurvePoint l = c.evaluate(left, 1.0);
      EXPECT_TRUE(near(l.d1, d1, tol(), "left d1 at " + std::to_string(j)));
      EXPECT_TRUE(near(l.d2, d2, tol() * 10 * d2Scale, "left d2 at " + std::to_string(j)));
    }
  }
}

TEST_P(AlphaCurve, DerivativesMatchFiniteDifferences) {
  const Curve c = make(53);
  const double s = scale_ / alphaMin_;
  for (int j = c.spans().first; j <= c.spans().last; ++j) {
    for (double t : kInteriorT) {
      const CurvePoint p = c.evaluate(j, t), a = c.evaluate(j, t - kFdStep), b = c.evaluate(j, t + kFdStep);
      EXPECT_TRUE(near(p.d1, (b.point - a.point) / (2 * kFdStep), kFdRel * (s + glm::length(p.d2)), "fd d1"));
      EXPECT_TRUE(near(p.d2, (b.d1 - a.d1) / (2 * kFdStep), kFdRel * 100 * (s + glm::length(p.d2)), "fd d2"));
    }
  }
}

TEST_P(AlphaCurve, NodesAndVMatchTheirDefinitions) {
  // node_j = [(k-λ)P_{j-1} + 2(k(k-2)+λ)P_j + (k-λ)P_{j+1}] / D_k (docs/math.md §2.3/§4.2), V_j from it;
  // the extended polygon follows the phantom rule (open) or the wrap (closed).
  const Curve c = make(54);
  const auto& P = c.model().points;
  const int n = static_cast<int>(P.size());
  const auto& E = c.extendedPoints();
  const double k = GetParam().degree, lambda = GetParam().lambda, D = 2 * k * (k - 1);
  if (GetParam().closed) {
    ASSERT_EQ(static_cast<int>(E.size()), n + 3);
    for (int i = 0; i < n + 3; ++i) EXPECT_EQ(E[i], P[(i - 1 + n) % n]) << i;
  } else {
    ASSERT_EQ(static_cast<int>(E.size()), n + 2);
    EXPECT_TRUE(near(E[0], 2.0 * P[0] - P[1], 0.0, "phantom P_-1"));
    EXPECT_TRUE(near(E[n + 1], 2.0 * P[n - 1] - P[n - 2], 0.0, "phantom P_N"));
  }
  for (int j = 0; j < n; ++j) {
    const dvec3 node = ((k - lambda) * E[j] + 2 * (k * (k - 2) + lambda) * E[j + 1] + (k - lambda) * E[j + 2]) / D;
    EXPECT_TRUE(near(c.alphaNodes()[j], node, kFp64Rel * scale_, "node"));
    const double a = c.alphas()[j];
    EXPECT_TRUE(near(c.alphaV()[j], P[j] + ((1 - a) / a) * (P[j] - node), tol(), "V"));
  }
}

TEST_P(AlphaCurve, ClosedCurvesArePeriodic) {
  if (!GetParam().closed) return;  // property of closed curves only
  const Curve c = make(55);
  const auto [u0, u1] = c.parameterRange();
  const CurvePoint a = c.evaluateAt(u0), b = c.evaluateAt(u1);
  EXPECT_TRUE(near(a.point, b.point, tol(), "point"));
  EXPECT_TRUE(near(a.d1, b.d1, tol(), "d1"));
  EXPECT_TRUE(near(a.d2, b.d2, tol() * 100, "d2"));
}

TEST_P(AlphaCurve, AlphaOneGivesZeroVelocityAndSmallAlphaItsLimit) {
  const auto& p = GetParam();
  CurveModel m = makeCurve(xuWang(p.degree, p.lambda), randomPoints(p.count, 56), p.closed);
  m.family.construction = Construction::AlphaEB;
  m.alpha.assign(p.count, 1.0);
  const Curve one = Curve::create(m);
  for (int j = one.spans().first; j <= one.spans().last; ++j)
    EXPECT_EQ(glm::length(one.evaluate(j, 0.0).d1), 0.0) << "α = 1: zero velocity at P_j";
  // Uniform tiny α: a = α and α V_j -> P_j - node_j, so Q_j(t) -> C_j(t) + (1-S)(P_j - node_j)
  // + S (P_{j+1} - node_{j+1}) with an O(α) error (§4.2). (The limit still interpolates: the
  // remark in docs/math.md R13 that it tends to the non-interpolating base curve does not hold.)
  m.alpha.assign(p.count, 1e-6);
  const Curve small = Curve::create(m);
  const SpanBasis basis = xuWangSpanBasis(p.degree, p.lambda);
  const int n = p.count;
  for (int j = small.spans().first; j <= small.spans().last; ++j) {
    for (double t : kInteriorT) {
      CurvePoint base;
      evalLocalSpan(basis, &small.extendedPoints()[j], t, 1.0, base);
      const double s = singularBlend(t).s;
      const int j1 = (j + 1) % n;
      const dvec3 limit = base.point + (1 - s) * (m.points[j] - small.alphaNodes()[j]) +
                          s * (m.points[j1] - small.alphaNodes()[j1]);
      EXPECT_TRUE(near(small.evaluate(j, t).point, limit, 1e-5 * scale_, "α → 0 limit"));
    }
  }
}

std::vector<AlphaParam> alphaParams() {
  std::vector<AlphaParam> out;
  for (int k = 4; k <= 6; ++k) {
    const double lmin = -k * (k - 2.0);
    for (double lambda : {lmin, lmin / 3, 0.0, 0.5, 1.0})
      for (bool closed : {false, true}) out.push_back({k, lambda, closed, closed ? 7 : 8});
  }
  out.push_back({4, 0.0, false, 2});  // the smallest open polygon
  out.push_back({5, -3.0, true, 3});  // the smallest closed polygon
  return out;
}

INSTANTIATE_TEST_SUITE_P(DegreeLambda, AlphaCurve, ::testing::ValuesIn(alphaParams()),
                         [](const ::testing::TestParamInfo<AlphaParam>& info) {
                           std::string s = "k" + std::to_string(info.param.degree) + "_l" +
                                           std::to_string(static_cast<int>(info.param.lambda * 10)) +
                                           (info.param.closed ? "_closed" : "_open") + "_n" +
                                           std::to_string(info.param.count);
                           std::replace(s.begin(), s.end(), '-', 'm');
                           return s;
                         });

TEST(CurveCreate, ValidatesTheModel) {
  CurveModel m = makeCurve(xuWang(4, 0.0), randomPoints(5, 61), false);
  m.family.construction = Construction::AlphaEB;
  m.alpha.assign(5, 0.0);  // α = 0 makes V undefined (docs/math.md §11)
  EXPECT_THROW(Curve::create(m), ModelError);
  CurveModel bad = makeCurve(xuWang(4, 2.0), randomPoints(5, 62), false);  // λ > 1
  EXPECT_THROW(Curve::create(bad), ModelError);
}

}  // namespace
}  // namespace shapespline
