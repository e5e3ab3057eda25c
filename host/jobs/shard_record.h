#pragma once
// The shard record (issue 16, requirement 3): every `sample --shard K/N` (or `--shard auto`) writes
// OUT.shard.json beside its data, committed in the same io::OutputSet as the data (it appears with
// it, or not at all): the job fingerprint, the kind and format, shard K/N, the item range, the
// points sampled and the vertices (records) the data file holds, the bytes and SHA-256 of every
// file of the shard (the data, its raw sidecar OUT.json / OUT.npy.json), and the job metadata
// (io/job_metadata.h). A rerun of the shard whose record and files verify does nothing (resume);
// `merge` verifies the record of every shard that has one before it reads the shard.
//
// The record is an input when read back: it is refused (ShardRecordError naming the key) unless it
// is exactly what writeShardRecord writes (bounded size and nesting, plain file names in the same
// folder, counts in range).
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/job_metadata.h>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace shapespline::jobs {

inline constexpr int kShardRecordVersion = 1;
inline constexpr std::string_view kShardRecordSuffix = ".shard.json";
inline constexpr uint64_t kMaxShardRecordBytes = uint64_t{256} << 20;  // as a raw sidecar (α lists)
inline constexpr size_t kMaxShardRecordFiles = 8;

struct ShardRecordFile {
  std::string name;    // file name in the record's folder (no folder part)
  std::string role;    // "data" | "sidecar" | "buffer"
  uint64_t bytes = 0;
  std::string sha256;  // 64 lowercase hex digits

  friend bool operator==(const ShardRecordFile&, const ShardRecordFile&) = default;
};

struct ShardRecord {
  std::string job;          // jobFingerprint, 16 hex digits
  bool surface = false;
  // "" for a `sample` shard; a `project` shard's target, "surface", "part" or "curve" (its items
  // are the cloud's points, its metadata names the --onto file: jobs/projection_merge.h).
  std::string projection;
  std::string format;       // the data file's extension without the dot: "f32", "npy", "ply", ...
  int shardIndex = 1, shardCount = 1;
  uint64_t firstItem = 0, itemCount = 0, totalItems = 0;
  uint64_t points = 0;      // points sampled for the shard's own items
  uint64_t vertices = 0;    // vertices (records, rows) the data file holds: welded shards add foreign ones
  std::vector<ShardRecordFile> files;
  io::JobMetadata metadata;
};

// OUT + ".shard.json".
std::filesystem::path shardRecordPath(const std::filesystem::path& dataPath);

// The record as JSON text (ends with a newline).
std::string shardRecordJson(const ShardRecord& r);

class ShardRecordError : public std::invalid_argument {
 public:
  ShardRecordError(std::string key, const std::string& rule)
      : std::invalid_argument(key.empty() ? rule : "\"" + key + "\" " + rule), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// Parses a record's text; ShardRecordError unless it is one writeShardRecord writes.
ShardRecord parseShardRecord(std::string_view text);
// Reads and parses the record at `path` (a regular file of at most kMaxShardRecordBytes, opened
// without blocking); a file that cannot be read is a ShardRecordError with an empty key.
ShardRecord readShardRecord(const std::filesystem::path& path);

// The bytes and SHA-256 of the file at `path` (sha256OfFile's errors), named by its file name.
ShardRecordFile describeShardFile(const std::filesystem::path& path, std::string role);

// Why the file at `path` is not the recorded `f` ("'x.f32' is 10 bytes, the record says 12",
// "'x.f32' has another SHA-256 than the record's ...", "'x.f32' is missing"); "" when it is. The size
// is checked first, so a wrong size costs no read; a symlink or non-regular file never verifies.
std::string verifyShardFile(const ShardRecordFile& f, const std::filesystem::path& path);

}  // namespace shapespline::jobs
