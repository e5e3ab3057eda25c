// core/point_math.h, the per-point formulas shared by the CPU core and every GLSL kernel, checked
// against references that do not use them: the properties of S(t) from docs/math.md §3, the
// [XW] form of its middle piece, derivatives against finite differences, the α-EB blends at the α
// where they reduce to the base surface or to the SR patch, and the §5.3 degeneracy thresholds.
#include "support/tolerances.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

#include <shapespline/core/point_math.h>

namespace shapespline {
namespace {

using glm::dvec3;

constexpr double kEps = std::numeric_limits<double>::epsilon();
using test::kFdRel;  // finite differences (support/tolerances.h)
using test::kFdStep;
// Interior parameters away from the S breakpoints 1/3, 2/3 by more than the step.
const double kInteriorT[] = {0.1, 0.3, 0.45, 0.6, 0.71, 0.93};

double fd(double (*f)(double), double t) { return (f(t + kFdStep) - f(t - kFdStep)) / (2 * kFdStep); }
double S(double t) { return pm::singularBlend(t).x; }
double dS(double t) { return pm::singularBlend(t).y; }

TEST(PointMath, SingularBlendEndValuesAndSymmetry) {
  const dvec3 s0 = pm::singularBlend(0.0), s1 = pm::singularBlend(1.0);
  EXPECT_EQ(s0, dvec3(0.0));
  EXPECT_EQ(s1.x, 1.0);
  EXPECT_EQ(s1.y, 0.0);
  EXPECT_EQ(s1.z, 0.0);
  for (double t : {0.05, 0.2, 1.0 / 3.0, 0.4, 0.5, 0.62}) {
    const dvec3 a = pm::singularBlend(t), b = pm::singularBlend(1.0 - t);
    EXPECT_NEAR(a.x + b.x, 1.0, 4 * kEps) << "S(t) + S(1-t), t = " << t;
    EXPECT_NEAR(a.y, b.y, 64 * kEps) << "S' even about 1/2, t = " << t;
    EXPECT_NEAR(a.z, -b.z, 64 * kEps) << "S'' odd about 1/2, t = " << t;
  }
}

TEST(PointMath, SingularBlendPiecesAreTheXuWangCubics) {
  for (int k = 0; k <= 60; ++k) {
    const double t = k / 60.0;
    double ref;  // [XW] §3: 9/2 t^3, 9/2 [t^3 - 3 (t - 1/3)^3], 1 - 9/2 (1-t)^3
    if (t <= 1.0 / 3.0) ref = 4.5 * t * t * t;
    else if (t <= 2.0 / 3.0) ref = 4.5 * (t * t * t - 3 * std::pow(t - 1.0 / 3.0, 3));
    else ref = 1.0 - 4.5 * std::pow(1.0 - t, 3);
    EXPECT_NEAR(S(t), ref, 8 * kEps) << "t = " << t;
    if (k > 0) {
      EXPECT_GT(S(t), S((k - 1) / 60.0)) << "S rises strictly, t = " << t;
    }
  }
}

TEST(PointMath, SingularBlendDerivativesMatchFiniteDifferences) {
  for (double t : kInteriorT) {
    EXPECT_NEAR(pm::singularBlend(t).y, fd(S, t), kFdRel * 27) << "S', t = " << t;
    EXPECT_NEAR(pm::singularBlend(t).z, fd(dS, t), kFdRel * 54) << "S'', t = " << t;
  }
}

// C^2 at the joins: one-sided differences from each side give the same S' and S'' (to O(h)).
TEST(PointMath, SingularBlendJoinsAreC2) {
  const double h = 1e-6;
  for (double b : {1.0 / 3.0, 2.0 / 3.0}) {
    const dvec3 s = pm::singularBlend(b);
    EXPECT_NEAR((S(b) - S(b - h)) / h, s.y, 30 * h) << "S' from the left at " << b;
    EXPECT_NEAR((S(b + h) - S(b)) / h, s.y, 30 * h) << "S' from the right at " << b;
    EXPECT_NEAR((dS(b) - dS(b - h)) / h, s.z, 60 * h) << "S'' from the left at " << b;
    EXPECT_NEAR((dS(b + h) - dS(b)) / h, s.z, 60 * h) << "S'' from the right at " << b;
  }
}

TEST(PointMath, HornerStepGivesValueDerivativeAndHalfSecond) {
  const double c[4] = {2.0, -3.0, 5.0, 7.0};  // 2 - 3t + 5t^2 + 7t^3
  for (double t : {-1.5, 0.0, 0.25, 1.0, 3.0}) {
    double p = c[3], dp = 0.0, hp = 0.0;
    for (int d = 2; d >= 0; --d) pm::hornerStep(p, dp, hp, t, c[d]);
    EXPECT_NEAR(p, 2 - 3 * t + 5 * t * t + 7 * t * t * t, 1e-13 * 200);
    EXPECT_NEAR(dp, -3 + 10 * t + 21 * t * t, 1e-13 * 200);
    EXPECT_NEAR(2 * hp, 10 + 42 * t, 1e-13 * 200);
  }
}

TEST(PointMath, AlphaEBVertex) {
  const dvec3 p(1.0, -2.0, 0.5), node(0.75, -1.5, 0.25);
  EXPECT_EQ(pm::alphaEBVertex(p, node, 1.0), p) << "α = 1: V = P";
  const dvec3 half = pm::alphaEBVertex(p, node, 0.5);
  EXPECT_EQ(half, p + (p - node)) << "α = 1/2: V = 2P - node";
  // α below 1/DBL_MAX: the factor overflows, V must not (P = node gives P, not NaN).
  EXPECT_EQ(pm::alphaEBVertex(p, p, 1e-310), p);
  const dvec3 v = pm::alphaEBVertex(dvec3(0.0), dvec3(-1e-300, 0.0, 0.0), 1e-310);  // (1-α)/α overflows
  EXPECT_NEAR(v.x, 1e-300 / 1e-310, 1e-12 * 1e10);
  EXPECT_EQ(v.y, 0.0);
}

// α-EB curve span: α = 0 keeps C; α = 1 gives the SR segment L through V0, V1; and the derivatives
// follow from the point by finite differences.
TEST(PointMath, AlphaEBCurveBlend) {
  const dvec3 v0(0.0, 1.0, 2.0), v1(3.0, -1.0, 0.5);
  auto base = [](double t, dvec3& p, dvec3& d1, dvec3& d2) {
    p = dvec3(t * t * t, 1.0 - t, 2.0 * t * t);
    d1 = dvec3(3 * t * t, -1.0, 4.0 * t);
    d2 = dvec3(6 * t, 0.0, 4.0);
  };
  for (double t : kInteriorT) {
    dvec3 p, d1, d2;
    base(t, p, d1, d2);
    dvec3 q = p, q1 = d1, q2 = d2;
    pm::alphaEBBlendCurve(pm::singularBlend(t), v0, v1, 0.0, 0.0, q, q1, q2);
    EXPECT_EQ(q, p);
    EXPECT_EQ(q1, d1);
    EXPECT_EQ(q2, d2);
    q = p, q1 = d1, q2 = d2;
    pm::alphaEBBlendCurve(pm::singularBlend(t), v0, v1, 1.0, 1.0, q, q1, q2);
    const dvec3 s = pm::singularBlend(t);
    EXPECT_LT(glm::length(q - (v0 + s.x * (v1 - v0))), 1e-14);
    EXPECT_LT(glm::length(q1 - s.y * (v1 - v0)), 1e-13);
    EXPECT_LT(glm::length(q2 - s.z * (v1 - v0)), 1e-12);
    // Varying α: Q' and Q'' against central differences of Q and Q'.
    auto blended = [&](double x, int order) {
      dvec3 a, b, c;
      base(x, a, b, c);
      pm::alphaEBBlendCurve(pm::singularBlend(x), v0, v1, 0.3, 0.9, a, b, c);
      return order == 0 ? a : order == 1 ? b : c;
    };
    const dvec3 fd1 = (blended(t + kFdStep, 0) - blended(t - kFdStep, 0)) / (2 * kFdStep);
    const dvec3 fd2 = (blended(t + kFdStep, 1) - blended(t - kFdStep, 1)) / (2 * kFdStep);
    EXPECT_LT(glm::length(blended(t, 1) - fd1), kFdRel * 100) << "t = " << t;
    EXPECT_LT(glm::length(blended(t, 2) - fd2), kFdRel * 1000) << "t = " << t;
  }
}

TEST(PointMath, CornerWeightsFormAndFactoredFormAgree) {
  const double al[4] = {0.2, 0.5, 0.7, 1.0};
  const dvec3 V[4] = {dvec3(0, 0, 0), dvec3(0, 1, 0.5), dvec3(1, 0, -0.5), dvec3(1, 1, 2)};
  for (double u : {0.0, 0.2, 0.5, 0.8, 1.0})
    for (double v : {0.0, 0.3, 0.6, 1.0}) {
      const pm::BlendFactors fu = pm::blendFactors(pm::singularBlend(u)), fv = pm::blendFactors(pm::singularBlend(v));
      EXPECT_EQ(fu.f00 + fu.f01, 1.0) << "order 0 factors are a partition of unity";
      double a, a2;
      dvec3 L, L2;
      pm::cornerBlend(fu.f10, fu.f11, fv.f00, fv.f01, al, V, a, L);
      pm::cornerBlendV(pm::cornerBlendU(fu.f10, fu.f11, al, V), fv.f00, fv.f01, a2, L2);
      EXPECT_NEAR(a, a2, 16 * kEps * 4.5);
      EXPECT_LT(glm::length(L - L2), 16 * kEps * 4.5 * 3);
      // The value weights reproduce the bilinear SR patch.
      pm::cornerBlend(fu.f00, fu.f01, fv.f00, fv.f01, al, V, a, L);
      const double su = pm::singularBlend(u).x, sv = pm::singularBlend(v).x;
      const double ref = (1 - su) * ((1 - sv) * al[0] + sv * al[1]) + su * ((1 - sv) * al[2] + sv * al[3]);
      EXPECT_NEAR(a, ref, 8 * kEps);
    }
  double a;
  dvec3 L;
  pm::cornerBlend(1.0, 0.0, 0.0, 1.0, al, V, a, L);
  EXPECT_EQ(a, al[1]);
  EXPECT_EQ(L, V[1]);
}

// The α-EB patch blend on an analytic base surface: α = 0 keeps C, α = 1 gives L, and with mixed
// α every partial matches central differences of the next lower one.
struct Partials {
  dvec3 p, u, v, uu, uv, vv;
};
Partials baseSurface(double u, double v) {  // C = (u^3 + v, u v^2, u^2 + v^3)
  return {dvec3(u * u * u + v, u * v * v, u * u + v * v * v), dvec3(3 * u * u, v * v, 2 * u),
          dvec3(1, 2 * u * v, 3 * v * v),                      dvec3(6 * u, 0, 2),
          dvec3(0, 2 * v, 0),                                  dvec3(0, 2 * u, 6 * v)};
}
Partials blendedSurface(double u, double v, const double al[4]) {
  const dvec3 V[4] = {dvec3(0, 0, 1), dvec3(0, 1, 0.5), dvec3(1, 0, -0.5), dvec3(1, 1, 2)};
  Partials q = baseSurface(u, v);
  pm::alphaEBBlendPatch(pm::alphaEBWeights(pm::singularBlend(u), pm::singularBlend(v), al, V), q.p, q.u, q.v, q.uu,
                        q.uv, q.vv);
  return q;
}

TEST(PointMath, AlphaEBPatchBlend) {
  const double zero[4] = {0, 0, 0, 0}, one[4] = {1, 1, 1, 1}, mixed[4] = {0.2, 0.5, 0.7, 0.95};
  const Partials c = baseSurface(0.3, 0.6), q0 = blendedSurface(0.3, 0.6, zero);
  EXPECT_EQ(q0.p, c.p);
  EXPECT_EQ(q0.uv, c.uv);
  EXPECT_EQ(q0.vv, c.vv);
  const Partials q1 = blendedSurface(0.0, 1.0, one);
  EXPECT_LT(glm::length(q1.p - dvec3(0, 1, 0.5)), 1e-15) << "α = 1 at a corner: the vertex V";
  EXPECT_LT(glm::length(q1.u) + glm::length(q1.v), 1e-15) << "α = 1 at a corner: zero velocity";
  for (double u : kInteriorT)
    for (double v : {0.15, 0.55, 0.8}) {
      const Partials q = blendedSurface(u, v, mixed);
      const double h2 = 2 * kFdStep;
      const Partials up = blendedSurface(u + kFdStep, v, mixed), um = blendedSurface(u - kFdStep, v, mixed);
      const Partials vp = blendedSurface(u, v + kFdStep, mixed), vm = blendedSurface(u, v - kFdStep, mixed);
      EXPECT_LT(glm::length(q.u - (up.p - um.p) / h2), kFdRel * 100) << u << ", " << v;
      EXPECT_LT(glm::length(q.v - (vp.p - vm.p) / h2), kFdRel * 100) << u << ", " << v;
      EXPECT_LT(glm::length(q.uu - (up.u - um.u) / h2), kFdRel * 1000) << u << ", " << v;
      EXPECT_LT(glm::length(q.uv - (vp.u - vm.u) / h2), kFdRel * 1000) << u << ", " << v;
      EXPECT_LT(glm::length(q.vv - (vp.v - vm.v) / h2), kFdRel * 1000) << u << ", " << v;
    }
}

TEST(PointMath, NormalRulePieces) {
  const dvec3 x(1, 0, 0), y(0, 2, 0);
  auto degenerate = [](dvec3 a, dvec3 b) { return pm::degenerateCross(a, b, glm::cross(a, b)); };
  EXPECT_FALSE(degenerate(x, y));
  EXPECT_TRUE(degenerate(x, 3.0 * x));
  EXPECT_TRUE(degenerate(dvec3(0.0), y));
  EXPECT_TRUE(degenerate(x, dvec3(0.0)));
  // sin of the angle 1e-13 is below the 1e-12 threshold, 1e-11 above it.
  EXPECT_TRUE(degenerate(x, dvec3(1, 1e-13, 0)));
  EXPECT_FALSE(degenerate(x, dvec3(1, 1e-11, 0)));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(degenerate(x, dvec3(0, nan, 0)));
  EXPECT_TRUE(pm::degenerateCrossLength(x, y, inf));
  EXPECT_TRUE(pm::degenerateCrossLength(x, y, nan));

  EXPECT_EQ(pm::kNormalShift, std::ldexp(1.0, -12));
  EXPECT_EQ(pm::towardCentre(0.0), pm::kNormalShift);
  EXPECT_EQ(pm::towardCentre(1.0), 1.0 - pm::kNormalShift);
  EXPECT_EQ(pm::towardCentre(0.5), 0.5);
  EXPECT_EQ(pm::fixedAxisNormal(), dvec3(0, 0, 1));

  // Corner axes: with node = P they are s (V_neighbour - P); α of the neighbour scales the node term.
  const dvec3 P(1, 1, 0), vU(2, 1, 0), vV(1, 3, 0);
  dvec3 au, av;
  pm::alphaEBCornerAxes(P, P, vU, 0.4, vV, 0.9, -1.0, 1.0, au, av);
  EXPECT_EQ(au, -(vU - P));
  EXPECT_EQ(av, vV - P);
  pm::alphaEBCornerAxes(P, dvec3(1, 1, 1), vU, 0.5, vV, 1.0, 1.0, 1.0, au, av);
  EXPECT_EQ(au, vU - P + 0.5 * dvec3(0, 0, 1));
  EXPECT_EQ(av, vV - P);
}

}  // namespace
}  // namespace shapespline
