// Raw little-endian float32/float64 records plus a JSON sidecar. One record per point, points in
// item order, then a (u sample), then b (v sample); a record is every requested field in the
// sidecar's "fields" order, 3 components each (2-D curves carry z = 0). Shards of one job
// concatenate byte for byte into the unsharded file (their sidecars give each item range, and list
// the spans of their own items only).
#include <shapespline/io/raw_records.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>

#include <bit>
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

void writeRecords(AtomicFile& out, const GridChunk& chunk, const std::vector<Field>& fields, bool float64) {
  const size_t n = chunk.pointCount();
  for (size_t p = 0; p < n; ++p) {
    char* e = out.space(fields.size() * 24);
    const char* s = e;
    for (Field f : fields) {
      for (int ax = 0; ax < 3; ++ax) e = putBinaryValue(e, chunk.coord(f, p, ax), float64);
    }
    out.advance(static_cast<size_t>(e - s));
  }
}

namespace {

class RawWriter final : public SampleWriter {
 public:
  RawWriter(AtomicFile& out, AtomicFile& sidecar, Precision filePrecision)
      : out_(out), sidecar_(sidecar), precision_(filePrecision) {}

  void begin(const SampleLayout& layout) override {
    layout_ = layout;
    fields_ = recordFields(layout.fields);
  }

  void consume(const GridChunk& chunk) override { writeRecords(out_, chunk, fields_, precision_ == Precision::Double); }

  // The sidecar describes this file's own items only (io/shard_info.h), so its size follows the
  // shard, not the model; `merge` rebuilds the unsharded job's sidecar from the shards'.
  void finish() override {
    writeRawSidecar(sidecar_, rawSidecarOf(layout_, layout_.job, precision_ == Precision::Double,
                                           out_.target().filename().string()));
  }

 private:
  AtomicFile& out_;
  AtomicFile& sidecar_;
  Precision precision_;
  SampleLayout layout_;
  std::vector<Field> fields_;
};

}  // namespace

std::unique_ptr<SampleWriter> makeRawWriter(AtomicFile& out, AtomicFile& sidecar, Precision filePrecision) {
  return std::make_unique<RawWriter>(out, sidecar, filePrecision);
}

}  // namespace shapespline::io
