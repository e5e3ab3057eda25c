#pragma once
// What a sampled file says about the job that made it (issue 15, requirement 6): the tool version,
// the model file (its name as given and the SHA-256 of its bytes), the construction and its
// parameters (degree/order, λ, μ, α per vertex), the α = 1 ("singular") vertices where the normal is
// a convention, where and in which precision the values were computed, the output precision and
// the grid. Not the shard: a shard says which part it is in its job line / sidecar "shard", and the
// metadata is the same for every shard of a job, so `merge` copies it into the merged file.
//
// Two renderings of one struct: comment lines for text headers (PLY `comment`, OBJ `#`) and a JSON
// object (the raw / .npy sidecar's "metadata", SVG <metadata>, glTF extras). metadataFromJson reads
// the JSON back (merge), and metadataJson(metadataFromJson(j)) reproduces j. Text that is not
// valid UTF-8 (a model path) is written as U+FFFD in the JSON and escaped in comment lines.
#include <shapespline/core/model.h>
#include <shapespline/core/surface.h>
#include <shapespline/core/sample_grid.h>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace shapespline::io {

// The JSON lists α (and the singular vertices) up to this many values; beyond it, a summary.
inline constexpr uint64_t kMetadataAlphaListMax = 4096;

class AlphaTally;

struct JobMetadata {
  std::string toolVersion;            // SHAPESPLINE_VERSION_STRING of the writer
  std::string toolCommit;             // SHAPESPLINE_GIT_COMMIT of the writer
  std::string modelFile;              // the model path as given (command line); unescaped
  std::string modelSha256;            // 64 lowercase hex digits of the file's bytes; empty: unknown
  bool surface = false;
  Construction construction = Construction::ExtendedBSpline;
  int degree = 0;                     // written when the family uses a degree
  int order = 0, orderV = 0;          // written when it uses an order (surfaces of two orders: both)
  bool rational = false;              // a B-spline with weights (NURBS): "rational": true; else absent
  double lambda = 0.0;                // written when it uses λ
  std::vector<double> mu;             // written when it uses μ
  // α per vertex when the family uses α (curves: one per point; surfaces: rows x cols, row-major),
  // listed when there are at most kMetadataAlphaListMax values, else empty: a 4096 x 4096 net's
  // 16.8 million values would make every sidecar 67 MB (the model_sha256 pins them anyway).
  std::vector<double> alpha;
  int rows = 0, cols = 0;             // surfaces: the net's shape (rows * cols values of α)
  // Always set when the family uses α (from the values as setAlpha saw them).
  struct AlphaSummary {
    uint64_t count = 0;               // vertices
    double min = 0.0, max = 0.0;
    uint64_t singular = 0;            // vertices with α == 1
    friend bool operator==(const AlphaSummary&, const AlphaSummary&) = default;
  } alphaSummary;
  std::string device = "cpu";         // "cpu" or the Vulkan device's name; unescaped
  Precision computedPrecision = Precision::Double;
  Precision outputPrecision = Precision::Double;  // what the file stores
  int samplesU = 2, samplesV = 1;     // grid per span (curves: samplesV = 1) or patch

  bool usesAlpha() const;
  // Sets alphaSummary from `values` and lists them in `alpha` when there are at most
  // kMetadataAlphaListMax (surfaces: rows x cols, row-major; curves: rows = cols = 0).
  void setAlpha(const std::vector<double>& values, int rows, int cols);
  // The same from α given a run at a time (AlphaTally).
  void setAlpha(const AlphaTally& values, int rows, int cols);
  bool alphaListed() const { return alphaSummary.count <= kMetadataAlphaListMax; }
  // "UxV" (surfaces) or "S" (curves).
  std::string grid() const;
  // The vertices with α == 1, in index order: curves (i, 0), surfaces (i, j); empty unless listed.
  std::vector<std::pair<int, int>> singularVertices() const;

  friend bool operator==(const JobMetadata&, const JobMetadata&) = default;
};

// Comment lines show α and the singular vertices in full up to this many values; beyond it, α as
// count/min/max and the singular vertices as a count (the JSON up to kMetadataAlphaListMax).
inline constexpr size_t kMetadataCommentListMax = 64;

// One line per key, "<linePrefix><key>: <value>\n", in a fixed order: tool_version, model_file,
// model_sha256, kind, construction, degree / order, rational, lambda, mu, alpha, singular_vertices, device,
// computed_precision, output_precision, grid. `linePrefix` is written as given ("# " for OBJ,
// "comment " for PLY). Text values are escapeText'ed (io/text_escape.h), so every value stays on its
// line; numbers are the shortest decimals that read back exactly.
std::string metadataComments(const JobMetadata& m, std::string_view linePrefix);

// The JSON object: "tool" ("shapespline"), "tool_version", "tool_commit", "model_file",
// "model_sha256", "kind", "construction", ["degree"], ["order"] (an [u, v] pair for two-order
// surfaces), ["rational"] (true, for a B-spline with weights), ["lambda"], ["mu"], ["alpha"] (curves: a list; surfaces: rows of lists, as in model
// files; more than kMetadataAlphaListMax values: {"values": N, "shape": [R, C] or [N], "min": a,
// "max": b}), ["singular_vertices"] (curves: [i, ...]; surfaces: [[i, j], ...]; with a summarised
// α: {"count": K}; present with "alpha"),
// "device", "computed_precision", "output_precision" ("float" | "double"), "grid" ("UxV" | "S").
nlohmann::json metadataJson(const JobMetadata& m);

// A "metadata" object that is not what metadataJson writes: `key()` names the offending key.
class MetadataError : public std::invalid_argument {
 public:
  MetadataError(std::string key, const std::string& rule)
      : std::invalid_argument("\"" + key + "\" " + rule), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// The inverse of metadataJson; throws MetadataError (keys named "metadata.<key>") unless `j` has
// exactly the keys metadataJson writes for its construction, with valid values (the singular
// vertices must be those of the α list).
JobMetadata metadataFromJson(const nlohmann::json& j);

// The JSON key of the first field in which a and b differ ("alpha", "device", ...); empty if equal.
std::string metadataDifference(const JobMetadata& a, const JobMetadata& b);

// SHA-256 of a regular file's bytes as 64 lowercase hex digits, read in 64 KiB pieces (OpenSSL
// EVP). Throws std::runtime_error when the file cannot be opened or read, or is not a regular file.
std::string sha256OfFile(const std::filesystem::path& path);
// SHA-256 of bytes in memory, the same digits.
std::string sha256Of(std::string_view bytes);

// The model's SHA-256 for its metadata: the bytes of the model file, then those of each .npy array
// it names (ModelArrays::files, in that order). A model without arrays gives sha256sum's digits.
// Reading a big net's arrays a second time and hashing them takes a while (0.25 s for 400 MB), so
// the hash runs on a thread of its own, beside the parse: the model file's bytes from the start,
// each array's as soon as add() names it (ModelArrays::onFile), before the parser reads it. Files
// of 256 KiB or less in all are hashed by get() instead, without a thread.
class ModelDigest {
 public:
  explicit ModelDigest(std::filesystem::path modelFile);
  ~ModelDigest();  // stops the hashing after the current file when get() was not called
  ModelDigest(const ModelDigest&) = delete;
  ModelDigest& operator=(const ModelDigest&) = delete;

  void add(const std::filesystem::path& arrayFile);
  // The 64 hex digits, once every file added is hashed; sha256OfFile's errors (the first file that
  // failed). Call once.
  std::string get();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// What JobMetadata::setAlpha keeps of α given a run at a time, in order (a net read from its
// files a window at a time): the summary, and the values while there are at most
// kMetadataAlphaListMax.
class AlphaTally {
 public:
  void add(const double* values, size_t count);
  const JobMetadata::AlphaSummary& summary() const { return summary_; }
  // Every value given, when there were at most kMetadataAlphaListMax; else empty.
  const std::vector<double>& listed() const { return listed_; }

 private:
  JobMetadata::AlphaSummary summary_;
  std::vector<double> listed_;
};

// ModelDigest's digits for a model whose arrays are known.
std::string modelSha256(const std::filesystem::path& modelPath, const std::vector<std::filesystem::path>& arrayFiles);

// The metadata of sampling `model`, read from `modelPath` whose modelSha256 is `modelSha256`, on
// `device` in `computedPrecision`, stored in `outputPrecision`, samplesU per span or samplesU x
// samplesV per patch. The tool version and commit are this build's (shapespline/version.h).
JobMetadata jobMetadataOf(const CurveModel& model, const std::string& modelPath, std::string modelSha256,
                          std::string_view device, Precision computedPrecision, Precision outputPrecision,
                          int samplesU);
// The same for a curve of shape `shape` whose α (AlphaTally) and weights (`rational`) were read as a
// stream (io/streamed_bands.h streamCurveSpans).
JobMetadata jobMetadataOf(const CurveModel& shape, const AlphaTally& alpha, bool rational, const std::string& modelPath,
                          std::string modelSha256, std::string_view device, Precision computedPrecision,
                          Precision outputPrecision, int samplesU);
JobMetadata jobMetadataOf(const Surface& surface, const std::string& modelPath, std::string modelSha256,
                          std::string_view device, Precision computedPrecision, Precision outputPrecision,
                          int samplesU, int samplesV);
// The same for a surface of `shape` whose α (AlphaTally) and weights (`rational`) were read as a
// stream: a shard with no items, which does not build its surface.
JobMetadata jobMetadataOf(const SurfaceShape& shape, const AlphaTally& alpha, bool rational,
                          const std::string& modelPath, std::string modelSha256, std::string_view device,
                          Precision computedPrecision, Precision outputPrecision, int samplesU, int samplesV);

}  // namespace shapespline::io
