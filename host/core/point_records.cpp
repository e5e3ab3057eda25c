// Record encoders (core/point_records.h): one tight loop per (source, record) precision pair, and
// AVX2 versions of the two hot ones (fp64 or fp32 planes, and fp64 rows, into fp32 records).
#include <shapespline/core/point_records.h>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define SHAPESPLINE_RECORDS_AVX2 1
#endif

namespace shapespline {
namespace {

// Points [first, first + count) of the field planes (record order) into records of `Dst`: the
// compiler keeps this loop in registers (the per-value precision branch of GridChunk::coord made
// the conversion the slowest stage of a raw job).
template <class Src, class Dst>
bool planesToRecords(char* dst, const Src* const* planes, size_t fieldCount, size_t first, size_t count) {
  constexpr double limit = recordRangeLimit(std::is_same_v<Src, float>, std::is_same_v<Dst, double>);
  bool inRange = true;
  for (size_t p = first; p < first + count; ++p) {
    for (size_t f = 0; f < fieldCount; ++f) {
      const Src* s = planes[f] + p * 3;
      for (int k = 0; k < 3; ++k) {  // one store each (a temporary array went through the stack)
        inRange &= std::abs(double(s[k])) <= limit;
        const Dst v = static_cast<Dst>(s[k]);
        std::memcpy(dst, &v, sizeof v);
        dst += sizeof v;
      }
    }
  }
  return inRange;
}

// Points [first, first + count) of structure-of-arrays rows into records of `Dst`.
template <class Dst>
bool rowsToRecords(char* dst, const double* const* rows, size_t fieldCount, size_t first, size_t count) {
  constexpr double limit = recordRangeLimit(false, std::is_same_v<Dst, double>);
  bool inRange = true;
  for (size_t b = first; b < first + count; ++b) {
    for (size_t k = 0; k < 3 * fieldCount; ++k) {
      inRange &= std::abs(rows[k][b]) <= limit;
      const Dst v = static_cast<Dst>(rows[k][b]);
      std::memcpy(dst, &v, sizeof v);
      dst += sizeof v;
    }
  }
  return inRange;
}

#ifdef SHAPESPLINE_RECORDS_AVX2
// 4 values to floats (a conversion for doubles); `bad` collects the lanes above FLT_MAX or NaN.
__attribute__((target("avx2"))) inline __m128 loadChecked(const double* s, __m256& bad) {
  const __m256d limit = _mm256_set1_pd(double(std::numeric_limits<float>::max()));
  const __m256d absMask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffff));
  const __m256d d = _mm256_loadu_pd(s);
  bad = _mm256_or_ps(bad, _mm256_castpd_ps(_mm256_cmp_pd(_mm256_and_pd(d, absMask), limit, _CMP_NLE_UQ)));
  return _mm256_cvtpd_ps(d);
}
__attribute__((target("avx2"))) inline __m128 loadChecked(const float* s, __m256& bad) {
  const __m128 limit = _mm_set1_ps(std::numeric_limits<float>::max());
  const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 v = _mm_loadu_ps(s);
  const __m128 out = _mm_cmp_ps(_mm_and_ps(v, absMask), limit, _CMP_NLE_UQ);
  bad = _mm256_or_ps(bad, _mm256_insertf128_ps(_mm256_setzero_ps(), out, 0));
  return v;
}

// Stores 4 points' (x, y, z, junk) quadruples, point-major, 16 bytes each: the junk float lands on
// the next field or record and is overwritten by that one's store, which comes later since points
// go in order and fields in order within a point (so each caller leaves its last point to the
// scalar loop).
__attribute__((target("avx2"))) inline char* storeQuadruples(char* out, const __m128 (*points)[4], size_t fieldCount,
                                                             size_t recordBytes) {
  for (int k = 0; k < 4; ++k, out += recordBytes)
    for (size_t f = 0; f < fieldCount; ++f) _mm_storeu_ps(reinterpret_cast<float*>(out + f * 12), points[f][k]);
  return out;
}

// fp64 or fp32 planes to fp32 records (GPU chunks, and CPU chunks without a RecordSink, into .f32
// / float .npy), 4 points a step: a field's 12 values of 4 points are 3 loads (and conversions)
// and 4 shifts into (x, y, z, next) quadruples. The range check costs 2 operations per 4 values.
// 2-4x the speed of the loops it replaced (an SSE2 pair loop for fp64, a scalar one for fp32).
// NF as in rowsToFloatAvx2 below.
template <size_t NF, class Src>
__attribute__((target("avx2"))) bool planesToFloatAvx2(char* dst, const Src* const* planes, size_t fieldCount,
                                                       size_t first, size_t count) {
  const size_t nf = NF ? NF : fieldCount;
  __m256 bad = _mm256_setzero_ps();  // a lane's sign bit set: a value out of range
  size_t p = first;
  char* out = dst;
  __m128 points[NF ? NF : kFieldCount][4];
  for (; p + 4 < first + count; p += 4) {
    for (size_t f = 0; f < nf; ++f) {
      const Src* s = planes[f] + p * 3;
      const __m128 a = loadChecked(s, bad), b = loadChecked(s + 4, bad), c = loadChecked(s + 8, bad);
      points[f][0] = a;  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
      points[f][1] = _mm_castsi128_ps(_mm_alignr_epi8(_mm_castps_si128(b), _mm_castps_si128(a), 12));
      points[f][2] = _mm_castsi128_ps(_mm_alignr_epi8(_mm_castps_si128(c), _mm_castps_si128(b), 8));
      points[f][3] = _mm_castsi128_ps(_mm_srli_si128(_mm_castps_si128(c), 4));
    }
    out = storeQuadruples(out, points, nf, nf * 12);
  }
  const bool tail = planesToRecords<Src, float>(out, planes, nf, p, first + count - p);
  return tail && _mm256_movemask_ps(bad) == 0;
}

// fp64 rows to fp32 records, 4 points a step: per field, 4 x, 4 y and 4 z values are 3 loads and
// conversions and one 4x4 transpose (with a zero row) into quadruples. Compiled for 1, 2 and 3
// fields (NF; 0: any count), so that the common records keep their quadruples in registers.
template <size_t NF>
__attribute__((target("avx2"))) bool rowsToFloatAvx2(char* dst, const double* const* rows, size_t fieldCount,
                                                     size_t n) {
  const size_t nf = NF ? NF : fieldCount;
  __m256 bad = _mm256_setzero_ps();
  size_t b = 0;
  char* out = dst;
  __m128 points[NF ? NF : kFieldCount][4];
  for (; b + 4 < n; b += 4) {
    for (size_t f = 0; f < nf; ++f) {
      __m128 x = loadChecked(rows[3 * f] + b, bad), y = loadChecked(rows[3 * f + 1] + b, bad);
      __m128 z = loadChecked(rows[3 * f + 2] + b, bad), w = _mm_setzero_ps();
      _MM_TRANSPOSE4_PS(x, y, z, w);  // now the points: (x0 y0 z0 0), (x1 y1 z1 0), ...
      points[f][0] = x, points[f][1] = y, points[f][2] = z, points[f][3] = w;
    }
    out = storeQuadruples(out, points, nf, nf * 12);
  }
  const bool tail = rowsToRecords<float>(out, rows, nf, b, n - b);
  return tail && _mm256_movemask_ps(bad) == 0;
}

bool hasAvx2() {
  static const bool avx2 = (__builtin_cpu_init(), __builtin_cpu_supports("avx2"));
  return avx2;
}
#endif

template <class Src>
bool planesToFloat(char* dst, const Src* const* planes, size_t fieldCount, size_t first, size_t count) {
#ifdef SHAPESPLINE_RECORDS_AVX2
  if (hasAvx2()) {
    switch (fieldCount) {
      case 1: return planesToFloatAvx2<1>(dst, planes, 1, first, count);
      case 2: return planesToFloatAvx2<2>(dst, planes, 2, first, count);
      case 3: return planesToFloatAvx2<3>(dst, planes, 3, first, count);
      default: return planesToFloatAvx2<0>(dst, planes, fieldCount, first, count);
    }
  }
#endif
  return planesToRecords<Src, float>(dst, planes, fieldCount, first, count);
}

}  // namespace

bool encodeRecords(char* dst, const GridChunk& chunk, const std::vector<Field>& fields, bool float64, size_t first,
                   size_t count) {
  const void* planes[kFieldCount];
  for (size_t f = 0; f < fields.size(); ++f) planes[f] = chunk.planes[static_cast<size_t>(fields[f])];
  const size_t nf = fields.size();
  if (chunk.precision == Precision::Double) {
    const auto* const* src = reinterpret_cast<const double* const*>(planes);
    return float64 ? planesToRecords<double, double>(dst, src, nf, first, count)
                   : planesToFloat(dst, src, nf, first, count);
  }
  const auto* const* src = reinterpret_cast<const float* const*>(planes);
  return float64 ? planesToRecords<float, double>(dst, src, nf, first, count) : planesToFloat(dst, src, nf, first, count);
}

bool encodeRowRecords(char* dst, const double* const* rows, size_t fieldCount, bool float64, size_t n) {
  if (float64) return rowsToRecords<double>(dst, rows, fieldCount, 0, n);
#ifdef SHAPESPLINE_RECORDS_AVX2
  if (hasAvx2()) {
    switch (fieldCount) {
      case 1: return rowsToFloatAvx2<1>(dst, rows, 1, n);
      case 2: return rowsToFloatAvx2<2>(dst, rows, 2, n);
      case 3: return rowsToFloatAvx2<3>(dst, rows, 3, n);
      default: return rowsToFloatAvx2<0>(dst, rows, fieldCount, n);
    }
  }
#endif
  return rowsToRecords<float>(dst, rows, fieldCount, 0, n);
}

}  // namespace shapespline
