#pragma once
// Records of sampled points: one per point, the chosen fields in the chosen order, x y z each, as
// fp32 (rounded once) or fp64 values in the host's byte order (little-endian: io checks). The one
// encoding of raw and .npy files (io/raw_records.h), written from a chunk's planes (GPU chunks,
// callers that deliver planes) or straight from the CPU sampler's rows (SamplerOptions::records).
// Every encoder also checks each value as it passes: the answer is whether all lie within
// recordRangeLimit (NaN does not), so that a caller need not read them again.
#include <shapespline/core/sample_grid.h>

#include <glm/vec3.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

namespace shapespline {

// The largest magnitude a record value may have: FLT_MAX when the values come from fp32 planes or
// go into fp32 records (beyond it they would be inf), else any finite fp64.
constexpr double recordRangeLimit(bool sourceFloat, bool float64) {
  return sourceFloat || !float64 ? double(std::numeric_limits<float>::max()) : std::numeric_limits<double>::max();
}

// Stores v at e as an fp64 or an fp32 (rounded once) and returns the end: the value encoding of
// every binary sample file (raw, .npy, binary PLY).
inline char* putBinaryValue(char* e, double v, bool float64) {
  if (float64) {
    std::memcpy(e, &v, 8);
    return e + 8;
  }
  const float x = static_cast<float>(v);
  std::memcpy(e, &x, 4);
  return e + 4;
}

// Bytes of one record.
inline size_t recordBytes(size_t fieldCount, bool float64) { return fieldCount * 3 * (float64 ? 8 : 4); }

// Records of points [first, first + count) of `chunk`, its planes `fields` in that order, at `dst`.
bool encodeRecords(char* dst, const GridChunk& chunk, const std::vector<Field>& fields, bool float64, size_t first,
                   size_t count);

// Records of n points from structure-of-arrays rows: rows[3 * f + c][b] is axis c of the record's
// field f at point b (fp64 values, the CPU sampler's). Bit for bit what encodeRecords makes of the
// same values in planes.
bool encodeRowRecords(char* dst, const double* const* rows, size_t fieldCount, bool float64, size_t n);

// One field of one record: 3 values at `dst`; `inRange` is cleared if one is out of range.
inline void encodeValue3(char* dst, const glm::dvec3& v, bool float64, bool& inRange) {
  const double limit = recordRangeLimit(false, float64);
  for (int c = 0; c < 3; ++c) {
    inRange &= std::abs(v[c]) <= limit;
    dst = putBinaryValue(dst, v[c], float64);
  }
}

}  // namespace shapespline
