// Identities of the uniform bases (docs/math.md §2, §7–§9) and the agreement of the coefficient-matrix
// form (core/span_basis.h) with the direct forms (core/basis_direct.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <shapespline/core/basis_direct.h>
#include <shapespline/core/bspline.h>
#include <shapespline/core/span_basis.h>

namespace shapespline {
namespace {

// Values of bounded bases: a few ulps per Horner step; derivative finite differences below use
// their own truncation-error bound.
constexpr double kTol = 1e-13;

std::vector<double> grid(int n = 41) {
  std::vector<double> t;
  for (int i = 0; i < n; ++i) t.push_back(double(i) / (n - 1));
  return t;
}

struct Vals {
  double b[kMaxBasisCount], d1[kMaxBasisCount], d2[kMaxBasisCount];
};
Vals eval(const SpanBasis& s, double t) {
  Vals v;
  evalSpanBasis(s, t, v.b, v.d1, v.d2);
  return v;
}

// Every admissible family, across its parameter range.
std::vector<std::pair<std::string, SpanBasis>> allBases() {
  std::vector<std::pair<std::string, SpanBasis>> out;
  for (int k = 4; k <= 6; ++k)
    for (double l : {-double(k * (k - 2)), -3.5, 0.0, 0.25, 1.0})
      out.push_back({"xuwang" + std::to_string(k) + " l=" + std::to_string(l), xuWangSpanBasis(k, l)});
  for (double l : {-8.0, -2.0, 0.0, 3.0, 1e3}) out.push_back({"gb l=" + std::to_string(l), gbSpanBasis(l)});
  const double lmin[11] = {0, 0, -2, -6, -8, -1150.0 / 107, -66.0 / 5, -82418.0 / 5239, -4832.0 / 265,
                           -14025042.0 / 676177, -156190.0 / 6719};
  for (int k = 3; k <= 10; ++k)
    for (double l : {lmin[k], -1.0, 0.0, 1.0})
      out.push_back({"ubp" + std::to_string(k) + " l=" + std::to_string(l), ubpSpanBasis(k, l)});
  out.push_back({"gubp5", gubpSpanBasis(5, std::vector<double>{0.1, 0.25, 0.65})});
  out.push_back({"gubp6", gubpSpanBasis(6, std::vector<double>{0.05, 0.2, 0.45, 0.6})});
  out.push_back({"gubp8", gubpSpanBasis(8, std::vector<double>{0.01, 0.1, 0.3, 0.4, 0.38})});
  for (int k = 2; k <= 10; ++k) out.push_back({"bspline" + std::to_string(k), uniformBSplineSpanBasis(k)});
  return out;
}

TEST(Basis, PartitionOfUnityAndSymmetry) {
  for (const auto& [name, s] : allBases()) {
    for (double t : grid()) {
      const Vals v = eval(s, t), w = eval(s, 1 - t);
      double sum = 0, sum1 = 0, sum2 = 0;
      for (int r = 0; r < s.count; ++r) {
        sum += v.b[r], sum1 += v.d1[r], sum2 += v.d2[r];
        EXPECT_NEAR(v.b[r], w.b[s.count - 1 - r], kTol) << name << " symmetry r=" << r << " t=" << t;
        EXPECT_NEAR(v.d1[r], -w.d1[s.count - 1 - r], kTol * 100) << name << " symmetry d1";
      }
      EXPECT_NEAR(sum, 1.0, kTol) << name << " t=" << t;
      EXPECT_NEAR(sum1, 0.0, kTol * 100) << name;
      EXPECT_NEAR(sum2, 0.0, kTol * 1e4) << name;  // d2 coefficients reach ~1e2 at λ_min(10)
    }
  }
}

TEST(Basis, NonNegativeExactlyOnTheDocumentedRange) {
  auto minValue = [](const SpanBasis& s) {
    double m = 1e300;
    for (double t : grid(2001)) {
      const Vals v = eval(s, t);
      for (int r = 0; r < s.count; ++r) m = std::min(m, v.b[r]);
    }
    return m;
  };
  for (int k = 4; k <= 6; ++k) {
    const double lo = -k * (k - 2);
    EXPECT_GE(minValue(xuWangSpanBasis(k, lo)), -kTol);
    EXPECT_GE(minValue(xuWangSpanBasis(k, 1.0)), -kTol);
    EXPECT_LT(minValue(xuWangSpanBasis(k, lo - 0.05)), 0.0) << "degree " << k << " just below the range";
    EXPECT_LT(minValue(xuWangSpanBasis(k, 1.05)), 0.0) << "degree " << k << " just above the range";
  }
  EXPECT_GE(minValue(gbSpanBasis(-8.0)), -kTol);
  EXPECT_LT(minValue(gbSpanBasis(-8.5)), 0.0);
}

TEST(Basis, MatrixFormMatchesPaperFormulas) {
  for (int k = 4; k <= 6; ++k)
    for (double l : {-24.0, -7.5, 0.0, 0.5, 1.0}) {
      const SpanBasis s = xuWangSpanBasis(k, l);
      for (double t : grid()) {
        double d[4];
        xuWangDirect(k, l, t, d);
        const Vals v = eval(s, t);
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(v.b[r], d[r], kTol * (1 + std::abs(l))) << "k=" << k << " l=" << l;
      }
    }
  for (double l : {-8.0, -1.0, 0.0, 4.0, 100.0}) {
    const SpanBasis s = gbSpanBasis(l);
    for (double t : grid()) {
      double d[4];
      gbDirect(l, t, d);
      const Vals v = eval(s, t);
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(v.b[r], d[r], kTol) << "gb l=" << l;
    }
  }
}

TEST(Basis, GubpMatrixFormMatchesPointwiseCoxDeBoor) {
  std::mt19937 rng(5);
  for (int k = 3; k <= 10; ++k) {
    // A random admissible mu: split each parity sum of the full vector.
    std::vector<double> full(k + 1);
    std::uniform_real_distribution<double> u(0.1, 1.0);
    for (int i = 0; i <= k / 2; ++i) full[i] = full[k - i] = u(rng);
    for (int parity = 0; parity < 2; ++parity) {
      double sum = 0;
      for (int i = parity; i <= k; i += 2) sum += full[i];
      for (int i = parity; i <= k; i += 2) full[i] /= sum;
    }
    std::vector<double> half(full.begin(), full.begin() + k / 2 + 1);
    const SpanBasis s = gubpSpanBasis(k, half);
    for (int q = 0; q < 200; ++q) {
      const double x = k * (q + 0.5) / 200.0;
      double v = 0;
      evalBell(s, x, &v, nullptr);
      EXPECT_NEAR(v, gubpBellDirect(k, full, x), kTol) << "k=" << k << " x=" << x;
    }
  }
}

// The matrix form of order k equals the integral of the order k-1 form (docs/math.md §8.1), and order 2
// equals the seed: together an induction over k = 2..10 that does not use the recurrence of §8.3.
TEST(Basis, UbpMatrixFormMatchesIntegralRecurrenceFromTheSeed) {
  for (double l : {-5.0, -0.5, 0.0, 0.75, 1.0}) {
    const SpanBasis seed = ubpSpanBasis(2, l);
    for (int q = 0; q <= 40; ++q) {
      const double x = 2.0 * q / 40.0;
      double v = 0;
      evalBell(seed, x, &v, nullptr);
      EXPECT_NEAR(v, ubpSeed(l, x), kTol) << "seed l=" << l << " x=" << x;
    }
    for (int k = 3; k <= 10; ++k) {
      const SpanBasis s = ubpSpanBasis(k, l);
      for (int q = 0; q <= 60; ++q) {
        const double x = k * q / 60.0;
        double v = 0;
        evalBell(s, x, &v, nullptr);
        EXPECT_NEAR(v, ubpBellByIntegration(k, l, x), kTol) << "k=" << k << " l=" << l << " x=" << x;
      }
    }
  }
}

TEST(Basis, Reductions) {
  auto same = [](const SpanBasis& a, const SpanBasis& b, const std::string& what) {
    ASSERT_EQ(a.count, b.count) << what;
    for (double t : grid()) {
      const Vals x = eval(a, t), y = eval(b, t);
      for (int r = 0; r < a.count; ++r) {
        EXPECT_NEAR(x.b[r], y.b[r], kTol) << what << " t=" << t;
        EXPECT_NEAR(x.d1[r], y.d1[r], kTol * 10) << what << " d1 t=" << t;
        EXPECT_NEAR(x.d2[r], y.d2[r], kTol * 100) << what << " d2 t=" << t;
      }
    }
  };
  same(xuWangSpanBasis(4, 0.0), uniformBSplineSpanBasis(4), "degree 4 at λ=0 is the cubic B-spline");
  same(xuWangSpanBasis(5, 0.0), xuWangSpanBasis(4, 1.0), "degree 5 at λ=0 equals degree 4 at λ=1");
  same(xuWangSpanBasis(6, 0.0), xuWangSpanBasis(5, 1.0), "degree 6 at λ=0 equals degree 5 at λ=1");
  same(gbSpanBasis(0.0), uniformBSplineSpanBasis(4), "GB at λ=0 is the cubic B-spline");
  for (double l : {-8.0, -2.0, 0.5, 1.0}) same(ubpSpanBasis(4, l), xuWangSpanBasis(4, l), "UBP order 4 = Xu-Wang 4");
  // UBP at λ=0 is the uniform B-spline of order k, checked against de Boor–Cox on integer knots.
  for (int k = 2; k <= 10; ++k) {
    const SpanBasis s = ubpSpanBasis(k, 0.0);
    std::vector<double> knots;
    for (int i = 0; i < 2 * k; ++i) knots.push_back(i);
    for (double t : grid(21)) {
      const double u = (k - 1) + std::min(t, 1.0 - 1e-15);
      double out[3][kMaxBasisCount];
      bsplineBasisDerivs(k, knots, k - 1, u, 2, out);
      const Vals v = eval(s, t);
      for (int r = 0; r < k; ++r) EXPECT_NEAR(v.b[r], out[0][r], 1e-12) << "order " << k << " t=" << t;
    }
  }
}

TEST(Basis, DerivativesMatchFiniteDifferences) {
  for (const auto& [name, s] : allBases()) {
    for (double t : {0.1, 0.37, 0.5, 0.81}) {
      const double h = 1e-5;
      const Vals v = eval(s, t), p = eval(s, t + h), m = eval(s, t - h);
      for (int r = 0; r < s.count; ++r) {
        // Central differences: truncation h^2 |B'''|/6 plus rounding eps/h; both ~1e-8 here.
        EXPECT_NEAR(v.d1[r], (p.b[r] - m.b[r]) / (2 * h), 1e-7 * (1 + std::abs(v.d2[r]))) << name;
        EXPECT_NEAR(v.d2[r], (p.d1[r] - m.d1[r]) / (2 * h), 1e-6 * (1 + std::abs(v.d2[r]))) << name;
      }
    }
  }
}

TEST(Basis, UbpDoubledKnotCoefficientsHaveUnitParitySums) {
  for (int k = 2; k <= 10; ++k)
    for (double l : {-5.0, 0.0, 1.0}) {
      const auto c = ubpDoubledKnotCoefficients(k, l);
      ASSERT_EQ(static_cast<int>(c.size()), k + 1);
      double even = 0, odd = 0;
      for (int i = 0; i <= k; ++i) (i % 2 ? odd : even) += c[i];
      if (k >= 3) {
        EXPECT_NEAR(even, 1.0, kTol) << "k=" << k;
        EXPECT_NEAR(odd, 1.0, kTol) << "k=" << k;
      }
      for (int i = 0; i <= k; ++i) EXPECT_NEAR(c[i], c[k - i], kTol);
    }
}

// Order k is exactly C^(k-2) at the integers: derivative k-2 continuous (checked through d1/d2
// for k = 3, 4), and for k = 3 the second derivative jumps.
TEST(Basis, JointSmoothness) {
  for (int k = 3; k <= 10; ++k) {
    const SpanBasis s = ubpSpanBasis(k, -1.0);
    // Span r ends where span r-1 starts (B_r(1) joins B_{r-1}(0) in the bell).
    for (int r = 1; r < k; ++r) {
      const Vals end = eval(s, 1.0), start = eval(s, 0.0);
      EXPECT_NEAR(end.b[r], start.b[r - 1], kTol) << "k=" << k;
      EXPECT_NEAR(end.d1[r], start.d1[r - 1], kTol * 10) << "k=" << k;
      if (k >= 4) {
        EXPECT_NEAR(end.d2[r], start.d2[r - 1], kTol * 100) << "k=" << k;
      }
    }
  }
  // λ = -1 is the one value where order 3 happens to be C^2 (1 + 2λ = -2 - λ), so use λ = 1/2.
  const SpanBasis s3 = ubpSpanBasis(3, 0.5);
  const Vals end = eval(s3, 1.0), start = eval(s3, 0.0);
  bool jumps = false;
  for (int r = 1; r < 3; ++r) jumps |= std::abs(end.d2[r] - start.d2[r - 1]) > 1e-3;
  EXPECT_TRUE(jumps) << "order-3 UBP must not be C^2";
}

}  // namespace
}  // namespace shapespline
