// Knot-vector B-spline basis (docs/math.md §10.1), included after common.glsl by bspline_*_eval.comp.
// Knots live in PARAMS (layout.h); the order is a specialization constant of the including kernel,
// so every loop bound below is a compile-time constant after specialization.
#ifndef SHAPESPLINE_BSPLINE_GLSL
#define SHAPESPLINE_BSPLINE_GLSL

REAL knotAt(uint knotOffset, int i) { return params[knotOffset + uint(i)]; }

// core/bspline.cpp bsplineBasisDerivs with derivs = min(2, order-1) (The NURBS Book A2.3, same
// operation order): N_{span-order+1+r}(t) and its first two derivatives in b/d1/d2[r], r < order;
// derivatives above order-1 are 0. `span` is a non-empty interval index (findKnotSpan).
void bsplineBasisDerivs(uint knotOffset, uint order, int span, REAL t, out REAL b[kMaxBasis],
                        out REAL d1[kMaxBasis], out REAL d2[kMaxBasis]) {
  const int p = int(order) - 1;
  REAL ndu[kMaxBasis][kMaxBasis];
  REAL left[kMaxBasis], right[kMaxBasis];
  REAL a[2][kMaxBasis];
  ndu[0][0] = REAL(1);
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knotAt(knotOffset, span + 1 - j);
    right[j] = knotAt(knotOffset, span + j) - t;
    REAL saved = REAL(0);
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      REAL temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  REAL ders[3][kMaxBasis];
  for (int r = 0; r <= p; ++r) {
    ders[0][r] = ndu[r][p];
    ders[1][r] = REAL(0);
    ders[2][r] = REAL(0);
  }
  const int n = min(2, p);
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
      int sw = s1;
      s1 = s2;
      s2 = sw;
    }
  }
  REAL factor = REAL(p);
  for (int k = 1; k <= n; ++k) {
    for (int j = 0; j <= p; ++j) ders[k][j] *= factor;
    factor *= REAL(p - k);
  }
  for (int r = 0; r < kMaxBasis; ++r) {
    b[r] = r <= p ? ders[0][r] : REAL(0);
    d1[r] = r <= p ? ders[1][r] : REAL(0);
    d2[r] = r <= p ? ders[2][r] : REAL(0);
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
