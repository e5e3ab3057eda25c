// Per-point spline math, written once and compiled twice: as C++ (namespace shapespline::pm, fp64,
// GLM types; included as <shapespline/core/point_math.h>) and as GLSL (included as "point_math.h"
// after common.glsl, REAL = float or double). The model is OpenSubdiv's osd/patchBasis.h: the text
// is the common subset of the two languages (GLM spells vec3, cross, length, mix, all, equal as GLSL
// does), and these macros cover the rest:
//   PM_FN              C++ `inline`, GLSL nothing
//   PM_OUT(T)          C++ `T&`, GLSL `out T`           (an out-parameter)
//   PM_INOUT(T)        C++ `T&`, GLSL `inout T`         (updated in place)
//   PM_IN4(T, name)    C++ `const T name[4]`, GLSL `in T name[4]` (the four patch corners)
//   PM_CONST(T, n, v)  C++ `inline constexpr T n = v`, GLSL `const T n = v`
//   PM_ROW_IN(name), PM_TABLE_IN(name), PM_TABLE_OUT(name)
//                      a REAL[kMaxBasis] row and a REAL[kMaxBasis][kMaxBasis] table as parameters
//                      (C++ pointers, GLSL in / out arrays; kMaxBasis is layout.h's in GLSL)
// REAL / REAL3 are double / glm::dvec3 in C++. Selects (mix with a bvec) instead of branches:
// llvmpipe runs both sides of a per-lane branch, and a select gives the same bits as the branch.
//
// Only per-point formulas live here (no loops over buffers, no bindings); the CPU core and every
// kernel keep their own loop shapes around them. Not a public header: host/core and shaders/ only.
#ifndef SHAPESPLINE_CORE_POINT_MATH_H
#define SHAPESPLINE_CORE_POINT_MATH_H

#ifdef SHAPESPLINE_GLSL
#define PM_FN
#define PM_OUT(T) out T
#define PM_INOUT(T) inout T
#define PM_IN4(T, name) in T name[4]
#define PM_CONST(T, name, value) const T name = value
#define PM_ROW_IN(name) in REAL name[kMaxBasis]
#define PM_TABLE_IN(name) in REAL name[kMaxBasis][kMaxBasis]
#define PM_TABLE_OUT(name) out REAL name[kMaxBasis][kMaxBasis]
#else
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vector_relational.hpp>

namespace shapespline::pm {
using REAL = double;
using REAL3 = glm::dvec3;
using glm::all;
using glm::any;
using glm::bvec3;
using glm::cross;
using glm::equal;
using glm::isinf;
using glm::length;
using glm::mix;
#define PM_FN inline
#define PM_OUT(T) T&
#define PM_INOUT(T) T&
#define PM_IN4(T, name) const T name[4]
#define PM_CONST(T, name, value) inline constexpr T name = value
#define PM_ROW_IN(name) const REAL name[kMaxBasis]
#define PM_TABLE_IN(name) const REAL name[kMaxBasis][kMaxBasis]
#define PM_TABLE_OUT(name) REAL name[kMaxBasis][kMaxBasis]
inline constexpr int kMaxBasis = 10;  // basis functions per span (core kMaxBasisCount, layout.h kMaxBasis)
#endif

// ---- S(t), docs/math.md §3 ----------------------------------------------------------------------

// (S, S', S'') of the singular blending function: piecewise cubic on the thirds of [0,1]; at a
// breakpoint the left piece.
PM_FN REAL3 singularBlend(REAL t) {
  REAL3 lo = REAL3(REAL(4.5) * t * t * t, REAL(13.5) * t * t, REAL(27) * t);
  REAL3 mid = REAL3(REAL(0.5) + t * (REAL(-4.5) + t * (REAL(13.5) - REAL(9) * t)),
                    REAL(-4.5) + t * (REAL(27) - REAL(27) * t), REAL(27) - REAL(54) * t);
  REAL u = REAL(1) - t;
  REAL3 hi = REAL3(REAL(1) - REAL(4.5) * u * u * u, REAL(13.5) * u * u, REAL(-27) * u);
  return mix(mix(hi, mid, bvec3(t <= REAL(2.0 / 3.0))), lo, bvec3(t <= REAL(1.0 / 3.0)));
}

// The u- (or v-) factor pairs of the SR bilinear weights (docs/math.md §5.3) from s = (S, S', S''):
// order 0 (1-S, S), order r >= 1 (-S^(r), S^(r)).
struct BlendFactors {
  REAL f00, f01, f10, f11, f20, f21;  // f<order><corner side>
};
PM_FN BlendFactors blendFactors(REAL3 s) {
  BlendFactors f;
  f.f00 = REAL(1) - s.x;
  f.f01 = s.x;
  f.f10 = -s.y;
  f.f11 = s.y;
  f.f20 = -s.z;
  f.f21 = s.z;
  return f;
}

// ---- Span bases from coefficient matrices, docs/math.md §1 --------------------------------------

// One step of the simultaneous Horner pass for a polynomial, its derivative and half its second
// derivative at t, taking in the next lower coefficient c (start: p = top coefficient, dp = hp = 0).
PM_FN void hornerStep(PM_INOUT(REAL) p, PM_INOUT(REAL) dp, PM_INOUT(REAL) hp, REAL t, REAL c) {
  hp = hp * t + dp;
  dp = dp * t + p;
  p = p * t + c;
}
// The same for a vector polynomial (a span or a patch row in the power basis).
PM_FN void hornerStep(PM_INOUT(REAL3) p, PM_INOUT(REAL3) dp, PM_INOUT(REAL3) hp, REAL t, REAL3 c) {
  hp = hp * t + dp;
  dp = dp * t + p;
  p = p * t + c;
}

// s_k += b_k P for k = 0, 1, 2: a point's contribution to a value and two derivatives.
PM_FN void accumulate3(PM_INOUT(REAL3) s0, PM_INOUT(REAL3) s1, PM_INOUT(REAL3) s2, REAL b0, REAL b1, REAL b2,
                       REAL3 P) {
  s0 += b0 * P;
  s1 += b1 * P;
  s2 += b2 * P;
}
// The same for a scalar (a rational net's weight).
PM_FN void accumulate3(PM_INOUT(REAL) s0, PM_INOUT(REAL) s1, PM_INOUT(REAL) s2, REAL b0, REAL b1, REAL b2, REAL w) {
  s0 += b0 * w;
  s1 += b1 * w;
  s2 += b2 * w;
}

// Row r of a tensor patch (docs/math.md §6): the row contracted along v gives s0 = Σ_s B_s P, s1 with
// B_s', s2 with B_s''; weighted with B_r, B_r', B_r'' (bu, du, ddu) it adds to the six partials.
// The point and first partials alone (the list kernel).
PM_FN void accumulateTensorRowFirst(PM_INOUT(REAL3) p, PM_INOUT(REAL3) u, PM_INOUT(REAL3) v, REAL bu, REAL du,
                                    REAL3 s0, REAL3 s1) {
  p += bu * s0;
  u += du * s0;
  v += bu * s1;
}
PM_FN void accumulateTensorRow(PM_INOUT(REAL3) p, PM_INOUT(REAL3) u, PM_INOUT(REAL3) v, PM_INOUT(REAL3) uu,
                               PM_INOUT(REAL3) uv, PM_INOUT(REAL3) vv, REAL bu, REAL du, REAL ddu, REAL3 s0,
                               REAL3 s1, REAL3 s2) {
  accumulateTensorRowFirst(p, u, v, bu, du, s0, s1);
  uu += ddu * s0;
  uv += du * s1;
  vv += bu * s2;
}

// ---- Rational B-splines (NURBS), docs/math.md §10.8 (The NURBS Book §4.3, §4.5) ----------------

// A curve's homogeneous sums A = Σ N w P, A', A'' (in c0, c1, c2) and W = Σ N w, W', W'' become the
// point and its derivatives: C = A / W, C' = (A' - W' C) / W, C'' = (A'' - 2 W' C' - W'' C) / W.
// One reciprocal instead of three vector divisions (the divisions were most of a rational sample's
// cost).
// The point alone (the list kernel, core/list_eval.h): C = A / W; returns 1 / W.
PM_FN REAL rationalPoint(PM_INOUT(REAL3) c0, REAL w0) {
  REAL r = REAL(1) / w0;
  c0 = c0 * r;
  return r;
}
// C and C' alone; returns 1 / W.
PM_FN REAL rationalCurveFirst(PM_INOUT(REAL3) c0, PM_INOUT(REAL3) c1, REAL w0, REAL w1) {
  REAL r = rationalPoint(c0, w0);
  c1 = (c1 - w1 * c0) * r;
  return r;
}
PM_FN void rationalCurve(PM_INOUT(REAL3) c0, PM_INOUT(REAL3) c1, PM_INOUT(REAL3) c2, REAL w0, REAL w1, REAL w2) {
  REAL r = rationalCurveFirst(c0, c1, w0, w1);
  c2 = (c2 - REAL(2) * w1 * c1 - w2 * c0) * r;
}

// S, S_u and S_v alone (the list kernel); returns 1 / W.
PM_FN REAL rationalSurfaceFirst(PM_INOUT(REAL3) p, PM_INOUT(REAL3) u, PM_INOUT(REAL3) v, REAL w, REAL wu, REAL wv) {
  REAL r = rationalPoint(p, w);
  u = (u - wu * p) * r;
  v = (v - wv * p) * r;
  return r;
}
// The same for a surface's six homogeneous partials and those of W: S = A / W,
// S_u = (A_u - W_u S) / W (v likewise), S_uu = (A_uu - 2 W_u S_u - W_uu S) / W (vv likewise),
// S_uv = (A_uv - W_u S_v - W_v S_u - W_uv S) / W.
PM_FN void rationalSurface(PM_INOUT(REAL3) p, PM_INOUT(REAL3) u, PM_INOUT(REAL3) v, PM_INOUT(REAL3) uu,
                           PM_INOUT(REAL3) uv, PM_INOUT(REAL3) vv, REAL w, REAL wu, REAL wv, REAL wuu, REAL wuv,
                           REAL wvv) {
  REAL r = rationalSurfaceFirst(p, u, v, w, wu, wv);
  uu = (uu - REAL(2) * wu * u - wuu * p) * r;
  uv = (uv - wu * v - wv * u - wuv * p) * r;
  vv = (vv - REAL(2) * wv * v - wvv * p) * r;
}

// ---- α-EB, docs/math.md §4.2, §5.2, §5.3 --------------------------------------------------------

// V = P + ((1-α)/α)(P - node). Where the factor overflows (α below 1/REAL_MAX), d/α - d is the same
// value without the infinite intermediate (0 * inf would make V NaN where P = node).
PM_FN REAL3 alphaEBVertex(REAL3 p, REAL3 node, REAL alpha) {
  REAL3 d = p - node;
  REAL c = (REAL(1) - alpha) / alpha;
  return isinf(c) ? p + (d / alpha - d) : p + c * d;
}

// α-EB curve span (§4.2): (p, d1, d2) hold C, C', C'' and become Q, Q', Q''; s = (S, S', S'') at t,
// (v0, a0) and (v1, a1) the V and α of the span's two vertices.
PM_FN void alphaEBBlendCurve(REAL3 s, REAL3 v0, REAL3 v1, REAL a0, REAL a1, PM_INOUT(REAL3) p, PM_INOUT(REAL3) d1,
                             PM_INOUT(REAL3) d2) {
  REAL da = a1 - a0;
  REAL3 dv = v1 - v0;
  REAL a = a0 + s.x * da, a1d = s.y * da, a2d = s.z * da;
  REAL3 m = v0 + s.x * dv - p, m1 = s.y * dv - d1, m2 = s.z * dv - d2;
  d2 = d2 + a * m2 + REAL(2) * a1d * m1 + a2d * m;
  d1 = d1 + a * m1 + a1d * m;
  p = p + a * m;
}

// The bilinear corner sums of §5.2/§5.3 with corners (i,j), (i,j+1), (i+1,j), (i+1,j+1) in al/V:
// a = Σ_k w_k α_k and L = Σ_k w_k V_k, w = (fu0 fv0, fu0 fv1, fu1 fv0, fu1 fv1) for one pair of
// factor pairs. cornerBlend forms the four weights (one point); cornerBlendU / cornerBlendV give the
// same sum factored, the u half once per grid row and the v half per sample.
PM_FN void cornerBlend(REAL fu0, REAL fu1, REAL fv0, REAL fv1, PM_IN4(REAL, al), PM_IN4(REAL3, V), PM_OUT(REAL) a,
                       PM_OUT(REAL3) L) {
  REAL w00 = fu0 * fv0, w01 = fu0 * fv1, w10 = fu1 * fv0, w11 = fu1 * fv1;
  a = w00 * al[0] + w01 * al[1] + w10 * al[2] + w11 * al[3];
  L = w00 * V[0] + w01 * V[1] + w10 * V[2] + w11 * V[3];
}
struct CornerHalf {
  REAL a0, a1;    // α blended along u on the v = 0 side (corners 0, 2) and the v = 1 side (1, 3)
  REAL3 L0, L1;   // V likewise
};
PM_FN CornerHalf cornerBlendU(REAL fu0, REAL fu1, PM_IN4(REAL, al), PM_IN4(REAL3, V)) {
  CornerHalf h;
  h.a0 = fu0 * al[0] + fu1 * al[2];
  h.a1 = fu0 * al[1] + fu1 * al[3];
  h.L0 = fu0 * V[0] + fu1 * V[2];
  h.L1 = fu0 * V[1] + fu1 * V[3];
  return h;
}
PM_FN void cornerBlendV(CornerHalf h, REAL fv0, REAL fv1, PM_OUT(REAL) a, PM_OUT(REAL3) L) {
  a = fv0 * h.a0 + fv1 * h.a1;
  L = fv0 * h.L0 + fv1 * h.L1;
}

// a_rq and L_rq of §5.3 for the six derivative orders (r, q) up to 2.
struct AlphaEBWeights {
  REAL a00, a10, a01, a20, a11, a02;
  REAL3 L00, L10, L01, L20, L11, L02;
};
PM_FN AlphaEBWeights alphaEBWeightsZero() {
  AlphaEBWeights w;
  w.a00 = w.a10 = w.a01 = w.a20 = w.a11 = w.a02 = REAL(0);
  w.L00 = w.L10 = w.L01 = w.L20 = w.L11 = w.L02 = REAL3(0);
  return w;
}
// All six at one point from su = (S, S', S'')(u), sv likewise.
PM_FN AlphaEBWeights alphaEBWeights(REAL3 su, REAL3 sv, PM_IN4(REAL, al), PM_IN4(REAL3, V)) {
  BlendFactors fu = blendFactors(su), fv = blendFactors(sv);
  AlphaEBWeights w;
  cornerBlend(fu.f00, fu.f01, fv.f00, fv.f01, al, V, w.a00, w.L00);
  cornerBlend(fu.f10, fu.f11, fv.f00, fv.f01, al, V, w.a10, w.L10);
  cornerBlend(fu.f00, fu.f01, fv.f10, fv.f11, al, V, w.a01, w.L01);
  cornerBlend(fu.f20, fu.f21, fv.f00, fv.f01, al, V, w.a20, w.L20);
  cornerBlend(fu.f10, fu.f11, fv.f10, fv.f11, al, V, w.a11, w.L11);
  cornerBlend(fu.f00, fu.f01, fv.f20, fv.f21, al, V, w.a02, w.L02);
  return w;
}

// α-EB patch (§5.3), with M_rq = L_rq - C_rq: the base partials C, C_u, C_v in (p, u, v) become
// Q = C + aM, Q_u = C_u + aM_u + a_uM, Q_v likewise.
PM_FN void alphaEBBlendFirst(AlphaEBWeights w, PM_INOUT(REAL3) p, PM_INOUT(REAL3) u, PM_INOUT(REAL3) v) {
  REAL3 m = w.L00 - p, mu = w.L10 - u, mv = w.L01 - v;
  p = p + w.a00 * m;
  u = u + w.a00 * mu + w.a10 * m;
  v = v + w.a00 * mv + w.a01 * m;
}
// The second partials C_uu, C_uv, C_vv become Q_uu = C_uu + aM_uu + 2a_uM_u + a_uuM, Q_uv = C_uv +
// aM_uv + a_uM_v + a_vM_u + a_uvM, Q_vv likewise; p, u, v are the base C, C_u, C_v (call this first).
PM_FN void alphaEBBlendSecond(AlphaEBWeights w, REAL3 p, REAL3 u, REAL3 v, PM_INOUT(REAL3) uu, PM_INOUT(REAL3) uv,
                              PM_INOUT(REAL3) vv) {
  REAL3 m = w.L00 - p, mu = w.L10 - u, mv = w.L01 - v;
  REAL3 muu = w.L20 - uu, muv = w.L11 - uv, mvv = w.L02 - vv;
  uu = uu + w.a00 * muu + REAL(2) * w.a10 * mu + w.a20 * m;
  uv = uv + w.a00 * muv + w.a10 * mv + w.a01 * mu + w.a11 * m;
  vv = vv + w.a00 * mvv + REAL(2) * w.a01 * mv + w.a02 * m;
}
// All six partials (a kernel drops those that feed no output as dead code).
PM_FN void alphaEBBlendPatch(AlphaEBWeights w, PM_INOUT(REAL3) p, PM_INOUT(REAL3) u, PM_INOUT(REAL3) v,
                             PM_INOUT(REAL3) uu, PM_INOUT(REAL3) uv, PM_INOUT(REAL3) vv) {
  alphaEBBlendSecond(w, p, u, v, uu, uv, vv);
  alphaEBBlendFirst(w, p, u, v);
}

// ---- The normal rule, docs/math.md §5.3 (its order: core/surface.cpp evalWithNormal) ------------

PM_CONST(REAL, kNormalDegeneracy, REAL(1e-12));  // |a x b| < 1e-12 |a||b| is degenerate
PM_CONST(REAL, kNormalShift, REAL(1.0 / 4096.0));  // δ = 2^-12 towards the patch centre

// True when a x b (of length len) gives no direction: a partial exactly zero, |a x b| below the
// threshold, zero or not finite (!(>=) makes NaN degenerate). No short-circuit (a select in GLSL).
PM_FN bool degenerateCrossLength(REAL3 a, REAL3 b, REAL len) {
  bool zeroA = all(equal(a, REAL3(0))), zeroB = all(equal(b, REAL3(0)));
  bool small = !(len >= kNormalDegeneracy * length(a) * length(b)) || len == REAL(0) || isinf(len);
  return any(bvec3(zeroA, zeroB, small));
}
PM_FN bool degenerateCross(REAL3 a, REAL3 b, REAL3 n) { return degenerateCrossLength(a, b, length(n)); }

// The diagonal-limit axes at an α = 1 vertex P: s_u A_u and s_v A_v with A_u = V_u - P +
// (1 - α_u)(node - P), (V_u, α_u) of the vertex's neighbour along u inside the patch, s_u = +1 if the
// vertex is at local u = 0 and -1 at u = 1 (v likewise); the limit normal is their cross product.
PM_FN void alphaEBCornerAxes(REAL3 p, REAL3 node, REAL3 vU, REAL alphaU, REAL3 vV, REAL alphaV, REAL sU, REAL sV,
                             PM_OUT(REAL3) axisU, PM_OUT(REAL3) axisV) {
  axisU = sU * (vU - p + (REAL(1) - alphaU) * (node - p));
  axisV = sV * (vV - p + (REAL(1) - alphaV) * (node - p));
}

// A local parameter moved towards the patch centre by δ (1/2 stays).
PM_FN REAL towardCentre(REAL t) {
  return t < REAL(0.5) ? t + kNormalShift : (t > REAL(0.5) ? t - kNormalShift : t);
}

// The last resort of the rule: +z.
PM_FN REAL3 fixedAxisNormal() { return REAL3(0, 0, 1); }

// ---- Knot-vector B-spline basis, docs/math.md §10.1 (The NURBS Book A2.3) ----------------------

// The triangle of A2.3 for degree p from the knot differences left[j] = t - t_{span+1-j} and
// right[j] = t_{span+j} - t, j = 1..p (scaled by a common power of two where core/bspline.cpp needs
// it): ndu[r][p] = N_{span-p+r}(t); the lower triangle holds the knot sums the derivatives divide by.
PM_FN void bsplineTriangle(int p, PM_ROW_IN(left), PM_ROW_IN(right), PM_TABLE_OUT(ndu)) {
  ndu[0][0] = REAL(1);
  for (int j = 1; j <= p; ++j) {
    REAL saved = REAL(0);
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      REAL temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
}

// ders[k][r] = d^k/dt^k N_{span-p+r}(t) for k = 0..n (n <= p), r = 0..p, from that triangle; rows
// above n are left unwritten.
PM_FN void bsplineDerivatives(int p, int n, PM_TABLE_IN(ndu), PM_TABLE_OUT(ders)) {
  REAL a[2][kMaxBasis];
  for (int r = 0; r <= p; ++r) ders[0][r] = ndu[r][p];
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = REAL(1);
    for (int k = 1; k <= n; ++k) {
      REAL d = REAL(0);
      int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      int j1 = rk >= -1 ? 1 : -rk;
      int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      int swap = s1;
      s1 = s2;
      s2 = swap;
    }
  }
  REAL factor = REAL(p);
  for (int k = 1; k <= n; ++k) {
    for (int j = 0; j <= p; ++j) ders[k][j] *= factor;
    factor *= REAL(p - k);
  }
}

#ifndef SHAPESPLINE_GLSL
}  // namespace shapespline::pm
#endif
#undef PM_FN
#undef PM_OUT
#undef PM_INOUT
#undef PM_IN4
#undef PM_CONST
#undef PM_ROW_IN
#undef PM_TABLE_IN
#undef PM_TABLE_OUT

#endif  // SHAPESPLINE_CORE_POINT_MATH_H
