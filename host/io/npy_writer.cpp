// NumPy .npy (format 1.0, NEP 1): a structured array of shape (points,) whose fields are the
// sampled fields by name, each ('<f4' or '<f8', (3,)), so the data after the header is exactly the
// raw .f32/.f64 file of the same job (io/raw_records.h) and numpy.load(mmap_mode="r") maps it.
// The shape follows from the grid, so the header is written first and the records stream. Beside
// every .npy the command line writes the raw sidecar OUT.npy.json (the job metadata, and for a
// shard the job, shard and item range, none of which a .npy header can hold); `merge` rebuilds the
// unsharded .npy byte for byte, and its sidecar but for the data_file name.
#include <shapespline/io/raw_records.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>

#include <cstring>
#include <limits>
#include <stdexcept>

namespace shapespline::io {

namespace {

// Magic, version 1.0, length, then `dict` padded with spaces and a newline.
std::string npyHeaderOf(std::string dict) {
  // magic (6) + version (2) + length (2) + dict + padding + '\n' = a multiple of 64 (NEP 1).
  const size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  if (dict.size() > std::numeric_limits<uint16_t>::max()) throw std::logic_error(".npy header exceeds version 1.0");
  const uint16_t len = static_cast<uint16_t>(dict.size());
  std::string h("\x93NUMPY\x01\x00", 8);
  h += static_cast<char>(len & 0xff);
  h += static_cast<char>(len >> 8);
  return h + dict;
}

}  // namespace

std::string npyHeader(const std::vector<std::string>& fieldNames, bool float64, uint64_t records) {
  std::vector<std::pair<std::string, int>> fields;
  for (const std::string& name : fieldNames) fields.emplace_back(name, 3);
  return npyHeader(fields, float64, records);
}

std::string npyHeader(const std::vector<std::pair<std::string, int>>& fields, bool float64, uint64_t records) {
  std::string dict = "{'descr': [";
  for (size_t k = 0; k < fields.size(); ++k) {
    dict += (k ? ", ('" : "('") + fields[k].first + (float64 ? "', '<f8', (" : "', '<f4', (") +
            std::to_string(fields[k].second) + ",))";
  }
  dict += "], 'fortran_order': False, 'shape': (" + std::to_string(records) + ",), }";
  return npyHeaderOf(std::move(dict));
}

std::string npyArrayHeader(const std::vector<uint64_t>& shape) {
  std::string dims;
  for (size_t k = 0; k < shape.size(); ++k) dims += (k ? ", " : "") + std::to_string(shape[k]);
  if (shape.size() == 1) dims += ",";
  return npyHeaderOf("{'descr': '<f8', 'fortran_order': False, 'shape': (" + dims + "), }");
}

namespace {

class NpyWriter final : public SampleWriter {
 public:
  NpyWriter(AtomicFile& out, AtomicFile* sidecar) : out_(out), sidecar_(sidecar) {}

  void begin(const SampleLayout& layout) override {
    if (layout.sharded() && !sidecar_) throw std::logic_error("a .npy shard needs its sidecar");
    layout_ = layout;
    fields_ = recordFields(layout.fields);
    std::vector<std::string> names;
    for (Field f : fields_) names.emplace_back(fieldName(f));
    const std::string header = npyHeader(names, float64(), layout.pointCount());
    out_.write(header);
    placed_.begin(out_, layout_, fields_, float64(), header.size());  // the records follow the header
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

  void finish() override {
    placed_.finish();
    if (sidecar_) {
      writeRawSidecar(*sidecar_, rawSidecarOf(layout_, layout_.job, float64(), out_.target().filename().string()));
    }
  }

 private:
  bool float64() const { return layout_.precision == Precision::Double; }
  AtomicFile& out_;
  AtomicFile* sidecar_;
  SampleLayout layout_;
  std::vector<Field> fields_;
  PlacedRecords placed_;
};

}  // namespace

std::unique_ptr<SampleWriter> makeNpyWriter(AtomicFile& out, AtomicFile* sidecar) {
  return std::make_unique<NpyWriter>(out, sidecar);
}

}  // namespace shapespline::io
