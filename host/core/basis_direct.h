#pragma once
// Direct (pointwise) forms of the uniform bases, independent of the SpanBasis coefficient
// matrices, so that tests can show the two agree (docs/math.md §2, §7, §8, §9).
#include <span>

namespace shapespline {

// [XW] Definitions 1–3 as printed (b_0..b_3 of degree 4, 5, 6), evaluated directly.
void xuWangDirect(int degree, double lambda, double t, double b[4]);
// [GB] §2: (12+λ) b_i as printed in docs/math.md §7.1.
void gbDirect(double lambda, double t, double b[4]);
// The order-`order` B-spline N*_{i,order} on the doubled knots t*_q = floor(q/2) at x,
// by the pointwise Cox–de Boor recursion (0/0 = 0), right-continuous except at the last knot.
double doubledKnotBSpline(int i, int order, double x);
// GUBP bell N^G_{0,k}(x) = sum_i mu_i N*_{i,k+1}(x) (docs/math.md §9), muFull of length k+1.
double gubpBellDirect(int order, std::span<const double> muFull, double x);
// The UBP seed N_{0,2}(x) of docs/math.md §8.1 (R5).
double ubpSeed(double lambda, double x);
// N_{0,k}(x) = integral over [x-1, x] of N_{0,k-1} (docs/math.md §8.1), with N_{0,k-1} taken from the
// coefficient-matrix form and integrated exactly by Gauss–Legendre on each unit piece. Used to
// check the matrix form of order k inductively from the seed.
double ubpBellByIntegration(int order, double lambda, double x);

}  // namespace shapespline
