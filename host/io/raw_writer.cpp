// Raw little-endian float32/float64 records plus a JSON sidecar. One record per point, points in
// item order, then a (u sample), then b (v sample); a record is every requested field in the
// sidecar's "fields" order, 3 components each (2-D curves carry z = 0). Shards of one job
// concatenate byte for byte into the unsharded file (their sidecars give each item range, and list
// the spans of their own items only).
#include <shapespline/io/raw_records.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>

#include <algorithm>
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif
#include <atomic>
#include <thread>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

namespace shapespline::io {

static_assert(std::endian::native == std::endian::little, "the raw/.npy writers assume a little-endian host");

std::vector<Field> recordFields(FieldMask mask) {
  std::vector<Field> fields;
  for (int f = 0; f < kFieldCount; ++f) {
    if (mask & fieldBit(static_cast<Field>(f))) fields.push_back(static_cast<Field>(f));
  }
  return fields;
}

namespace {

// The largest magnitude a value may have: a file of fp32 values or fp32 planes hold at most
// FLT_MAX, fp64 ones any finite value (cli requireFinite's rule, checked here as the values pass).
template <class Src, class Dst>
constexpr double rangeLimit() {
  return std::is_same_v<Src, float> || std::is_same_v<Dst, float> ? double(std::numeric_limits<float>::max())
                                                                   : std::numeric_limits<double>::max();
}

// Interleaves points [first, first + count) of the field planes into records of `Dst` at `dst`,
// and tells whether every value lies within rangeLimit (NaN does not): one tight loop per
// (source, file) precision pair, which the compiler keeps in registers (the per-value precision
// branch of GridChunk::coord made this the slowest stage of a raw job).
template <class Src, class Dst>
bool interleave(char* dst, const Src* const* planes, size_t fieldCount, size_t first, size_t count) {
  constexpr double limit = rangeLimit<Src, Dst>();
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

#if defined(__x86_64__) && defined(__GNUC__)
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

// fp64 or fp32 planes to fp32 records (the CPU sampler's and the GPU's chunks into .f32 / float
// .npy), 4 points a step with AVX2: a field's 12 values of 4 points are 3 loads (and conversions)
// and 4 shifts into (x, y, z, next) quadruples, each stored as 16 bytes; the 4th float lands on
// the next field or record and is overwritten by its own store, which comes later since points go
// in order and fields in order within a point (so the last point of the range is left to the
// scalar loop). The range check costs 2 operations per 4 values. 2-4x the speed of the loops it
// replaced (an SSE2 pair loop for fp64, a scalar one for fp32).
template <class Src>
__attribute__((target("avx2"))) bool interleaveToFloatAvx2(char* dst, const Src* const* planes, size_t fieldCount,
                                                           size_t first, size_t count) {
  const size_t recordBytes = fieldCount * 12;
  __m256 bad = _mm256_setzero_ps();  // a lane's sign bit set: a value out of range
  size_t p = first;
  char* out = dst;
  __m128 points[kFieldCount][4];
  for (; p + 4 < first + count; p += 4) {
    for (size_t f = 0; f < fieldCount; ++f) {
      const Src* s = planes[f] + p * 3;
      const __m128 a = loadChecked(s, bad), b = loadChecked(s + 4, bad), c = loadChecked(s + 8, bad);
      points[f][0] = a;  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
      points[f][1] = _mm_castsi128_ps(_mm_alignr_epi8(_mm_castps_si128(b), _mm_castps_si128(a), 12));
      points[f][2] = _mm_castsi128_ps(_mm_alignr_epi8(_mm_castps_si128(c), _mm_castps_si128(b), 8));
      points[f][3] = _mm_castsi128_ps(_mm_srli_si128(_mm_castps_si128(c), 4));
    }
    for (int k = 0; k < 4; ++k, out += recordBytes)
      for (size_t f = 0; f < fieldCount; ++f) _mm_storeu_ps(reinterpret_cast<float*>(out + f * 12), points[f][k]);
  }
  const bool tail = interleave<Src, float>(out, planes, fieldCount, p, first + count - p);
  return tail && _mm256_movemask_ps(bad) == 0;
}
#endif

template <class Src>
bool interleaveToFloat(char* dst, const Src* const* planes, size_t fieldCount, size_t first, size_t count) {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2) return interleaveToFloatAvx2(dst, planes, fieldCount, first, count);
#endif
  return interleave<Src, float>(dst, planes, fieldCount, first, count);
}

// Calls put(first, count, recordBytes, interleaveInto) over blocks of at most `blockBytes`, with
// interleaveInto(dst) filling that block's records and telling whether its values are in range;
// returns whether all were.
template <class Put>
bool forEachBlock(const GridChunk& chunk, const std::vector<Field>& fields, bool float64, size_t first, size_t count,
                  size_t blockBytes, Put put) {
  const void* planes[kFieldCount];
  for (size_t f = 0; f < fields.size(); ++f) planes[f] = chunk.planes[static_cast<size_t>(fields[f])];
  const size_t recordBytes = fields.size() * 3 * (float64 ? 8 : 4);
  const size_t block = std::max<size_t>(1, blockBytes / recordBytes);
  bool inRange = true;
  for (size_t b = first; b < first + count; b += block) {
    const size_t n = std::min(block, first + count - b);
    put(b, n, recordBytes, [&](char* dst) {
      const size_t nf = fields.size();
      bool ok;
      if (chunk.precision == Precision::Double) {
        const auto* const* src = reinterpret_cast<const double* const*>(planes);
        ok = float64 ? interleave<double, double>(dst, src, nf, b, n) : interleaveToFloat(dst, src, nf, b, n);
      } else {
        const auto* const* src = reinterpret_cast<const float* const*>(planes);
        ok = float64 ? interleave<float, double>(dst, src, nf, b, n) : interleaveToFloat(dst, src, nf, b, n);
      }
      inRange &= ok;
    });
  }
  return inRange;
}

}  // namespace

void writeRecords(AtomicFile& out, const GridChunk& chunk, const std::vector<Field>& fields, bool float64) {
  forEachBlock(chunk, fields, float64, 0, chunk.pointCount(), AtomicFile::kMaxSpace,
               [&](size_t, size_t n, size_t recordBytes, const auto& fill) {
                 fill(out.space(n * recordBytes));
                 out.advance(n * recordBytes);
               });
}

bool writeRecordsAt(BlockWriter& out, uint64_t offset, const GridChunk& chunk, size_t first, size_t count,
                    const std::vector<Field>& fields, bool float64) {
  return forEachBlock(chunk, fields, float64, first, count, out.blockBytes(),
               [&](size_t b, size_t n, size_t recordBytes, const auto& fill) {
                 const BlockWriter::Block block = out.acquire();
                 fill(block.data);
                 out.submit(block, offset + (b - first) * recordBytes, n * recordBytes);
               });
}

// 1 MiB blocks, four per core: enough for the workers to fill blocks while one is being written.
constexpr size_t kBlockBytes = size_t{1} << 20;

void PlacedRecords::begin(AtomicFile& out, const SampleLayout& layout, const std::vector<Field>& fields, bool float64,
                          uint64_t base) {
  layout_ = &layout;
  fields_ = fields;
  float64_ = float64;
  base_ = base;
  recordBytes_ = fields.size() * 3 * (float64 ? 8 : 4);
  const size_t blocks = 4 * std::max<size_t>(1, std::thread::hardware_concurrency());
  writer_ = std::make_unique<BlockWriter>(out, std::max(kBlockBytes, recordBytes_), blocks);
  sliced_ = false;
}

PlacedRecords::~PlacedRecords() = default;

uint64_t PlacedRecords::offsetOf(const GridChunk& chunk, size_t first) const {
  const uint64_t point = (chunk.firstItem - layout_->firstItem) * layout_->pointsPerItem() + chunk.firstItemPoint() + first;
  return base_ + point * recordBytes_;
}

bool PlacedRecords::slice(const GridChunk& chunk, size_t first, size_t count) {
  sliced_.store(true, std::memory_order_relaxed);
  return writeRecordsAt(*writer_, offsetOf(chunk, first), chunk, first, count, fields_, float64_);
}

void PlacedRecords::consume(const GridChunk& chunk) {
  if (!sliced_.load(std::memory_order_relaxed)) {
    writeRecordsAt(*writer_, offsetOf(chunk, 0), chunk, 0, chunk.pointCount(), fields_, float64_);
  }
}

void PlacedRecords::finish() { writer_->finish(); }

namespace {

class RawWriter final : public SampleWriter {
 public:
  RawWriter(AtomicFile& out, AtomicFile& sidecar, Precision filePrecision)
      : out_(out), sidecar_(sidecar), precision_(filePrecision) {}

  void begin(const SampleLayout& layout) override {
    layout_ = layout;
    fields_ = recordFields(layout.fields);
    placed_.begin(out_, layout_, fields_, precision_ == Precision::Double, 0);
  }

  bool writeSlice(const GridChunk& chunk, size_t first, size_t count) override {
    return placed_.slice(chunk, first, count);
  }
  void consume(const GridChunk& chunk) override { placed_.consume(chunk); }

  // The sidecar describes this file's own items only (io/shard_info.h), so its size follows the
  // shard, not the model; `merge` rebuilds the unsharded job's sidecar from the shards'.
  void finish() override {
    placed_.finish();
    writeRawSidecar(sidecar_, rawSidecarOf(layout_, layout_.job, precision_ == Precision::Double,
                                           out_.target().filename().string()));
  }

 private:
  AtomicFile& out_;
  AtomicFile& sidecar_;
  Precision precision_;
  SampleLayout layout_;
  PlacedRecords placed_;
  std::vector<Field> fields_;
};

}  // namespace

std::unique_ptr<SampleWriter> makeRawWriter(AtomicFile& out, AtomicFile& sidecar, Precision filePrecision) {
  return std::make_unique<RawWriter>(out, sidecar, filePrecision);
}

}  // namespace shapespline::io
