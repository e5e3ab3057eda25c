#pragma once
// Per-span coefficient matrices of the uniform local families (docs/math.md §1–§9).
//
// Every uniform family is a set of m polynomials B_0..B_{m-1} on t in [0,1]; span j of a curve is
// C_j(t) = sum_r B_r(t) P_{j-c+r} with c = floor((m-1)/2) (docs/math.md §1). SpanBasis stores the power-basis
// coefficients of the B_r, computed in fp64 from the family's parameters. This is the form the GPU
// consumes (uploaded as a small parameter buffer) and the form the CPU hot loops evaluate by Horner.
#include <shapespline/core/model.h>

#include <span>
#include <vector>

namespace shapespline {

inline constexpr int kMaxBasisCount = 10;   // m: UBP/GUBP/B-spline order up to 10
inline constexpr int kMaxPolyDegree = 10;   // UBP order k pieces have degree k

struct SpanBasis {
  int count = 0;    // m, number of basis functions (= control points per span)
  int degree = 0;   // polynomial degree in t
  int centre = 0;   // c = floor((m-1)/2), docs/math.md §1
  double coef[kMaxBasisCount][kMaxPolyDegree + 1] = {};  // B_r(t) = sum_d coef[r][d] t^d
};

// Xu-Wang extended cubic basis of degree 4..6 (docs/math.md §2.1 tables).
SpanBasis xuWangSpanBasis(int degree, double lambda);
// GB-spline basis (docs/math.md §7.1).
SpanBasis gbSpanBasis(double lambda);
// UBP of order 2..10 (docs/math.md §8). Order 2 is the seed: a basis query only, not a curve basis.
SpanBasis ubpSpanBasis(int order, double lambda);
// GUBP of order 3..10 from the half vector mu_0..mu_{floor(k/2)} (docs/math.md §9).
SpanBasis gubpSpanBasis(int order, std::span<const double> muHalf);
// Uniform B-spline of order 2..10 (= UBP at lambda 0).
SpanBasis uniformBSplineSpanBasis(int order);
// The span basis of any uniform family (everything but BSpline with knots).
SpanBasis makeSpanBasis(const FamilySpec& family);

// Theorem-1 coefficients lambda_{0,k}..lambda_{k,k} of UBP order k (docs/math.md §8.3 recurrence).
std::vector<double> ubpDoubledKnotCoefficients(int order, double lambda);
// Full symmetric GUBP vector mu_0..mu_k from the half vector (docs/math.md §9).
std::vector<double> gubpFullMu(int order, std::span<const double> muHalf);

// Raw kernel: B_r(t), B_r'(t), B_r''(t) for r < basis.count by Horner in t. Any output may be null.
void evalSpanBasis(const SpanBasis& basis, double t, double* b, double* d1, double* d2);

// The bell function N(x) on [0, m] assembled from the pieces, N(x) = B_{m-1-floor(x)}(x - floor(x))
// (docs/math.md §1). At an integer x the piece to the right is used, except at x = m (last piece).
// Outside [0, m] the value is 0.
void evalBell(const SpanBasis& basis, double x, double* value, double* d1);

}  // namespace shapespline
