// Raw little-endian float32/float64 records plus a JSON sidecar. One record per point, points in
// item order, then a (u sample), then b (v sample); a record is every requested field in the
// sidecar's "fields" order, 3 components each (2-D curves carry z = 0). Shards of one job
// concatenate byte for byte into the unsharded file (their sidecars give each item range, and list
// the spans of their own items only).
#include <shapespline/core/cores.h>
#include <shapespline/io/raw_records.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>

#include <algorithm>
#include <bit>
#include <optional>
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

// 1 MiB blocks, four per core: enough for the workers to fill blocks while one is being written.
// A smaller job gets blocks of its own size (one of a batch of small models allocated and faulted
// in 8 MiB for 300 KB of records), written on the sampler's thread: a writer thread for one block
// overlaps nothing and costs its start and wake-ups (docs/performance.md, batches).
constexpr size_t kBlockBytes = size_t{1} << 20;

void PlacedRecords::begin(AtomicFile& out, const SampleLayout& layout, const std::vector<Field>& fields, bool float64,
                          uint64_t base) {
  layout_ = &layout;
  fields_ = fields;
  float64_ = float64;
  base_ = base;
  recordBytes_ = recordBytes(fields.size(), float64);
  const size_t blocks = 4 * static_cast<size_t>(availableCores());
  const uint64_t jobBytes = layout.pointCount() * recordBytes_;
  const size_t blockBytes = static_cast<size_t>(std::min<uint64_t>(kBlockBytes, jobBytes));
  writer_ = std::make_unique<BlockWriter>(out, std::max(blockBytes, recordBytes_), blocks,
                                          jobBytes > kBlockBytes ? BlockWriter::Writes::OnOwnThread
                                                                 : BlockWriter::Writes::OnCaller);
  written_ = false;
}

PlacedRecords::~PlacedRecords() = default;

uint64_t PlacedRecords::offsetOf(const GridChunk& chunk, size_t first) const {
  const uint64_t point = (chunk.firstItem - layout_->firstItem) * layout_->pointsPerItem() + chunk.firstItemPoint() + first;
  return base_ + point * recordBytes_;
}

bool PlacedRecords::writeAt(const GridChunk& chunk, size_t first, size_t count) {
  const size_t perBlock = writer_->blockBytes() / recordBytes_;
  bool inRange = true;
  for (size_t b = first; b < first + count; b += perBlock) {
    const size_t n = std::min(perBlock, first + count - b);
    const BlockWriter::Block block = writer_->acquire();
    inRange &= encodeRecords(block.data, chunk, fields_, float64_, b, n);
    writer_->submit(block, offsetOf(chunk, b), n * recordBytes_);
  }
  return inRange;
}

bool PlacedRecords::slice(const GridChunk& chunk, size_t first, size_t count) {
  written_.store(true, std::memory_order_relaxed);
  return writeAt(chunk, first, count);
}

void PlacedRecords::consume(const GridChunk& chunk) {
  if (!written_.load(std::memory_order_relaxed)) writeAt(chunk, 0, chunk.pointCount());
}

RecordSink PlacedRecords::sink() {
  RecordSink s;
  s.fields = fields_;
  s.float64 = float64_;
  s.maxPoints = writer_->blockBytes() / recordBytes_;
  s.ownThreads = writer_->ownThread() ? 1 : 0;  // the BlockWriter's
  s.acquire = [this] {
    written_.store(true, std::memory_order_relaxed);
    const BlockWriter::Block block = writer_->acquire();
    return RecordBlock{block.data, block.index};
  };
  s.submit = [this](RecordBlock block, const GridChunk& chunk, size_t first, size_t count) {
    writer_->submit({block.data, block.token}, offsetOf(chunk, first), count * recordBytes_);
  };
  return s;
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
  void setIdentity(const std::string& job, const JobMetadata& metadata) override {
    layout_.job = job;
    layout_.metadata = metadata;
  }
  void consume(const GridChunk& chunk) override { placed_.consume(chunk); }
  std::optional<RecordSink> recordSink() override { return placed_.sink(); }

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
