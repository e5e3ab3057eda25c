// The knot-vector surface patch of bspline_surface_eval.comp and bspline_surface_grid.comp
// (docs/math.md §10.1, core/bspline.h evalBSplineSurface), included after their buffers and push
// block (net, params, pc: KnotEvalPush) and bspline.glsl.
#ifndef SHAPESPLINE_KNOT_PATCH_GLSL
#define SHAPESPLINE_KNOT_PATCH_GLSL

struct Sample {
  REAL3 p, u, v, uu, uv, vv, n;
};

// core/bspline.cpp evalBSplineSurface: contract in v first, then u (rational surfaces: the
// homogeneous sums of NET's (w P, w) records, then point_math.h's quotient rule).
Sample evalKnotPatch(int spanU, REAL x, int spanV, REAL y) {
  REAL bu[kMaxBasis], du[kMaxBasis], ddu[kMaxBasis];
  REAL bv[kMaxBasis], dv[kMaxBasis], ddv[kMaxBasis];
  bsplineBasisDerivs(pc.knotOffsetU, BASIS_COUNT_U, spanU, x, bu, du, ddu);
  bsplineBasisDerivs(pc.knotOffsetV, BASIS_COUNT_V, spanV, y, bv, dv, ddv);
  uint firstU = uint(spanU) + 1u - BASIS_COUNT_U, firstV = uint(spanV) + 1u - BASIS_COUNT_V;
  Sample o;
  o.p = REAL3(0); o.u = REAL3(0); o.v = REAL3(0); o.uu = REAL3(0); o.uv = REAL3(0); o.vv = REAL3(0);
  o.n = fixedAxisNormal();
  REAL w = REAL(0), wu = REAL(0), wv = REAL(0), wuu = REAL(0), wuv = REAL(0), wvv = REAL(0);  // rational: W
  for (uint r = 0; r < BASIS_COUNT_U; ++r) {
    REAL3 s0 = REAL3(0), s1 = REAL3(0), s2 = REAL3(0);
    REAL w0 = REAL(0), w1 = REAL(0), w2 = REAL(0);
    uint row = (firstU + r) * pc.netCols + firstV;
    for (uint s = 0; s < BASIS_COUNT_V; ++s) {
      REAL4 P = net[row + s];
      accumulate3(s0, s1, s2, bv[s], dv[s], ddv[s], P.xyz);
      w0 += bv[s] * P.w, w1 += dv[s] * P.w, w2 += ddv[s] * P.w;
    }
    accumulateTensorRow(o.p, o.u, o.v, o.uu, o.uv, o.vv, bu[r], du[r], ddu[r], s0, s1, s2);
    w += bu[r] * w0, wu += du[r] * w0, wuu += ddu[r] * w0, wv += bu[r] * w1, wuv += du[r] * w1, wvv += bu[r] * w2;
  }
  if (RATIONAL != 0u) rationalSurface(o.p, o.u, o.v, o.uu, o.uv, o.vv, w, wu, wv, wuu, wuv, wvv);
  return o;
}

// The point of interval pair (iu, iv) at local (lu, lv) moved 2^-12 towards the pair's centre, as
// knot parameters: the second step of core/surface.cpp evalWithNormal's normal rule.
void knotsTowardCentre(int iu, int iv, REAL lu, REAL lv, out REAL xs, out REAL ys) {
  REAL u0 = knotAt(pc.knotOffsetU, iu), u1 = knotAt(pc.knotOffsetU, iu + 1);
  REAL v0 = knotAt(pc.knotOffsetV, iv), v1 = knotAt(pc.knotOffsetV, iv + 1);
  precise REAL x = u0 + towardCentre(lu) * (u1 - u0);
  precise REAL y = v0 + towardCentre(lv) * (v1 - v0);
  xs = x;
  ys = y;
}

// Normal of core/surface.cpp evalWithNormal for a plain surface, given the partials (du, dv) of a
// sample of interval pair (iu, iv) at local (lu, lv): du x dv; if degenerate, again at the point
// moved towards the centre (the base-surface step repeats the regular one here); then +z.
REAL3 knotNormal(REAL3 du, REAL3 dv, int iu, int iv, REAL lu, REAL lv) {
  REAL3 nn = cross(du, dv);
  if (!degenerateCross(du, dv, nn)) return normalize(nn);
  REAL xs, ys;
  knotsTowardCentre(iu, iv, lu, lv, xs, ys);
  Sample s = evalKnotPatch(iu, xs, iv, ys);
  nn = cross(s.u, s.v);
  return degenerateCross(s.u, s.v, nn) ? fixedAxisNormal() : normalize(nn);
}

#endif  // SHAPESPLINE_KNOT_PATCH_GLSL
