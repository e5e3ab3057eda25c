#pragma once
// Joins the outputs of `sample --shard K/N` into the file the unsharded job writes, byte for byte,
// after verifying that they belong together. Streams: every shard is read through a fixed 1 MiB
// buffer (PLY: vertex blocks copied, then faces/edges re-offset chunk by chunk; OBJ and CSV line by
// line; .npy: the header checked against the shard's raw sidecar OUT.npy.json, the records copied
// after the whole job's header), so memory does not grow with the data; raw sidecars (.f32/.f64 and
// .npy) are parsed one at a time and the merged one holds the model's span lists (4 bytes per row
// and column) and the job metadata (io/job_metadata.h), which must be the same in every shard but
// for the device and computed precision (the merged sidecar says "mixed" / the least precise).
//
// Verified (io/shard_info.h): every shard carries the same job fingerprint (model, samples per item,
// fields, precision, format), kind, grid and item total; shard k of the list is shard k/N and all N
// are given; shard k covers exactly items floor((k-1)T/N) .. floor(kT/N) (so the shards are
// consecutive, non-overlapping and complete: the first starts at item 0, the last ends at T); the
// file is exactly as large as its header says (overflow-checked arithmetic), every record and
// index is in range. CSV carries no job line (a comment would break pandas' read_csv), so a CSV
// merge checks what the text shows: identical header lines, rows with the header's column count,
// items (span / patch_i,patch_j) strictly increasing across all shards (order, overlaps, a shard
// given twice), the same rows per item in every shard, every line complete. It cannot tell shards of
// two models with the same header apart, nor a missing last shard: use raw, PLY or OBJ for that.
//
// A `project --shard` job's shards (each with its record OUT.shard.json, kind "projection") are
// joined by their records: shards 1..N of one job in order, covering every point; each file must be
// exactly the header of its own count and its records, which go under the whole count's header.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapespline::jobs {

// A shard that cannot be merged (exit code 2 at the command line): `field` names it ("SHARD[2]",
// 1-based position in the list), `value` shows its path (shortened), `rule` the reason.
class MergeError : public std::invalid_argument {
 public:
  MergeError(std::string field, std::string value, std::string rule);
  const std::string& field() const { return field_; }
  const std::string& value() const { return value_; }
  const std::string& rule() const { return rule_; }

 private:
  std::string field_, value_, rule_;
};

// Reading a shard failed after it was opened (an I/O error): exit code 3.
class MergeReadError : public std::runtime_error {
 public:
  MergeReadError(std::string field, std::string value, std::string rule);
  const std::string& field() const { return field_; }
  const std::string& value() const { return value_; }
  const std::string& rule() const { return rule_; }

 private:
  std::string field_, value_, rule_;
};

struct MergeResult {
  uint64_t items = 0;   // spans/patches in the merged file
  uint64_t bytes = 0;   // size of the merged data file
};

inline constexpr size_t kMergeBufferBytes = size_t{1} << 20;
inline constexpr uint64_t kMaxSidecarBytes = uint64_t{256} << 20;

// Writes `output` (.obj .ply .csv, .f32/.f64/.npy + sidecar) from `shards`, given in order 1..N. The format
// comes from the extensions (all equal). Throws MergeError / MergeReadError as above, and
// OutputPathError / OutputWriteError (io/atomic_file.h) for the output; nothing is left behind on
// any error.
MergeResult mergeShards(const std::vector<std::string>& shards, const std::string& output);

}  // namespace shapespline::jobs
