#pragma once
// Passes over big arrays of doubles (a 4096² net holds 5·10^7 of them; its validation, bounds and
// metadata each read it once). Written with independent lanes and no exit inside a block, so that
// the compiler vectorises them: a single chain of max or of `isfinite` tests ran at a value per
// 3-4 cycles.
#include <cstddef>

namespace shapespline {

// The index of the first value that is NaN or infinite; n when every value is finite.
size_t firstNonFinite(const double* values, size_t n);

// The largest |value| (0 when n = 0); the values must be finite.
double largestMagnitude(const double* values, size_t n);

struct ValueRange {
  double min = 0.0, max = 0.0;
};
// The smallest and the largest value (n >= 1, every value finite).
ValueRange valueRange(const double* values, size_t n);

}  // namespace shapespline
