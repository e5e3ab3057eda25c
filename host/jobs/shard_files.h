#pragma once
// The files of a shard at the command line (issue 16): `sample`'s shard pattern and --shard auto
// (resolveShardOutput), its shard record OUT.shard.json and the resume check (shardAlreadyDone,
// writeShardRecord), and `merge`'s inputs: a shard pattern expanded to the shards 1..N, and the
// shard record of every shard that has one verified (mergeInputs).
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/trimmed_points.h>
#include <shapespline/jobs/shard_record.h>

#include <string>
#include <vector>

namespace shapespline::jobs {

struct ShardOutput {
  std::string out;    // -o with a shard pattern expanded
  std::string shard;  // "" (unsharded) or "K/N" (--shard K/N or auto resolved)
  int index = 1, count = 1;  // K and N (1/1 unsharded)
  std::string source; // where K/N came from: "" or "Slurm job array" / "Kubernetes Indexed Job"
};

// --shard (K/N, auto or ""), --shard-count and -o (a path or a shard pattern, jobs/shard_pattern.h).
// InputError naming -o for a malformed pattern; a pattern without --shard expands as shard 1/1.
ShardOutput resolveShardOutput(const std::string& out, const std::string& shard, const std::string& shardCount);

// The files of the shard besides its record: the data (-o) first, then its raw sidecar or glTF buffer.
struct ShardFileList {
  std::string data;
  std::string extra;       // "" when none
  std::string extraRole;   // "sidecar" | "buffer"
};

// The record of a grid job's shard, without its files (a trimmed job's is this with its own job,
// items and records: cli/part_sample.cpp, cli/cmd_sample.cpp).
ShardRecord shardRecordOf(const io::SampleLayout& layout, io::OutputFormat format);

// The record of a trimmed job's shard (a face with --trim, a part): the grid job's of `layout` (its
// format, grid and metadata) under the trimmed job's fingerprint, shard and items, holding the
// shard's records, its `points` the grid samples of its items.
ShardRecord trimmedShardRecordOf(const io::SampleLayout& layout, io::OutputFormat format, const io::TrimmedShard& shard,
                                 uint64_t points);

// True when OUT.shard.json exists, is the record `want` (job fingerprint, shard, items, counts,
// metadata: for raw/.npy/CSV shards but for device and computed precision, which merge allows to
// differ) but for its files, and every file verifies (size, SHA-256): prints a notice (unless
// quiet) and the caller writes nothing. A record that does not verify prints a notice saying why,
// and false is returned (the shard is sampled again); no record: false, silently.
bool shardAlreadyDone(const ShardRecord& want, io::OutputFormat format, const ShardFileList& files, bool quiet);

// Writes the shard record `r` into `record`, after hashing the (flushed) temporary files of `data`
// and `extra` (nullptr when none) under their target names.
void writeShardRecord(io::AtomicFile& record, ShardRecord r, const io::AtomicFile& data, const io::AtomicFile* extra,
                      const std::string& extraRole);

// `merge`'s SHARD arguments: one shard pattern is expanded to shards 1..N (N from the {count} of the
// files present, else from shard 1's record, raw sidecar or PLY/OBJ job line, else the highest K
// present); a list is kept as given. Then every shard with a record (SHARD.shard.json) is verified
// against it: its data file and raw sidecar have the recorded size and SHA-256, and the record's
// shard count is the number of shards given. InputError naming SHARD / SHARD[k] otherwise.
std::vector<std::string> mergeInputs(const std::vector<std::string>& args);

}  // namespace shapespline::jobs
