#pragma once
// Point clouds of a trimmed face (`sample --trim`, docs/cad.md): of a grid job's samples, only those
// whose knot parameters (U, V) lie inside the model's trim loops (core/trim_classifier.h), each
// written with its (U, V) before the requested fields. The chunks may come from the CPU or the GPU:
// the choice is made on the parameters alone, so both paths keep the same samples. The count is
// known before the first chunk (the classifier runs over the job's parameters in begin()), so
// every header is written up front and memory stays bounded.
//
// Formats: .npy (a structured array: 'uv' (2,), then one (3,) field per requested field), .f32 /
// .f64 (the same records, raw, with the OUT.json sidecar describing them), CSV (U, V, then x y z of
// each field) and PLY (a binary point cloud: x y z of the point, nx ny nz of the normal, u v, then
// the other fields' NAME_x NAME_y NAME_z; no faces). Meshes of trimmed faces are not written.
#include <shapespline/core/model.h>
#include <shapespline/core/trim_classifier.h>
#include <shapespline/io/sample_writer.h>

#include <nlohmann/json.hpp>

#include <optional>
#include <string_view>
#include <vector>

namespace shapespline::io {

bool trimmedPointFormat(OutputFormat format);
// The formats a trimmed job shards to: those that carry the shard's identity (not CSV).
bool trimmedShardFormat(OutputFormat format);

// The samples of each of a job's items inside `trim`, in item order (what begin() counts, without
// sampling anything).
std::vector<uint64_t> samplesInsideByItem(const SampleLayout& layout, const TrimLoops& trim);

// One shard of a trimmed job (docs/cluster.md "Trimmed faces and parts"): a run of the job's items
// (a part's items are its faces' items, face after face) and the records (samples inside the trim
// loops) they hold. Written into the shard's raw sidecar as "shard" and into its PLY header as a
// "comment shard: " line; `merge` joins shards whose runs follow each other from the first item
// and record to the last.
struct TrimmedShard {
  std::string job;  // io/shard_info.h trimmedJobFingerprint or partJobFingerprint
  int index = 1, count = 1;
  uint64_t firstItem = 0, items = 0, totalItems = 0;
  uint64_t firstRecord = 0, records = 0, totalRecords = 0;

  nlohmann::json toJson() const;
  // The inverse of toJson for a value read back: nullopt unless it is exactly such an object with
  // consistent numbers (1 <= index <= count, runs within their totals).
  static std::optional<TrimmedShard> fromJson(const nlohmann::json& j);
};
inline constexpr std::string_view kTrimmedShardComment = "comment shard: ";

// Shard k of n of a job whose items keep `kept[i]` records: the items cut where the records before
// the cut first reach (k-1)/n and k/n of all of them, so that shards hold about the same number of
// records whatever the sizes of the faces (within one item's records); by item count when no item
// keeps any. `job`, `index` and `count` are left to the caller.
TrimmedShard balancedTrimmedShard(const std::vector<uint64_t>& kept, int k, int n);

class TrimmedPointWriter final : public SampleWriter {
 public:
  // One face: `sidecar` is the OUT.json of .f32/.f64/.npy (may be null for .npy).
  TrimmedPointWriter(OutputFormat format, AtomicFile& out, AtomicFile* sidecar, const TrimLoops& trim);
  // A whole part (`sample part.json`): every record also carries its face's id (a `face` column).
  // beginPart() writes the header for `total` records (the sum of samplesInsideByItem over the faces);
  // then each face's job is nextFace() and its chunks; finish() after the last.
  TrimmedPointWriter(OutputFormat format, AtomicFile& out, AtomicFile* sidecar);
  // `part`: what the header comments and the sidecar say of the part instead of one model's job
  // metadata (the manifest's name and SHA-256, the faces).
  // `gridPoints`: the grid samples of every face's items (of the whole job, also in a shard).
  void beginPart(const SampleLayout& anyFace, uint64_t total, uint64_t gridPoints, const nlohmann::json& part);
  // A shard's identity, given before begin() / beginPart().
  void setShard(const TrimmedShard& shard) { shard_ = shard; }
  void nextFace(const SampleLayout& layout, const TrimLoops& trim, int faceId);

  void begin(const SampleLayout& layout) override;
  void consume(const GridChunk& chunk) override;
  void finish() override;

  uint64_t kept() const { return kept_; }  // records the file holds (after begin() / beginPart())

 private:
  // One column of a record: the sample's (U, V), its face id, or a field's x y z.
  struct Column {
    enum Kind { Uv, Face, Vector } kind;
    Field field = Field::Point;
  };
  void setLayout(const SampleLayout& layout);  // and the fields and file precision it implies
  static std::string columnName(const Column& c);
  static int columnWidth(const Column& c);
  void header(bool withFace);
  void appendRecord(const GridChunk& chunk, size_t p, std::pair<double, double> uv);
  void flush();

  OutputFormat format_;
  AtomicFile& out_;
  AtomicFile* sidecar_;
  TrimLoops trim_;  // of the face being written
  TrimClassifier classifier_;
  int faceId_ = 0;
  SampleLayout layout_;
  std::vector<Field> fields_;
  std::vector<Column> columns_;
  bool float64_ = true;
  uint64_t kept_ = 0, written_ = 0;
  uint64_t gridPoints_ = 0;             // of the whole job, for the sidecar
  std::optional<TrimmedShard> shard_;
  nlohmann::json part_;  // a part's description (null for one face)
  std::string buffer_;
};

}  // namespace shapespline::io
