#include <shapespline/core/basis_direct.h>

#include <shapespline/core/span_basis.h>

#include <algorithm>
#include <cmath>

namespace shapespline {

void xuWangDirect(int k, double l, double t, double b[4]) {
  const double s = 1.0 - t;
  if (k == 4) {
    b[0] = (4 - l - 3 * l * t) * s * s * s / 24;
    b[1] = (16 + 2 * l - 12 * (2 + l) * t * t + 12 * (1 + l) * t * t * t - 3 * l * std::pow(t, 4)) / 24;
    b[2] = (4 - l + 12 * t + 6 * (2 + l) * t * t - 12 * t * t * t - 3 * l * std::pow(t, 4)) / 24;
    b[3] = (4 * (1 - l) + 3 * l * t) * t * t * t / 24;
  } else if (k == 5) {
    b[0] = (5 - l - 4 * l * t) * std::pow(s, 4) / 40;
    b[1] = (30 + 2 * l - 20 * (3 + l) * t * t + 40 * (1 + l) * std::pow(t, 3) - 5 * (1 + 7 * l) * std::pow(t, 4) +
            12 * l * std::pow(t, 5)) / 40;
    b[2] = (5 - l + 20 * t + 10 * (3 + l) * t * t - 20 * (1 + l) * std::pow(t, 3) - 5 * (1 - 5 * l) * std::pow(t, 4) -
            12 * l * std::pow(t, 5)) / 40;
    b[3] = (5 * (1 - l) + 4 * l * t) * std::pow(t, 4) / 40;
  } else {
    b[0] = (6 - l - 5 * l * t) * std::pow(s, 5) / 60;
    b[1] = (48 + 2 * l - 30 * (4 + l) * t * t + 40 * (3 + 2 * l) * std::pow(t, 3) - 30 * (2 + 3 * l) * std::pow(t, 4) +
            6 * (3 + 7 * l) * std::pow(t, 5) - 5 * l * std::pow(t, 6)) / 60;
    b[2] = (6 - l + 30 * t + 15 * (4 + l) * t * t - 20 * (3 + 2 * l) * std::pow(t, 3) + 15 * (2 + 3 * l) * std::pow(t, 4) -
            6 * (3 + 2 * l) * std::pow(t, 5) - 5 * l * std::pow(t, 6)) / 60;
    b[3] = (6 * (1 - l) + 5 * l * t) * std::pow(t, 5) / 60;
  }
}

void gbDirect(double l, double t, double b[4]) {
  const double d = 12 + l, s = 1 - t;
  b[0] = 2 * s * s * s / d;
  b[1] = (2 * (3 + l) * t * t * t - 3 * (4 + l) * t * t + 8 + l) / d;
  b[2] = (-2 * (3 + l) * t * t * t + 3 * (2 + l) * t * t + 6 * t + 2) / d;
  b[3] = 2 * t * t * t / d;
}

double doubledKnotBSpline(int i, int order, double x) {
  auto knot = [](int q) { return static_cast<double>(q / 2); };
  if (order == 1) {
    const double a = knot(i), b = knot(i + 1);
    return (a <= x && x < b) ? 1.0 : 0.0;
  }
  double v = 0.0;
  const double tl = knot(i), tr = knot(i + order - 1), ul = knot(i + 1), ur = knot(i + order);
  if (tr > tl) v += (x - tl) / (tr - tl) * doubledKnotBSpline(i, order - 1, x);
  if (ur > ul) v += (ur - x) / (ur - ul) * doubledKnotBSpline(i + 1, order - 1, x);
  return v;
}

double gubpBellDirect(int order, std::span<const double> muFull, double x) {
  double v = 0.0;
  for (int i = 0; i <= order; ++i) v += muFull[i] * doubledKnotBSpline(i, order + 1, x);
  return v;
}

double ubpSeed(double lambda, double x) {
  if (x < 0.0 || x > 2.0) return 0.0;
  const double y = x < 1.0 ? x : 2.0 - x;
  return (1 - lambda) * y + 1.5 * lambda * y * y;
}

double ubpBellByIntegration(int order, double lambda, double x) {
  // 6-point Gauss–Legendre is exact for polynomials of degree <= 11 >= the piece degree k-1.
  static const double nodes[6] = {-0.9324695142031520, -0.6612093864662645, -0.2386191860831969,
                                  0.2386191860831969,  0.6612093864662645,  0.9324695142031520};
  static const double weights[6] = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                                    0.4679139345726910, 0.3607615730481386, 0.1713244923791704};
  const SpanBasis lower = ubpSpanBasis(order - 1, lambda);
  auto lowerBell = [&](double s) {
    double v = 0.0;
    evalBell(lower, s, &v, nullptr);
    return v;
  };
  // Split [x-1, x] at the integer inside it so each sub-interval lies in one polynomial piece.
  const double a = x - 1.0, b = x, mid = std::floor(x);
  double sum = 0.0;
  for (auto [lo, hi] : {std::pair{a, mid}, std::pair{mid, b}}) {
    if (hi <= lo) continue;
    const double half = 0.5 * (hi - lo), centre = 0.5 * (hi + lo);
    for (int q = 0; q < 6; ++q) sum += weights[q] * half * lowerBell(centre + half * nodes[q]);
  }
  return sum;
}

}  // namespace shapespline
