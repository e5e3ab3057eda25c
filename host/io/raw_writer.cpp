// Raw little-endian float32/float64 records plus a JSON sidecar. One record per point, points in
// item order, then a (u sample), then b (v sample); a record is every requested field in the
// sidecar's "fields" order, 3 components each (2-D curves carry z = 0). Shards of one job
// concatenate byte for byte into the unsharded file (their sidecars give each item range, and list
// the spans of their own items only).
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>

#include <bit>
#include <cstring>
#include <vector>

namespace shapespline::io {
namespace {

class RawWriter final : public SampleWriter {
 public:
  RawWriter(AtomicFile& out, AtomicFile& sidecar, Precision filePrecision)
      : out_(out), sidecar_(sidecar), precision_(filePrecision) {}

  void begin(const SampleLayout& layout) override {
    layout_ = layout;
    for (int f = 0; f < kFieldCount; ++f) {
      if (layout.fields & fieldBit(static_cast<Field>(f))) fields_.push_back(static_cast<Field>(f));
    }
  }

  void consume(const GridChunk& chunk) override {
    const bool dbl = precision_ == Precision::Double;
    const size_t n = chunk.pointCount();
    for (size_t p = 0; p < n; ++p) {
      char* e = out_.space(fields_.size() * 24);
      const char* s = e;
      for (Field f : fields_) {
        for (int ax = 0; ax < 3; ++ax) {
          const double v = chunk.coord(f, p, ax);
          if (dbl) {
            std::memcpy(e, &v, 8);
            e += 8;
          } else {
            const float x = static_cast<float>(v);
            std::memcpy(e, &x, 4);
            e += 4;
          }
        }
      }
      out_.advance(static_cast<size_t>(e - s));
    }
  }

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
