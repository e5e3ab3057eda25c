// Raw little-endian float32/float64 records plus a JSON sidecar. One record per point, points in
// item order, then a (u sample), then b (v sample); a record is every requested field in the
// sidecar's "fields" order, 3 components each (2-D curves carry z = 0). Shards of one job
// concatenate byte for byte into the unsharded file (their sidecars give each item range).
#include "io/sample_writer.h"

#include <nlohmann/json.hpp>

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

  void finish() override {
    nlohmann::ordered_json j;
    j["format"] = "shapespline-raw";
    j["format_version"] = 1;
    j["data_file"] = out_.target().filename().string();
    j["dtype"] = precision_ == Precision::Double ? "float64" : "float32";
    j["byte_order"] = "little";
    j["kind"] = layout_.surface ? "surface" : "curve";
    j["item"] = layout_.surface ? "patch" : "span";
    nlohmann::ordered_json names = nlohmann::ordered_json::array();
    for (Field f : fields_) names.push_back(fieldName(f));
    j["fields"] = names;
    j["components"] = 3;
    j["values_per_record"] = fields_.size() * 3;
    j["order"] = layout_.surface ? "item, then u sample a, then v sample b; record = fields in order, xyz each"
                                 : "item (span), then sample s; record = fields in order, xyz each";
    j["grid"] = {{"samples_u", layout_.samplesU}, {"samples_v", layout_.samplesV},
                 {"points_per_item", layout_.pointsPerItem()},
                 {"local_parameters", "s/(S-1), both ends included"}};
    j["counts"] = {{"items", layout_.itemCount}, {"points", layout_.pointCount()},
                   {"values", layout_.pointCount() * fields_.size() * 3},
                   {"bytes", layout_.pointCount() * fields_.size() * 3 * (precision_ == Precision::Double ? 8 : 4)}};
    j["items"] = {{"first", layout_.firstItem}, {"count", layout_.itemCount}, {"total", layout_.totalItems},
                  {"items_v", layout_.itemsV}, {"spans_u", layout_.spanU}, {"spans_v", layout_.spanV},
                  {"mapping", layout_.surface ? "item k (0-based over the whole model) is patch (spans_u[k / items_v], spans_v[k % items_v])"
                                              : "item k (0-based over the whole model) is span spans_u[k]"}};
    j["shard"] = {{"index", layout_.shardIndex}, {"count", layout_.shardCount}};
    j["computed_precision"] = layout_.precision == Precision::Double ? "double" : "float";
    j["source"] = layout_.source;
    sidecar_.write(j.dump(2));
    sidecar_.write("\n");
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
