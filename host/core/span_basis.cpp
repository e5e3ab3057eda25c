#include <shapespline/core/span_basis.h>

#include <shapespline/core/point_math.h>

#include <cmath>

namespace shapespline {
namespace {

// Xu-Wang tables (docs/math.md §2.1): coefficient of t^d of b_r is A[r][d] + B[r][d]*lambda.
struct XuWangTable {
  double a[4][7];
  double b[4][7];
};

constexpr XuWangTable kXuWang4 = {
    {{1. / 6, -1. / 2, 1. / 2, -1. / 6, 0},
     {2. / 3, 0, -1, 1. / 2, 0},
     {1. / 6, 1. / 2, 1. / 2, -1. / 2, 0},
     {0, 0, 0, 1. / 6, 0}},
    {{-1. / 24, 0, 1. / 4, -1. / 3, 1. / 8},
     {1. / 12, 0, -1. / 2, 1. / 2, -1. / 8},
     {-1. / 24, 0, 1. / 4, 0, -1. / 8},
     {0, 0, 0, -1. / 6, 1. / 8}}};

constexpr XuWangTable kXuWang5 = {
    {{1. / 8, -1. / 2, 3. / 4, -1. / 2, 1. / 8, 0},
     {3. / 4, 0, -3. / 2, 1, -1. / 8, 0},
     {1. / 8, 1. / 2, 3. / 4, -1. / 2, -1. / 8, 0},
     {0, 0, 0, 0, 1. / 8, 0}},
    {{-1. / 40, 0, 1. / 4, -1. / 2, 3. / 8, -1. / 10},
     {1. / 20, 0, -1. / 2, 1, -7. / 8, 3. / 10},
     {-1. / 40, 0, 1. / 4, -1. / 2, 5. / 8, -3. / 10},
     {0, 0, 0, 0, -1. / 8, 1. / 10}}};

constexpr XuWangTable kXuWang6 = {
    {{1. / 10, -1. / 2, 1, -1, 1. / 2, -1. / 10, 0},
     {4. / 5, 0, -2, 2, -1, 3. / 10, 0},
     {1. / 10, 1. / 2, 1, -1, 1. / 2, -3. / 10, 0},
     {0, 0, 0, 0, 0, 1. / 10, 0}},
    {{-1. / 60, 0, 1. / 4, -2. / 3, 3. / 4, -2. / 5, 1. / 12},
     {1. / 30, 0, -1. / 2, 4. / 3, -3. / 2, 7. / 10, -1. / 12},
     {-1. / 60, 0, 1. / 4, -2. / 3, 3. / 4, -1. / 5, -1. / 12},
     {0, 0, 0, 0, 0, -1. / 10, 1. / 12}}};

// A polynomial in the local variable s, as power-basis coefficients.
struct Poly {
  double c[kMaxPolyDegree + 2] = {};
};

// Pieces of the doubled-knot B-splines N*_{i,k+1} (knots t*_q = floor(q/2)) on [m, m+1],
// as polynomials in s = x - m, by Cox-de Boor on polynomials (0/0 treated as 0).
// out[i] for i = 0..k.
void doubledKnotPieces(int k, int m, Poly* out) {
  const int order = k + 1;
  auto knot = [](int q) { return static_cast<double>(q / 2); };
  const int n = 2 * order + 2;  // enough basis functions for every i <= k at the top level
  Poly cur[2 * kMaxBasisCount + 8];
  for (int i = 0; i < n; ++i) {
    cur[i] = Poly{};
    if (knot(i) == m && knot(i + 1) == m + 1) cur[i].c[0] = 1.0;
  }
  for (int p = 2; p <= order; ++p) {
    Poly next[2 * kMaxBasisCount + 8];
    for (int i = 0; i + 1 < n; ++i) {
      const double tl = knot(i), tr = knot(i + p - 1);
      const double ul = knot(i + 1), ur = knot(i + p);
      if (tr > tl) {  // (x - t_i)/(t_{i+p-1} - t_i) * N_{i,p-1}, x = m + s
        const double inv = 1.0 / (tr - tl), off = m - tl;
        for (int d = kMaxPolyDegree; d >= 0; --d) {
          next[i].c[d + 1] += cur[i].c[d] * inv;
          next[i].c[d] += cur[i].c[d] * off * inv;
        }
      }
      if (ur > ul) {  // (t_{i+p} - x)/(t_{i+p} - t_{i+1}) * N_{i+1,p-1}
        const double inv = 1.0 / (ur - ul), off = ur - m;
        for (int d = kMaxPolyDegree; d >= 0; --d) {
          next[i].c[d + 1] -= cur[i + 1].c[d] * inv;
          next[i].c[d] += cur[i + 1].c[d] * off * inv;
        }
      }
    }
    for (int i = 0; i < n; ++i) cur[i] = next[i];
  }
  for (int i = 0; i <= k; ++i) out[i] = cur[i];
}

// Span basis of N = sum_i mu_i N*_{i,k+1}: B_r is the piece on [k-1-r, k-r].
SpanBasis spanBasisFromDoubledKnots(int k, std::span<const double> muFull) {
  SpanBasis basis;
  basis.count = k;
  basis.degree = k;
  basis.centre = (k - 1) / 2;
  Poly pieces[kMaxBasisCount + 1];
  for (int m = 0; m < k; ++m) {
    doubledKnotPieces(k, m, pieces);
    const int r = k - 1 - m;
    for (int d = 0; d <= k; ++d) {
      double sum = 0.0;
      for (int i = 0; i <= k; ++i) sum += muFull[i] * pieces[i].c[d];
      basis.coef[r][d] = sum;
    }
  }
  return basis;
}

}  // namespace

SpanBasis xuWangSpanBasis(int degree, double lambda) {
  const XuWangTable& table = degree == 4 ? kXuWang4 : degree == 5 ? kXuWang5 : kXuWang6;
  SpanBasis basis;
  basis.count = 4;
  basis.degree = degree;
  basis.centre = 1;
  for (int r = 0; r < 4; ++r)
    for (int d = 0; d <= degree; ++d) basis.coef[r][d] = table.a[r][d] + table.b[r][d] * lambda;
  return basis;
}

SpanBasis gbSpanBasis(double lambda) {
  const double s = 1.0 / (12.0 + lambda);
  SpanBasis basis;
  basis.count = 4;
  basis.degree = 3;
  basis.centre = 1;
  // factor * x * s; for λ near DBL_MAX factor * x overflows, so s is applied first there (the same
  // bits as before wherever the product is finite).
  const auto scaled = [s](double factor, double x) {
    const double p = factor * x;
    return std::isfinite(p) ? p * s : factor * (x * s);
  };
  const double rows[4][4] = {{2 * s, -6 * s, 6 * s, -2 * s},
                             {(8 + lambda) * s, 0, scaled(-3, 4 + lambda), scaled(2, 3 + lambda)},
                             {2 * s, 6 * s, scaled(3, 2 + lambda), scaled(-2, 3 + lambda)},
                             {0, 0, 0, 2 * s}};
  for (int r = 0; r < 4; ++r)
    for (int d = 0; d < 4; ++d) basis.coef[r][d] = rows[r][d];
  return basis;
}

std::vector<double> ubpDoubledKnotCoefficients(int order, double lambda) {
  // Start at k = 2 and apply the bidiagonal M_k of docs/math.md §8.3 for k = 3..order.
  std::vector<double> coeffs = {(1 - lambda) / 2, 1 + lambda / 2, (1 - lambda) / 2};
  for (int k = 3; k <= order; ++k) {
    std::vector<double> next(k + 1, 0.0);
    for (int i = 0; i < k; ++i) {
      const int d = (i + k) / 2 - i / 2;
      const double w = static_cast<double>(d) / k;
      next[i] += coeffs[i] * w;
      next[i + 1] += coeffs[i] * w;
    }
    coeffs = std::move(next);
  }
  return coeffs;
}

std::vector<double> gubpFullMu(int order, std::span<const double> muHalf) {
  std::vector<double> full(order + 1);
  for (int i = 0; i <= order; ++i) {
    const int h = i <= order / 2 ? i : order - i;
    full[i] = muHalf[h];
  }
  return full;
}

SpanBasis ubpSpanBasis(int order, double lambda) {
  if (order == 2) {
    // The seed (docs/math.md §8.1): (1-lambda)x + (3 lambda/2)x^2 on [0,1), mirrored on [1,2).
    SpanBasis basis;
    basis.count = 2;
    basis.degree = 2;
    basis.centre = 0;
    // B_1 is the piece on [0,1]; B_0 the piece on [1,2] in s = x - 1: N(2 - x) = N(1 - s).
    basis.coef[1][1] = 1 - lambda;
    basis.coef[1][2] = 1.5 * lambda;
    basis.coef[0][0] = (1 - lambda) + 1.5 * lambda;
    basis.coef[0][1] = -(1 - lambda) - 3 * lambda;
    basis.coef[0][2] = 1.5 * lambda;
    return basis;
  }
  const std::vector<double> coeffs = ubpDoubledKnotCoefficients(order, lambda);
  return spanBasisFromDoubledKnots(order, coeffs);
}

SpanBasis gubpSpanBasis(int order, std::span<const double> muHalf) {
  const std::vector<double> full = gubpFullMu(order, muHalf);
  return spanBasisFromDoubledKnots(order, full);
}

SpanBasis uniformBSplineSpanBasis(int order) { return ubpSpanBasis(order, 0.0); }

SpanBasis makeSpanBasis(const FamilySpec& family) { return familyOf(family.construction).spanBasis(family); }

void evalSpanBasis(const SpanBasis& basis, double t, double* b, double* d1, double* d2) {
  for (int r = 0; r < basis.count; ++r) {
    const double* c = basis.coef[r];
    double p = c[basis.degree], dp = 0.0, ddp = 0.0;
    for (int d = basis.degree - 1; d >= 0; --d) pm::hornerStep(p, dp, ddp, t, c[d]);
    if (b) b[r] = p;
    if (d1) d1[r] = dp;
    if (d2) d2[r] = 2.0 * ddp;
  }
}

void evalBell(const SpanBasis& basis, double x, double* value, double* d1) {
  const int m = basis.count;
  if (!(x >= 0.0 && x <= m)) {
    if (value) *value = 0.0;
    if (d1) *d1 = 0.0;
    return;
  }
  int piece = static_cast<int>(std::floor(x));
  if (piece >= m) piece = m - 1;
  const int r = m - 1 - piece;
  double b[kMaxBasisCount], db[kMaxBasisCount];
  evalSpanBasis(basis, x - piece, b, db, nullptr);
  if (value) *value = b[r];
  if (d1) *d1 = db[r];
}

}  // namespace shapespline
