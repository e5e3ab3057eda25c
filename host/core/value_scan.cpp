#include <shapespline/core/value_scan.h>

#include <algorithm>
#include <cmath>

namespace shapespline {
namespace {

constexpr size_t kLanes = 8;
constexpr size_t kBlock = 4096;  // values per block: a non-finite block is searched again, value by value

// NaN when some value of [v, v + n) is not finite (0 * x is NaN exactly for NaN and ±inf), else 0.
double nonFiniteSignal(const double* v, size_t n) {
  double lane[kLanes] = {};
  size_t i = 0;
  for (; i + kLanes <= n; i += kLanes)
    for (size_t k = 0; k < kLanes; ++k) lane[k] += v[i + k] * 0.0;
  for (; i < n; ++i) lane[0] += v[i] * 0.0;
  double s = 0.0;
  for (double x : lane) s += x;
  return s;
}

}  // namespace

size_t firstNonFinite(const double* values, size_t n) {
  for (size_t b = 0; b < n; b += kBlock) {
    const size_t e = std::min(n, b + kBlock);
    if (nonFiniteSignal(values + b, e - b) == 0.0) continue;
    for (size_t i = b; i < e; ++i)
      if (!std::isfinite(values[i])) return i;
  }
  return n;
}

double largestMagnitude(const double* values, size_t n) {
  double lane[kLanes] = {};
  size_t i = 0;
  for (; i + kLanes <= n; i += kLanes)
    for (size_t k = 0; k < kLanes; ++k) {
      const double a = std::abs(values[i + k]);
      lane[k] = a > lane[k] ? a : lane[k];
    }
  for (; i < n; ++i) lane[0] = std::max(lane[0], std::abs(values[i]));
  return *std::max_element(lane, lane + kLanes);
}

ValueRange valueRange(const double* values, size_t n) {
  double lo[kLanes], hi[kLanes];
  std::fill(lo, lo + kLanes, values[0]);
  std::fill(hi, hi + kLanes, values[0]);
  size_t i = 0;
  for (; i + kLanes <= n; i += kLanes)
    for (size_t k = 0; k < kLanes; ++k) {
      const double a = values[i + k];
      lo[k] = a < lo[k] ? a : lo[k];
      hi[k] = a > hi[k] ? a : hi[k];
    }
  for (; i < n; ++i) lo[0] = std::min(lo[0], values[i]), hi[0] = std::max(hi[0], values[i]);
  return {*std::min_element(lo, lo + kLanes), *std::max_element(hi, hi + kLanes)};
}

}  // namespace shapespline
