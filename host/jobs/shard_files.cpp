#include <shapespline/jobs/job_input_error.h>
#include <shapespline/jobs/scheduler_env.h>
#include <shapespline/jobs/shard_files.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/shard_info.h>
#include <shapespline/jobs/shard_pattern.h>
#include <shapespline/jobs/shard_record.h>
#include <shapespline/io/welded_mesh.h>

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <set>

namespace shapespline::jobs {

namespace fs = std::filesystem;

namespace {

constexpr size_t kMaxDistinctCounts = 16;

}  // namespace

ShardRecord shardRecordOf(const io::SampleLayout& layout, io::OutputFormat format) {
  ShardRecord r;
  r.job = layout.job;
  r.surface = layout.surface;
  r.format = std::string(io::outputFormatName(format));
  r.shardIndex = layout.shardIndex;
  r.shardCount = layout.shardCount;
  r.firstItem = layout.firstItem;
  r.itemCount = layout.itemCount;
  r.totalItems = layout.totalItems;
  r.points = layout.pointCount();
  r.vertices = layout.welded && io::isMesh(format)
                   ? io::WeldedNumbering(layout.weldGrid(), layout.firstItem, layout.firstItem + layout.itemCount)
                         .vertexCount()
                   : layout.pointCount();
  r.metadata = layout.metadata;
  return r;
}

ShardRecord trimmedShardRecordOf(const io::SampleLayout& layout, io::OutputFormat format, const io::TrimmedShard& shard,
                                 uint64_t points) {
  ShardRecord r = shardRecordOf(layout, format);
  r.job = shard.job;
  r.shardIndex = shard.index;
  r.shardCount = shard.count;
  r.firstItem = shard.firstItem;
  r.itemCount = shard.items;
  r.totalItems = shard.totalItems;
  r.points = points;
  r.vertices = shard.records;
  return r;
}

namespace {

fs::path folderOf(const std::string& path) {
  const fs::path f = fs::path(path).parent_path();
  return f.empty() ? fs::path(".") : f;
}

std::string kn(int k, int n) { return std::to_string(k) + "/" + std::to_string(n); }

// Why `got` (read back) is not the record this run would write; "" when it is.
std::string recordDifference(const ShardRecord& got, const ShardRecord& want, io::OutputFormat format,
                             const ShardFileList& files) {
  if (got.job != want.job) return "it is of another job (" + got.job + ", this one is " + want.job + ")";
  if (got.format != want.format || got.surface != want.surface || got.projection != want.projection)
    return "it describes another format or kind";
  if (got.shardIndex != want.shardIndex || got.shardCount != want.shardCount) {
    return "it is shard " + kn(got.shardIndex, got.shardCount) + ", this one is " +
           kn(want.shardIndex, want.shardCount);
  }
  if (got.firstItem != want.firstItem || got.itemCount != want.itemCount || got.totalItems != want.totalItems ||
      got.points != want.points || got.vertices != want.vertices) {
    return "its item range or counts differ from this shard's";
  }
  io::JobMetadata a = got.metadata;
  // Raw, .npy and CSV shards of one job may come from different devices (merge allows it).
  if (!io::isMesh(format) && format != io::OutputFormat::Svg) {
    a.device = want.metadata.device;
    a.computedPrecision = want.metadata.computedPrecision;
  }
  if (const std::string key = io::metadataDifference(a, want.metadata); !key.empty()) {
    return "its job metadata \"" + key + "\" differs from this run's";
  }
  std::vector<std::string> names{fs::path(files.data).filename().string()};
  if (!files.extra.empty()) names.push_back(fs::path(files.extra).filename().string());
  if (got.files.size() != names.size()) return "it lists other files than this shard writes";
  for (size_t i = 0; i < names.size(); ++i) {
    if (got.files[i].name != names[i]) return "it lists '" + got.files[i].name + "', this shard writes '" + names[i] + "'";
  }
  return "";
}

// Up to `limit` bytes from the start of a regular file (never blocks on a FIFO); "" when unreadable.
std::string readHead(const fs::path& path, size_t limit) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return "";
  std::string text;
  struct stat st {};
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
    text.resize(limit);
    size_t got = 0;
    while (got < limit) {
      const ssize_t n = ::read(fd, text.data() + got, limit - got);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      got += static_cast<size_t>(n);
    }
    text.resize(got);
  }
  ::close(fd);
  return text;
}

// N as shard 1 states it: its record, raw sidecar ("shard": {"count"}) or PLY/OBJ job line.
std::optional<uint64_t> shardCountOfFile(const std::string& path) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(shardRecordPath(path), ec))) {
    try {
      return static_cast<uint64_t>(readShardRecord(shardRecordPath(path)).shardCount);
    } catch (const ShardRecordError&) {
      // merge refuses the broken record with its reason below
    }
  }
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".f32" || ext == ".f64" || ext == ".npy") {
    const std::string text = readHead(path + ".json", static_cast<size_t>(kMaxShardRecordBytes));
    // A sidecar of a few MiB is read whole; its nesting was bounded when it was written, and a crafted
    // one only fails to parse here (merge then refuses it with its reason).
    bool shallow = true;
    int depth = 0;
    for (char c : text) {
      if (c == '[' || c == '{') shallow = shallow && ++depth <= 16;
      if (c == ']' || c == '}') --depth;
    }
    if (!shallow) return std::nullopt;
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_object() && j.contains("shard") && j["shard"].is_object() && j["shard"].contains("count") &&
        j["shard"]["count"].is_number_unsigned()) {
      return j["shard"]["count"].get<uint64_t>();
    }
    return std::nullopt;
  }
  if (ext == ".ply" || ext == ".obj") {
    const std::string head = readHead(path, 64 << 10);
    size_t at = 0;
    while (at < head.size()) {
      size_t eol = head.find('\n', at);
      if (eol == std::string::npos) break;
      std::string_view line(head.data() + at, eol - at);
      for (std::string_view prefix : {io::kPlyJobPrefix, io::kObjJobPrefix}) {
        if (line.starts_with(prefix)) {
          if (const auto info = io::parseShardInfoLine(line.substr(prefix.size()))) {
            return static_cast<uint64_t>(info->shardCount);
          }
        }
      }
      if (line == "end_header") break;
      at = eol + 1;
    }
  }
  return std::nullopt;
}

std::vector<std::string> expandMergePattern(const std::string& text) {
  ShardPattern p;
  try {
    p = ShardPattern::parse(text);
  } catch (const ShardPatternError& e) {
    throw JobInputError("SHARD", text, e.what());
  }
  if (!p.hasShard()) throw JobInputError("SHARD", text, "a shard pattern for merge needs {shard} (the shard K)");
  // The files present that the pattern names: their counts (at most a few distinct) and highest K.
  std::set<uint64_t> counts;
  uint64_t highest = 0;
  const fs::path folder = p.folder().empty() ? fs::path(".") : fs::path(p.folder());
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const auto m = p.match(it->path().filename().string());
    if (!m || m->first < 1 || m->first > io::kMaxShardCount) continue;
    if (p.hasCount()) {
      if (m->second < 1 || m->second > io::kMaxShardCount || m->first > m->second) continue;
      counts.insert(m->second);
      if (counts.size() > kMaxDistinctCounts) break;
    }
    highest = std::max(highest, m->first);
  }
  if (ec) throw JobInputError("SHARD", text, "cannot list the folder '" + folder.string() + "': " + ec.message());
  uint64_t n = 0;
  std::string why;
  if (p.hasCount()) {
    if (counts.empty()) throw JobInputError("SHARD", text, "no file matches the shard pattern");
    if (counts.size() > 1) {
      std::string list;
      for (uint64_t c : counts) list += (list.empty() ? "" : ", ") + std::to_string(c);
      throw JobInputError("SHARD", text,
                       "files of several shard counts match the pattern ({count} = " + list +
                           "); remove the stale ones, or give the shards by name");
    }
    n = *counts.begin();
    why = "{count} of the files present";
  } else if (const auto stated = shardCountOfFile(p.expand(1, 0)); stated && *stated >= 1 && *stated <= io::kMaxShardCount) {
    n = *stated;
    why = "shard 1 says so";
  } else {
    if (highest == 0) throw JobInputError("SHARD", text, "no file matches the shard pattern");
    n = highest;
    why = "the highest shard present";
  }
  std::vector<std::string> shards;
  for (uint64_t k = 1; k <= n; ++k) {
    std::string path = p.expand(k, n);
    if (!fs::exists(fs::symlink_status(path, ec))) {
      throw JobInputError("SHARD[" + std::to_string(k) + "]", path,
                       "is missing: the pattern expands to shards 1.." + std::to_string(n) + " (N = " +
                           std::to_string(n) + ": " + why + ")");
    }
    shards.push_back(std::move(path));
  }
  return shards;
}

}  // namespace

ShardOutput resolveShardOutput(const std::string& out, const std::string& shard, const std::string& shardCount) {
  const ShardChoice c = parseShardOption(shard, shardCount);
  ShardOutput o;
  o.shard = shard.empty() ? "" : kn(c.index, c.count);
  o.index = c.index;
  o.count = c.count;
  o.source = c.source;
  o.out = out;
  if (ShardPattern::looksLikePattern(out)) {
    try {
      o.out = ShardPattern::parse(out).expand(static_cast<uint64_t>(c.index), static_cast<uint64_t>(c.count));
    } catch (const ShardPatternError& e) {
      throw JobInputError("-o", out, e.what());
    }
  }
  return o;
}

bool shardAlreadyDone(const ShardRecord& want, io::OutputFormat format, const ShardFileList& files, bool quiet) {
  const fs::path recordPath = shardRecordPath(files.data);
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(recordPath, ec))) return false;
  auto redo = [&](const std::string& why) {
    if (!quiet) {
      std::fprintf(stderr, "shapespline: notice: %s: the shard record '%s' does not verify (%s); %s the shard again\n",
                   files.data.c_str(), recordPath.c_str(), why.c_str(), want.projection.empty() ? "sampling" : "projecting");
    }
    return false;
  };
  ShardRecord got;
  try {
    got = readShardRecord(recordPath);
  } catch (const ShardRecordError& e) {
    return redo(std::string("the record ") + e.what());
  }
  if (const std::string why = recordDifference(got, want, format, files); !why.empty()) {
    return redo(why);
  }
  const fs::path folder = folderOf(files.data);
  for (const auto& f : got.files) {
    if (const std::string why = verifyShardFile(f, folder / f.name); !why.empty()) return redo(why);
  }
  if (!quiet) {
    std::fprintf(stderr,
                 "shapespline: notice: %s: shard %s is complete: its files verify against '%s' (job %s, sizes and "
                 "SHA-256); nothing to do\n",
                 files.data.c_str(), kn(want.shardIndex, want.shardCount).c_str(), recordPath.c_str(), want.job.c_str());
  }
  return true;
}

void writeShardRecord(io::AtomicFile& record, ShardRecord r, const io::AtomicFile& data, const io::AtomicFile* extra,
                      const std::string& extraRole) {
  auto describe = [](const io::AtomicFile& f, const std::string& role) {
    try {
      ShardRecordFile d = describeShardFile(f.tempPath(), role);
      d.name = f.target().filename().string();
      return d;
    } catch (const std::exception& e) {
      throw io::OutputWriteError(f.option(), f.target().string(),
                                 std::string("reading the written file back for its SHA-256 failed: ") + e.what());
    }
  };
  r.files.push_back(describe(data, "data"));
  if (extra) r.files.push_back(describe(*extra, extraRole));
  record.write(shardRecordJson(r));
}

std::vector<std::string> mergeInputs(const std::vector<std::string>& args) {
  std::vector<std::string> shards;
  const bool pattern = args.size() == 1 && ShardPattern::looksLikePattern(args[0]);
  if (pattern) {
    shards = expandMergePattern(args[0]);
  } else {
    shards = args;
  }
  const std::string ext0 = shards.empty() ? "" : fs::path(shards[0]).extension().string();
  for (size_t i = 0; i < shards.size(); ++i) {
    const std::string field = "SHARD[" + std::to_string(i + 1) + "]";
    const std::string& path = shards[i];
    const fs::path recordPath = shardRecordPath(path);
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(recordPath, ec))) continue;
    ShardRecord r;
    try {
      r = readShardRecord(recordPath);
    } catch (const ShardRecordError& e) {
      throw JobInputError(field, path,
                       "its shard record '" + io::shortText(recordPath.string(), 120) + "' " + e.what() +
                           " (not a record that sample or project writes; remove it or run the shard again)");
    }
    for (const auto& f : r.files) {
      const fs::path p = f.role == "data" ? fs::path(path) : f.role == "sidecar" ? fs::path(path + ".json") : fs::path();
      if (p.empty()) continue;  // a glTF buffer: glTF files are not merged
      if (const std::string why = verifyShardFile(f, p); !why.empty()) {
        throw JobInputError(field, path,
                         "does not verify against its shard record '" + io::shortText(recordPath.string(), 120) +
                             "': " + why + (r.projection.empty() ? "; sample the shard again" : "; project the shard again"));
      }
    }
    // CSV carries no job line, so only the record shows a missing last shard (other formats: merge
    // checks their headers, with the same words).
    if (ext0 == ".csv" && static_cast<size_t>(r.shardCount) != shards.size()) {
      throw JobInputError(field, path,
                       "is shard " + kn(r.shardIndex, r.shardCount) + " of a job of " + std::to_string(r.shardCount) +
                           " shards (its shard record), but " + std::to_string(shards.size()) +
                           (shards.size() == 1 ? " was" : " were") + " given (give all N shards, in order)");
    }
  }
  return shards;
}

}  // namespace shapespline::jobs
