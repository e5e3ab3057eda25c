// core/value_scan.h, the vectorised passes over big arrays, against plain loops: every position of
// a non-finite value (inside a lane group, at a block's edge, in the tail), signs and magnitudes;
// and the model validation that uses them, which must still name the first value that breaks a
// rule (points[i][j][d], alpha[i][j]) wherever it is in a big net.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <shapespline/core/surface.h>
#include <shapespline/core/validate.h>
#include <shapespline/core/value_scan.h>

namespace shapespline {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<double> randomValues(size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> d(-1e3, 1e3);
  std::vector<double> v(n);
  for (double& x : v) x = d(rng);
  return v;
}

TEST(ValueScan, FirstNonFiniteFindsTheFirstAnywhere) {
  const size_t n = 3 * 4096 + 13;  // three whole blocks and a tail that is not a lane multiple
  const std::vector<double> clean = randomValues(n, 1);
  EXPECT_EQ(firstNonFinite(clean.data(), n), n);
  EXPECT_EQ(firstNonFinite(clean.data(), 0), 0u);
  for (size_t at : {size_t{0}, size_t{5}, size_t{4095}, size_t{4096}, size_t{8191}, n - 13, n - 1}) {
    for (double bad : {kNaN, kInf, -kInf}) {
      std::vector<double> v = clean;
      v[at] = bad;
      EXPECT_EQ(firstNonFinite(v.data(), n), at) << at;
      if (at + 3 < n) v[at + 3] = kNaN;  // a later one does not hide the first
      EXPECT_EQ(firstNonFinite(v.data(), n), at) << at;
    }
  }
  // The largest and smallest finite doubles are finite (0 * x is 0 for them).
  std::vector<double> extremes = {std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
                                  std::numeric_limits<double>::denorm_min(), -0.0};
  EXPECT_EQ(firstNonFinite(extremes.data(), extremes.size()), extremes.size());
}

TEST(ValueScan, LargestMagnitudeAndRangeMatchPlainLoops) {
  for (size_t n : {size_t{1}, size_t{7}, size_t{8}, size_t{9}, size_t{1000}, size_t{4099}}) {
    std::vector<double> v = randomValues(n, static_cast<unsigned>(n));
    v[n / 2] = -1e6;  // the largest magnitude is negative
    double largest = 0.0, lo = v[0], hi = v[0];
    for (double x : v) largest = std::max(largest, std::abs(x)), lo = std::min(lo, x), hi = std::max(hi, x);
    EXPECT_EQ(largestMagnitude(v.data(), n), largest) << n;
    EXPECT_EQ(largestMagnitude(v.data(), n), 1e6) << n;
    const ValueRange r = valueRange(v.data(), n);
    EXPECT_EQ(r.min, lo) << n;
    EXPECT_EQ(r.max, hi) << n;
  }
  EXPECT_EQ(largestMagnitude(nullptr, 0), 0.0);
}

// A 70 x 70 α-EB net (4,900 points: 14,700 coordinates, more than three blocks of the scan).
SurfaceModel bigNet() {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.rows = m.cols = 70;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) m.points.emplace_back(i, j, std::sin(0.1 * i) * std::cos(0.2 * j));
  m.alpha.assign(m.points.size(), 0.5);
  return m;
}

std::string fieldOfError(const SurfaceModel& m) {
  try {
    validateSurface(m);
  } catch (const ModelError& e) {
    return e.field();
  }
  return "(no error)";
}

TEST(ValueScan, SurfaceValidationNamesTheFirstBadValue) {
  EXPECT_EQ(fieldOfError(bigNet()), "(no error)");
  for (const auto& [i, j, d] : {std::tuple{0, 0, 0}, std::tuple{0, 69, 2}, std::tuple{19, 35, 1}, std::tuple{69, 69, 2}}) {
    SurfaceModel m = bigNet();
    m.points[static_cast<size_t>(i) * 70 + j][d] = kNaN;
    m.points.back().x = kInf;  // a later one
    const std::string want = "points[" + std::to_string(i) + "][" + std::to_string(j) + "][" + std::to_string(d) + "]";
    EXPECT_EQ(fieldOfError(m), (i == 69 && j == 69 ? "points[69][69][0]" : want));
  }
  for (double bad : {0.0, -0.5, 1.5, kNaN, kInf}) {
    SurfaceModel m = bigNet();
    m.alpha[static_cast<size_t>(41) * 70 + 7] = bad;
    m.alpha.back() = 2.0;
    EXPECT_EQ(fieldOfError(m), "alpha[41][7]") << bad;
  }
  SurfaceModel ok = bigNet();
  ok.alpha.front() = 1.0;  // the range's ends are allowed: (0, 1]
  ok.alpha.back() = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(fieldOfError(ok), "(no error)");
}

}  // namespace
}  // namespace shapespline
