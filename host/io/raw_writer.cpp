// Raw little-endian float32/float64 records plus a JSON sidecar. One record per point, points in
// item order, then a (u sample), then b (v sample); a record is every requested field in the
// sidecar's "fields" order, 3 components each (2-D curves carry z = 0). Shards of one job
// concatenate byte for byte into the unsharded file (their sidecars give each item range, and list
// the spans of their own items only).
#include <shapespline/io/raw_records.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>

#include <algorithm>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <atomic>
#include <thread>
#include <bit>
#include <cstring>
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

// Interleaves points [first, first + count) of the field planes into records of `Dst` at `dst`: one
// tight loop per (source, file) precision pair, which the compiler keeps in registers (the
// per-value precision branch of GridChunk::coord made this the slowest stage of a raw job).
template <class Src, class Dst>
void interleave(char* dst, const Src* const* planes, size_t fieldCount, size_t first, size_t count);

#if defined(__SSE2__)
// fp64 planes to fp32 records, the common case (CPU sampler, .f32 / float .npy): x and y of a field
// converted and stored as one pair, 2 stores per field instead of 3 (the stores bound this loop).
template <>
void interleave<double, float>(char* dst, const double* const* planes, size_t fieldCount, size_t first, size_t count) {
  for (size_t p = first; p < first + count; ++p) {
    for (size_t f = 0; f < fieldCount; ++f) {
      const double* s = planes[f] + p * 3;
      _mm_storel_pi(reinterpret_cast<__m64*>(dst), _mm_cvtpd_ps(_mm_loadu_pd(s)));
      _mm_store_ss(reinterpret_cast<float*>(dst + 8), _mm_cvtsd_ss(_mm_setzero_ps(), _mm_load_sd(s + 2)));
      dst += 12;
    }
  }
}
#endif

template <class Src, class Dst>
void interleave(char* dst, const Src* const* planes, size_t fieldCount, size_t first, size_t count) {
  for (size_t p = first; p < first + count; ++p) {
    for (size_t f = 0; f < fieldCount; ++f) {
      const Src* s = planes[f] + p * 3;
      for (int k = 0; k < 3; ++k) {  // one store each (a temporary array went through the stack)
        const Dst v = static_cast<Dst>(s[k]);
        std::memcpy(dst, &v, sizeof v);
        dst += sizeof v;
      }
    }
  }
}

// Calls put(first, count, recordBytes, interleaveInto) over blocks of at most `blockBytes`, with
// interleaveInto(dst) filling that block's records.
template <class Put>
void forEachBlock(const GridChunk& chunk, const std::vector<Field>& fields, bool float64, size_t first, size_t count,
                  size_t blockBytes, Put put) {
  const void* planes[kFieldCount];
  for (size_t f = 0; f < fields.size(); ++f) planes[f] = chunk.planes[static_cast<size_t>(fields[f])];
  const size_t recordBytes = fields.size() * 3 * (float64 ? 8 : 4);
  const size_t block = std::max<size_t>(1, blockBytes / recordBytes);
  for (size_t b = first; b < first + count; b += block) {
    const size_t n = std::min(block, first + count - b);
    put(b, n, recordBytes, [&](char* dst) {
      const size_t nf = fields.size();
      if (chunk.precision == Precision::Double) {
        const auto* const* src = reinterpret_cast<const double* const*>(planes);
        float64 ? interleave<double, double>(dst, src, nf, b, n) : interleave<double, float>(dst, src, nf, b, n);
      } else {
        const auto* const* src = reinterpret_cast<const float* const*>(planes);
        float64 ? interleave<float, double>(dst, src, nf, b, n) : interleave<float, float>(dst, src, nf, b, n);
      }
    });
  }
}

}  // namespace

void writeRecords(AtomicFile& out, const GridChunk& chunk, const std::vector<Field>& fields, bool float64) {
  forEachBlock(chunk, fields, float64, 0, chunk.pointCount(), AtomicFile::kMaxSpace,
               [&](size_t, size_t n, size_t recordBytes, const auto& fill) {
                 fill(out.space(n * recordBytes));
                 out.advance(n * recordBytes);
               });
}

void writeRecordsAt(BlockWriter& out, uint64_t offset, const GridChunk& chunk, size_t first, size_t count,
                    const std::vector<Field>& fields, bool float64) {
  forEachBlock(chunk, fields, float64, first, count, out.blockBytes(),
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

void PlacedRecords::slice(const GridChunk& chunk, size_t first, size_t count) {
  sliced_.store(true, std::memory_order_relaxed);
  writeRecordsAt(*writer_, offsetOf(chunk, first), chunk, first, count, fields_, float64_);
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

  void writeSlice(const GridChunk& chunk, size_t first, size_t count) override { placed_.slice(chunk, first, count); }
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
