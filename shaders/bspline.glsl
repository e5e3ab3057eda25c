// Knot-vector B-spline basis (docs/math.md §10.1), included after common.glsl by bspline_*_eval.comp.
// Knots live in PARAMS (layout.h); the order is a specialization constant of the including kernel,
// so every loop bound below is a compile-time constant after specialization.
#ifndef SHAPESPLINE_BSPLINE_GLSL
#define SHAPESPLINE_BSPLINE_GLSL

REAL knotAt(uint knotOffset, int i) { return params[knotOffset + uint(i)]; }

// core/bspline.cpp bsplineBasisDerivs with derivs = min(2, order-1) (point_math.h bsplineTriangle
// and bsplineDerivatives): N_{span-order+1+r}(t) and its first two derivatives in b/d1/d2[r],
// r < order; derivatives above order-1 are 0. `span` is a non-empty interval index (findKnotSpan).
void bsplineBasisDerivs(uint knotOffset, uint order, int span, REAL t, out REAL b[kMaxBasis],
                        out REAL d1[kMaxBasis], out REAL d2[kMaxBasis]) {
  const int p = int(order) - 1;
  REAL left[kMaxBasis], right[kMaxBasis];
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knotAt(knotOffset, span + 1 - j);
    right[j] = knotAt(knotOffset, span + j) - t;
  }
  REAL ndu[kMaxBasis][kMaxBasis], ders[kMaxBasis][kMaxBasis];
  bsplineTriangle(p, left, right, ndu);
  const int n = min(2, p);
  bsplineDerivatives(p, n, ndu, ders);
  for (int r = 0; r < kMaxBasis; ++r) {
    b[r] = r <= p ? ders[0][r] : REAL(0);
    d1[r] = r <= p ? ders[1][r] : REAL(0);  // p >= 1: row 1 is written
    d2[r] = r <= p && n >= 2 ? ders[2][r] : REAL(0);
  }
}

// Grid sample a of S on interval record `rec` (layout.h): the span findKnotSpan picks and the knot
// parameter t_j + s (t_{j+1} - t_j), s = a/(S-1), exactly as core/curve.cpp / core/surface.cpp form it.
void gridKnotParameter(uint knotOffset, uint rec, uint a, uint S, out int span, out REAL x, out REAL local) {
  local = S > 1u ? REAL(a) / REAL(S - 1u) : REAL(0);
  if (S > 1u && a == S - 1u) {
    span = int(params[rec + 1u]);
    x = params[rec + 2u];
    return;
  }
  span = int(params[rec]);
  REAL t0 = knotAt(knotOffset, span), t1 = knotAt(knotOffset, span + 1);
  precise REAL xp = t0 + local * (t1 - t0);
  x = xp;
}

#endif  // SHAPESPLINE_BSPLINE_GLSL
