#pragma once
// What every output of `sample` says about the job it belongs to, so that `merge` (jobs/merge.h) can
// verify the shards it joins: a job fingerprint (64-bit FNV-1a, http://www.isthe.com/chongo/tech/
// comp/fnv/, over the sampled model's data, the grid, the fields, the precision and the format),
// the shard K of N and its item range. Written as one text line into PLY `comment` and OBJ `#`
// headers, and as JSON keys into the raw sidecar; CSV stays plain (see jobs/merge.h).
#include <shapespline/core/model.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/text_escape.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace shapespline::io {

// The bounds of every job line, raw sidecar and shard record: shards 1 <= K <= N <= kMaxShardCount,
// item numbers and counts up to kMaxItemCount (below 2^62, so that products with small factors
// and sums of two stay in 64 bits).
inline constexpr uint64_t kMaxShardCount = 1'000'000'000;
inline constexpr uint64_t kMaxItemCount = (uint64_t{1} << 62) - 1;

// The first item of shard k + 1 of n of a job of `total` items (k = 0..n; shard K covers
// shardBound(T, K-1, N) .. shardBound(T, K, N)): floor(k T / N), computed as (T / N) k + floor((T % N) k / N),
// since T times k would overflow (T <= kMaxItemCount, k <= N <= kMaxShardCount).
inline uint64_t shardBound(uint64_t total, uint64_t k, uint64_t n) { return total / n * k + total % n * k / n; }

// 16 lowercase hex digits. Equal for every shard of one job (and the unsharded job), different when
// the model, samples per item, fields, computed precision or output format differ.
std::string jobFingerprint(const CurveModel& model, const SampleLayout& layout, OutputFormat format);
std::string jobFingerprint(const Surface& surface, const SampleLayout& layout, OutputFormat format);

// A trimmed job's fingerprint (`sample --trim`, `sample part.json`): the fingerprint of the face's
// grid job (above) and its trim loops; a part's, the ordered (face id, trimmed fingerprint) of its
// faces. Shards of one trimmed job, and only they, carry the same one.
std::string trimmedJobFingerprint(const std::string& faceJob, const TrimLoops& trim);
std::string partJobFingerprint(const std::vector<std::pair<int, std::string>>& faces);

// The fingerprint's word hash of an array given in pieces: the same value as the whole array at
// once (jobFingerprint hashes 10^8 values without holding them twice, or at all when streamed).
class FingerprintWords {
 public:
  void begin(uint64_t hash);
  void add(const unsigned char* words, size_t count);  // `count` 8-byte words
  uint64_t end(uint64_t hash) const;

 private:
  static uint64_t mix(uint64_t h, uint64_t w) {
    h ^= w;
    h *= 1099511628211ull;
    return h ^ (h >> 32);
  }
  uint64_t lane_[4] = {}, carry_[4] = {};
  int carried_ = 0;
};

// A job fingerprint taken from a net's points in model order given in runs of any length, then its
// α likewise, then its weights, then finish(): a net read a run at a time from its files has the
// fingerprint of the built model (the streams of io/streamed_bands.h feed either kind). The α and
// weight phases are the same for curves and surfaces; the head and the points' words are each's.
class NetFingerprint {
 public:
  virtual ~NetFingerprint() = default;
  virtual void points(const glm::dvec3* points, size_t count) = 0;
  void alphas(const double* values, size_t count);
  void weights(const double* values, size_t count);
  std::string finish();

 protected:
  NetFingerprint(size_t alphaCount, size_t weightCount) : alphaCount_(alphaCount), weightCount_(weightCount) {}
  // The hash once every point is in, and that hash with the model's knots.
  virtual uint64_t afterPoints() const = 0;
  virtual uint64_t withKnots(uint64_t hash) const = 0;
  uint64_t hash_ = 0;
  FingerprintWords words_;

 private:
  enum class Phase { Points, Alpha, Weights };
  size_t alphaCount_ = 0, weightCount_ = 0;
  Phase phase_ = Phase::Points;
};

// jobFingerprint(model, ...) of a curve of shape `shape` (its own points, α and weights not read)
// with `pointCount` points, `alphaCount` α values and `weightCount` weights. `shape` is kept by
// reference.
class CurveFingerprint final : public NetFingerprint {
 public:
  CurveFingerprint(const CurveModel& shape, size_t pointCount, size_t alphaCount, size_t weightCount,
                   const SampleLayout& layout, OutputFormat format);
  void points(const glm::dvec3* points, size_t count) override;

 private:
  uint64_t afterPoints() const override { return words_.end(hash_); }
  uint64_t withKnots(uint64_t hash) const override;
  const CurveModel& shape_;
};

// jobFingerprint(surface, ...) of a surface of shape `shape` (its own α not read) with
// `alphaCount` α values and `weightCount` weights. `shape` is kept by reference.
class SurfaceFingerprint final : public NetFingerprint {
 public:
  SurfaceFingerprint(const SurfaceShape& shape, size_t alphaCount, size_t weightCount, const SampleLayout& layout,
                     OutputFormat format);
  void points(const glm::dvec3* points, size_t count) override;

 private:
  uint64_t afterPoints() const override { return hash_; }  // each row ends its own words
  uint64_t withKnots(uint64_t hash) const override;
  const SurfaceShape& shape_;
  size_t rowDone_ = 0;  // points of the current row hashed
};

struct ShardInfo {
  std::string job;                    // jobFingerprint
  bool surface = false;
  int shardIndex = 1, shardCount = 1; // K of N
  uint64_t firstItem = 0, itemCount = 0, totalItems = 0;
  int samplesU = 2, samplesV = 1;

  uint64_t endItem() const { return firstItem + itemCount; }
  uint64_t pointsPerItem() const { return static_cast<uint64_t>(samplesU) * static_cast<uint64_t>(samplesV); }
};

ShardInfo shardInfoOf(const SampleLayout& layout);
// The unsharded job of a shard: shard 1/1, items 0..T of T.
ShardInfo wholeJobOf(const ShardInfo& shard);

// "shapespline job <hex> <curve|surface> shard K/N items F..E of T grid UxV" (no newline).
std::string shardInfoLine(const ShardInfo& info);
// The inverse of shardInfoLine; nullopt unless `line` is exactly such a line with consistent
// numbers (1 <= K <= N <= 10^9, F <= E <= T < 2^62, 2 <= U, V <= 65536 (V = 1 for curves)).
std::optional<ShardInfo> parseShardInfoLine(std::string_view line);

// Header lines naming the source and the job, shared by the writers and `merge` so that a merged
// file is byte-identical to the unsharded one. `escapedSource` is escapeText(model path).
std::string plyInfoComments(const ShardInfo& info, std::string_view escapedSource);
// `welded`: absolute indices in a shard too (welded shards are merged, not concatenated).
std::string objHeader(const ShardInfo& info, std::string_view escapedSource, bool welded);
// A welded mesh file (io/welded_mesh.h) also carries its grid of items, closed directions and
// orientation on the line after the job line, which is all `merge` needs to renumber its shards:
// "shapespline mesh welded items PUxPV closed uv|u|v|none orientation du-x-dv|reversed".
struct MeshInfo {
  uint64_t patchesU = 1, patchesV = 1;
  bool closedU = false, closedV = false;
  bool reversed = false;
};
MeshInfo meshInfoOf(const SampleLayout& layout);
std::string meshInfoLine(const MeshInfo& mesh);
std::optional<MeshInfo> parseMeshInfoLine(std::string_view line);
inline constexpr std::string_view kMeshLinePrefix = "shapespline mesh ";

inline constexpr std::string_view kPlySourcePrefix = "comment shapespline sample of ";
inline constexpr std::string_view kPlyJobPrefix = "comment ";
inline constexpr std::string_view kObjSourcePrefix = "# shapespline sample of ";
inline constexpr std::string_view kObjJobPrefix = "# ";

// The raw sidecar (OUT.json, and OUT.npy.json beside every .npy), format_version
// kRawSidecarVersion. A shard lists the model spans of its own items only: spans_u from row spans_u_offset on (the rows its items touch), spans_v from column
// spans_v_offset on (the columns of its row when its items lie in one row, else all). Item k of
// the model is patch (spans_u[k / items_v - spans_u_offset], spans_v[k % items_v - spans_v_offset])
// (curves: span spans_u[k - spans_u_offset]).
struct RawSidecar {
  std::string dataFile;               // file name of the data, no folder
  bool float64 = true;                // dtype
  std::vector<std::string> fields;    // field names in record order
  ShardInfo info;
  uint64_t itemsV = 1;
  uint64_t spansUOffset = 0, spansVOffset = 0;
  std::vector<int> spansU, spansV;
  bool computedDouble = true;        // the arithmetic's precision (the CPU path: always fp64)
  std::string device = "cpu";         // where the values were computed: "cpu" or a Vulkan device name
  std::string source;                 // the model path as given (escaped when written)
  // "metadata" (io/job_metadata.h metadataJson): the same in every shard of a job but for device and
  // computed precision, which follow "device" and "computed_precision" (a merge may mix devices).
  JobMetadata metadata;

  uint64_t valueSize() const { return float64 ? 8 : 4; }
  uint64_t valuesPerRecord() const { return static_cast<uint64_t>(fields.size()) * 3; }
};

// [row0, row1) and [col0, col1) of the item range [first, first + count) over items_v columns.
struct SpanWindow {
  uint64_t row0 = 0, row1 = 0, col0 = 0, col1 = 0;
};
SpanWindow spanWindow(uint64_t first, uint64_t count, uint64_t itemsV);

// The sidecar of a job from its layout (spans cut to the shard's window).
// The raw sidecar's format_version: 3 added "device" and made "computed_precision" the precision
// the path computed in (docs/format.md); 4 added "metadata" (tool, model SHA-256, parameters,
// singular vertices, precisions, grid). Merge reads exactly this version.
inline constexpr int kRawSidecarVersion = 4;

RawSidecar rawSidecarOf(const SampleLayout& layout, const std::string& job, bool float64, const std::string& dataFile);
// Writes `s` as JSON text (ends with a newline). Counts follow from info, grid and fields.
void writeRawSidecar(AtomicFile& out, const RawSidecar& s);

}  // namespace shapespline::io
