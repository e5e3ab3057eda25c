// The merge of every format (see merge.h). Over 700 lines on purpose: the PLY, OBJ, CSV and raw/.npy
// mergers (one section each, below) share the bounded shard reader, the shard sequence and mesh
// checks and the error texts of the first 300 lines; split by format they would need all of those
// in a private header, and a reader would follow one merge across five files instead of one.
#include <shapespline/jobs/merge.h>

#include <shapespline/io/atomic_file.h>
#include <shapespline/io/json_depth.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/projection_writer.h>
#include <shapespline/io/raw_records.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/shard_info.h>
#include <shapespline/io/trimmed_points.h>
#include <shapespline/io/welded_formats.h>
#include <shapespline/io/welded_mesh.h>
#include <shapespline/jobs/shard_record.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fcntl.h>
#include <limits>
#include <memory>
#include <optional>
#include <sys/stat.h>
#include <unistd.h>

namespace shapespline::jobs {

// What the merge reads and writes is io's: the formats, their headers and the atomic output set.
using io::AtomicFile;
using io::JobMetadata;
using io::MeshInfo;
using io::MetadataError;
using io::OutputFormat;
using io::OutputSet;
using io::RawSidecar;
using io::ShardInfo;
using io::SpanWindow;
using io::WeldGrid;
using io::WeldedNumbering;
using io::escapeText;
using io::fieldName;
using io::isGltf;
using io::jsonDepthWithin;
using io::kMeshLinePrefix;
using io::kObjJobPrefix;
using io::kObjSourcePrefix;
using io::kPlyJobPrefix;
using io::kPlySourcePrefix;
using io::kRawSidecarVersion;
using io::meshInfoLine;
using io::metadataDifference;
using io::metadataFromJson;
using io::npyHeader;
using io::objHeader;
using io::objLinesPerVertex;
using io::outputFormatFromPath;
using io::outputFormatName;
using io::parseMeshInfoLine;
using io::parseShardInfoLine;
using io::plyConnectivityHeader;
using io::plyInfoComments;
using io::spanWindow;
using io::wholeJobOf;
using io::writeObjConnectivity;
using io::writePlyConnectivity;
using io::writeRawSidecar;

MergeError::MergeError(std::string field, std::string value, std::string rule)
    : std::invalid_argument(field + ": " + rule + (value.empty() ? "" : " (got " + value + ")")),
      field_(std::move(field)),
      value_(std::move(value)),
      rule_(std::move(rule)) {}

MergeReadError::MergeReadError(std::string field, std::string value, std::string rule)
    : std::runtime_error(field + ": " + rule + (value.empty() ? "" : " (got " + value + ")")),
      field_(std::move(field)),
      value_(std::move(value)),
      rule_(std::move(rule)) {}

namespace {

// A sidecar's value at `key` when it has that type, else "" or 0: nlohmann's value(key, default)
// throws type_error when the key holds another type, and a sidecar is a foreign file.
std::string stringOr(const nlohmann::json& doc, const char* key) {
  const auto it = doc.is_object() ? doc.find(key) : doc.end();
  return it != doc.end() && it->is_string() ? it->get<std::string>() : std::string();
}
uint64_t unsignedOr(const nlohmann::json& doc, const char* key) {
  const auto it = doc.is_object() ? doc.find(key) : doc.end();
  return it != doc.end() && it->is_number_unsigned() ? it->get<uint64_t>() : 0;
}

constexpr size_t kMaxLineBytes = 64 * 1024;       // OBJ/CSV lines; shapespline writes < 1 KiB
constexpr size_t kMaxPlyHeaderBytes = 64 * 1024;
constexpr int kMaxSidecarDepth = 16;

// A path as shown in a message: escaped (one line) and at most ~60 characters, keeping the end
// (the file name).
std::string shown(const std::string& path) {
  const std::string e = escapeText(path);
  if (e.size() <= 60) return e;
  size_t cut = e.size() - 57;
  while (cut < e.size() && (static_cast<unsigned char>(e[cut]) & 0xc0) == 0x80) ++cut;
  return "..." + e.substr(cut);
}

// A line or token as shown in a message.
std::string snippet(std::string_view s) {
  std::string e = escapeText(s.substr(0, 40));
  return "'" + e + (s.size() > 40 ? "...'" : "'");
}

struct Where {
  std::string field, path;
};

[[noreturn]] void refuse(const Where& w, const std::string& rule) { throw MergeError(w.field, shown(w.path), rule); }

std::string shardField(size_t k) { return "SHARD[" + std::to_string(k) + "]"; }

bool mulOk(uint64_t a, uint64_t b, uint64_t* r) { return !__builtin_mul_overflow(a, b, r); }
bool addOk(uint64_t a, uint64_t b, uint64_t* r) { return !__builtin_add_overflow(a, b, r); }

std::optional<uint64_t> parseCount(std::string_view s, uint64_t limit) {
  if (s.empty() || s.size() > 20 || (s.size() > 1 && s[0] == '0')) return std::nullopt;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
  }
  uint64_t v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size() || v > limit) return std::nullopt;
  return v;
}

bool startsWith(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

// A shard opened for reading: a regular file (a directory, FIFO or device is refused without
// blocking), read through a fixed buffer.
class ShardFile {
 public:
  ShardFile(Where where) : w_(std::move(where)) {
    fd_ = ::open(w_.path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd_ < 0) refuse(w_, std::string("cannot open the file (") + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(fd_, &st) != 0) fail("cannot stat the file");
    if (!S_ISREG(st.st_mode)) {
      ::close(fd_);
      fd_ = -1;
      refuse(w_, "not a regular file");
    }
    const int flags = ::fcntl(fd_, F_GETFL);
    if (flags >= 0) ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK);
    size_ = static_cast<uint64_t>(st.st_size);
  }
  ~ShardFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  ShardFile(const ShardFile&) = delete;
  ShardFile& operator=(const ShardFile&) = delete;

  const Where& where() const { return w_; }
  uint64_t size() const { return size_; }

  // Up to `n` bytes (fewer only at the end of the file).
  size_t read(char* dst, size_t n) {
    size_t got = std::min(n, end_ - pos_);
    if (got) std::memcpy(dst, buffer_.get() + pos_, got);
    pos_ += got;
    while (got < n) {
      const ssize_t r = ::read(fd_, dst + got, n - got);
      if (r < 0 && errno == EINTR) continue;
      if (r < 0) fail("cannot read the file");
      if (r == 0) break;
      got += static_cast<size_t>(r);
    }
    return got;
  }
  // Exactly `n` bytes, else the file is shorter than its header says.
  void readExact(char* dst, size_t n) {
    if (read(dst, n) != n) refuse(w_, "is shorter than its header says (truncated, or changed while merging)");
  }
  void expectEnd() {
    char c;
    if (read(&c, 1) != 0) refuse(w_, "is longer than its header says (changed while merging?)");
  }
  void seek(uint64_t offset) {
    if (::lseek(fd_, static_cast<off_t>(offset), SEEK_SET) < 0) fail("cannot seek in the file");
    pos_ = end_ = 0;
  }
  // The next line without its '\n'; false at the end of the file. `complete` tells whether it
  // ended with '\n'. A line longer than `maxBytes` is refused.
  bool line(std::string& out, size_t maxBytes, bool* complete) {
    out.clear();
    while (true) {
      if (pos_ == end_ && !fill()) {
        *complete = false;
        return !out.empty();
      }
      const char* start = buffer_.get() + pos_;
      const void* nl = std::memchr(start, '\n', end_ - pos_);
      const size_t take = nl ? static_cast<size_t>(static_cast<const char*>(nl) - start) : end_ - pos_;
      if (out.size() + take > maxBytes) refuse(w_, "has a line longer than " + std::to_string(maxBytes) + " bytes");
      out.append(start, take);
      pos_ += take;
      if (nl) {
        ++pos_;
        *complete = true;
        return true;
      }
    }
  }

 private:
  bool fill() {
    if (!buffer_) buffer_ = std::make_unique_for_overwrite<char[]>(kMergeBufferBytes);
    while (true) {
      const ssize_t r = ::read(fd_, buffer_.get(), kMergeBufferBytes);
      if (r < 0 && errno == EINTR) continue;
      if (r < 0) fail("cannot read the file");
      pos_ = 0;
      end_ = static_cast<size_t>(r);
      return r > 0;
    }
  }
  [[noreturn]] void fail(const std::string& what) {
    throw MergeReadError(w_.field, shown(w_.path), what + " (" + std::strerror(errno) + ")");
  }

  Where w_;
  int fd_ = -1;
  uint64_t size_ = 0;
  std::unique_ptr<char[]> buffer_;  // allocated on the first buffered read (line())
  size_t pos_ = 0, end_ = 0;
};

// Copies `n` bytes of `in` to `out` through a fixed buffer.
void copyBytes(ShardFile& in, AtomicFile& out, uint64_t n, std::vector<char>& buffer) {
  while (n > 0) {
    const size_t take = static_cast<size_t>(std::min<uint64_t>(n, buffer.size()));
    in.readExact(buffer.data(), take);
    out.write(buffer.data(), take);
    n -= take;
  }
}

std::string describe(const ShardInfo& s) {
  return "job " + s.job + ", " + (s.surface ? "surface" : "curve") + ", shard " + std::to_string(s.shardIndex) + "/" +
         std::to_string(s.shardCount) + " of " + std::to_string(s.totalItems) + " items, grid " +
         std::to_string(s.samplesU) + "x" + std::to_string(s.samplesV);
}

using io::shardBound;

// Shard k (1-based) of n given, against the first shard's job.
void checkSequence(const ShardInfo& s, const ShardInfo& first, size_t k, size_t n, const Where& w) {
  if (k > 1 && (s.job != first.job || s.surface != first.surface || s.samplesU != first.samplesU ||
                s.samplesV != first.samplesV || s.totalItems != first.totalItems || s.shardCount != first.shardCount)) {
    refuse(w, "belongs to another job than SHARD[1] (" + describe(s) + "; SHARD[1]: " + describe(first) + ")");
  }
  const std::string kn = std::to_string(s.shardIndex) + "/" + std::to_string(s.shardCount);
  if (static_cast<size_t>(s.shardIndex) != k) {
    refuse(w, "is shard " + kn + ", expected shard " + std::to_string(k) + "/" + std::to_string(s.shardCount) +
                  " (give the shards in order 1..N, each once)");
  }
  if (static_cast<size_t>(s.shardCount) != n) {
    refuse(w, "is shard " + kn + " of a job of " + std::to_string(s.shardCount) + " shards, but " + std::to_string(n) +
                  (n == 1 ? " was" : " were") + " given (give all N shards, in order)");
  }
  const uint64_t a = shardBound(s.totalItems, k - 1, n), b = shardBound(s.totalItems, k, n);
  if (s.firstItem != a || s.endItem() != b) {
    refuse(w, "holds items " + std::to_string(s.firstItem) + ".." + std::to_string(s.endItem()) + ", but shard " + kn +
                  " of " + std::to_string(s.totalItems) + " items is " + std::to_string(a) + ".." + std::to_string(b));
  }
}

// Items of a shard times a per-item count, overflow-checked.
uint64_t perItem(const ShardInfo& s, uint64_t each, const Where& w, const char* what) {
  uint64_t r = 0;
  if (!mulOk(s.itemCount, each, &r)) refuse(w, std::string("its ") + what + " overflow 64 bits");
  return r;
}

// The welded numbering of a shard's items; refuses a mesh line that does not fit the job line.
std::unique_ptr<WeldedNumbering> weldedNumbering(const ShardInfo& s, const MeshInfo& m, const Where& w) {
  if (m.patchesU * m.patchesV != s.totalItems || (!s.surface && (m.patchesV != 1 || m.closedV))) {
    refuse(w, "has a mesh line for " + std::to_string(m.patchesU) + "x" + std::to_string(m.patchesV) +
                  " items, but its job line says " + std::to_string(s.totalItems) + " " +
                  (s.surface ? "patches" : "spans"));
  }
  const WeldGrid grid(m.patchesU, m.patchesV, s.samplesU, s.surface ? s.samplesV : 1, m.closedU, m.closedV);
  return std::make_unique<WeldedNumbering>(grid, s.firstItem, s.endItem());
}

// The first metadata comment line in which a shard differs from SHARD[1]. Mesh shards must agree
// on every line (device and precision too): their welded vertices are then the unsharded file's.
std::string commentMismatch(const std::string& mine, const std::string& first) {
  size_t at = 0;
  while (at < mine.size() && at < first.size() && mine[at] == first[at]) ++at;
  const size_t start = mine.rfind('\n', at == 0 ? 0 : at - 1);
  const size_t from = start == std::string::npos || at == 0 ? 0 : start + 1;
  const size_t end = mine.find('\n', from);
  return "has the metadata line " + snippet(std::string_view(mine).substr(from, end == std::string::npos ? end : end - from)) +
         " where SHARD[1] differs (another job, device or precision; mesh shards must agree on every line)";
}

bool sameMesh(const MeshInfo& a, const MeshInfo& b) {
  return a.patchesU == b.patchesU && a.patchesV == b.patchesV && a.closedU == b.closedU && a.closedV == b.closedV &&
         a.reversed == b.reversed;
}

// ---- PLY ---------------------------------------------------------------------------------------

struct PlyShard {
  ShardInfo info;
  std::string source, properties;  // escaped source as written; vertex property lines
  std::optional<MeshInfo> mesh;    // welded files
  std::string comments;            // the other comment lines (job metadata), copied to the merged file
  std::unique_ptr<WeldedNumbering> numbering;
  bool faces = false;
  uint64_t vertices = 0, records = 0, vertexBytes = 0, recordBytes = 0, headerBytes = 0, fileBytes = 0;
};

PlyShard readPlyHeader(ShardFile& f) {
  const Where& w = f.where();
  PlyShard p;
  std::string line;
  bool complete = false;
  size_t n = 0;
  auto next = [&](const char* expected) {
    if (!f.line(line, kMaxPlyHeaderBytes, &complete) || !complete) {
      refuse(w, "is not a PLY file written by shapespline (the header ends before '" + std::string(expected) + "')");
    }
    ++n;
    p.headerBytes += line.size() + 1;
    if (p.headerBytes > kMaxPlyHeaderBytes) refuse(w, "has a PLY header longer than 64 KiB");
  };
  auto bad = [&](const char* expected) {
    refuse(w, "is not a PLY file written by shapespline (header line " + std::to_string(n) + " is " + snippet(line) +
                  ", expected " + expected + ")");
  };
  auto count = [&](std::string_view prefix, const char* expected) {
    if (!startsWith(line, prefix)) bad(expected);
    const auto v = parseCount(std::string_view(line).substr(prefix.size()), std::numeric_limits<uint64_t>::max());
    if (!v) refuse(w, "has an element count that is not an integer below 2^64 (" + snippet(line) + ")");
    return *v;
  };
  next("ply");
  if (line != "ply") bad("'ply'");
  next("format");
  if (line != "format binary_little_endian 1.0") bad("'format binary_little_endian 1.0'");
  next("comment");
  if (!startsWith(line, kPlySourcePrefix)) bad("'comment shapespline sample of ...'");
  p.source = line.substr(kPlySourcePrefix.size());
  next("comment");
  std::optional<ShardInfo> info;
  if (startsWith(line, kPlyJobPrefix)) info = parseShardInfoLine(std::string_view(line).substr(kPlyJobPrefix.size()));
  if (!info) bad("'comment shapespline job ...' (written by an older shapespline? sample again)");
  p.info = *info;
  while (true) {
    next("element vertex");
    if (!startsWith(line, kPlyJobPrefix)) break;
    const std::string_view text = std::string_view(line).substr(kPlyJobPrefix.size());
    if (startsWith(text, kMeshLinePrefix)) {
      if (p.mesh) bad("one 'comment shapespline mesh' line");
      p.mesh = parseMeshInfoLine(text);
      if (!p.mesh) bad("'comment shapespline mesh welded items PUxPV closed C orientation O'");
    } else {
      p.comments += line + "\n";
    }
  }
  p.vertices = count("element vertex ", "'element vertex N'");
  std::string type;
  while (true) {
    next("element");
    if (!startsWith(line, "property ")) break;
    const size_t sp = line.find(' ', 9);
    const std::string t = line.substr(9, sp == std::string::npos ? std::string::npos : sp - 9);
    const std::string name = sp == std::string::npos ? "" : line.substr(sp + 1);
    if ((t != "float" && t != "double") || (!type.empty() && t != type) || name.empty() ||
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos) {
      bad("'property float NAME' or 'property double NAME', one type for all");
    }
    type = t;
    p.vertexBytes += t == "float" ? 4 : 8;
    p.properties += line + "\n";
  }
  if (type.empty()) bad("'property float|double x'");
  if (startsWith(line, "element face ")) {
    p.faces = true;
    p.records = count("element face ", "'element face N'");
    next("property list");
    if (line != "property list uchar uint vertex_indices") bad("'property list uchar uint vertex_indices'");
    p.recordBytes = 13;
  } else {
    p.records = count("element edge ", "'element face N' or 'element edge N'");
    next("property");
    if (line != "property uint vertex1") bad("'property uint vertex1'");
    next("property");
    if (line != "property uint vertex2") bad("'property uint vertex2'");
    p.recordBytes = 8;
  }
  next("end_header");
  if (line != "end_header") bad("'end_header'");
  // Sizes, overflow-checked: a crafted count must not wrap around into a "matching" size.
  uint64_t vertexBlock = 0, recordBlock = 0, data = 0;
  if (!mulOk(p.vertices, p.vertexBytes, &vertexBlock) || !mulOk(p.records, p.recordBytes, &recordBlock) ||
      !addOk(vertexBlock, recordBlock, &data) || !addOk(data, p.headerBytes, &p.fileBytes)) {
    refuse(w, "has element counts whose sizes overflow 64 bits (" + std::to_string(p.vertices) + " vertices, " +
                  std::to_string(p.records) + (p.faces ? " faces)" : " edges)"));
  }
  if (f.size() != p.fileBytes) {
    refuse(w, "is " + std::to_string(f.size()) + " bytes, its header says " + std::to_string(p.fileBytes) +
                  (f.size() < p.fileBytes ? " (truncated?)" : ""));
  }
  const ShardInfo& s = p.info;
  if (s.surface != p.faces) {
    refuse(w, "has " + std::string(p.faces ? "faces" : "edges") + " but its job line says " +
                  (s.surface ? "surface" : "curve"));
  }
  const uint64_t su = static_cast<uint64_t>(s.samplesU), sv = static_cast<uint64_t>(s.samplesV);
  // Welded or not, the connectivity has the same count per item; checked first, so the welded
  // numbering below (which visits every item's boundary) is bounded by the file's size.
  const uint64_t r = perItem(s, s.surface ? 2 * (su - 1) * (sv - 1) : su - 1, w, s.surface ? "faces" : "edges");
  if (p.records != r) {
    refuse(w, "has " + std::to_string(p.records) + (p.faces ? " faces" : " edges") + ", but " +
                  std::to_string(s.itemCount) + " items of grid " + std::to_string(su) + "x" + std::to_string(sv) +
                  " have " + std::to_string(r));
  }
  if (p.mesh) p.numbering = weldedNumbering(s, *p.mesh, w);
  const uint64_t v = p.numbering ? p.numbering->vertexCount() : perItem(s, s.pointsPerItem(), w, "vertices");
  if (p.vertices != v || p.records != r) {
    refuse(w, "has " + std::to_string(p.vertices) + " vertices and " + std::to_string(p.records) +
                  (p.faces ? " faces" : " edges") + ", but " + std::to_string(s.itemCount) + " items of grid " +
                  std::to_string(su) + "x" + std::to_string(sv) + " have " + std::to_string(v) + " and " +
                  std::to_string(r));
  }
  return p;
}

MergeResult mergePly(const std::vector<std::string>& shards, AtomicFile& out) {
  std::vector<PlyShard> headers;
  uint64_t vertices = 0, records = 0;
  for (size_t k = 1; k <= shards.size(); ++k) {
    ShardFile f({shardField(k), shards[k - 1]});
    headers.push_back(readPlyHeader(f));
    const PlyShard& p = headers.back();
    checkSequence(p.info, headers.front().info, k, shards.size(), f.where());
    if (p.properties != headers.front().properties) {
      refuse(f.where(), "has other vertex properties than SHARD[1] (another job)");
    }
    const PlyShard& first = headers.front();
    if (p.mesh.has_value() != first.mesh.has_value() || (p.mesh && !sameMesh(*p.mesh, *first.mesh))) {
      refuse(f.where(), "has another mesh layout than SHARD[1] (another job)");
    }
    if (p.comments != first.comments) refuse(f.where(), commentMismatch(p.comments, first.comments));
    // Welded: the vertices each shard owns (its foreign ones are the next shards').
    vertices += p.numbering ? p.numbering->ownedCount() : p.vertices;  // each < 2^62 / 12 by the size check
    records += p.records;
    if (vertices > std::numeric_limits<uint32_t>::max()) {
      refuse(f.where(),
             "brings the merged PLY above 2^32-1 vertices (PLY stores 32-bit indices; merge to a raw format)");
    }
  }
  const PlyShard& first = headers.front();
  const ShardInfo whole = wholeJobOf(first.info);
  std::string h = "ply\nformat binary_little_endian 1.0\n" + plyInfoComments(whole, first.source);
  std::unique_ptr<WeldedNumbering> wholeNumbering;
  if (first.mesh) {
    h += std::string(kPlyJobPrefix) + meshInfoLine(*first.mesh) + "\n";
    wholeNumbering = weldedNumbering(whole, *first.mesh, {shardField(1), shards[0]});
  }
  h += first.comments + "element vertex " + std::to_string(vertices) + "\n" + first.properties;
  if (wholeNumbering) {
    h += plyConnectivityHeader(*wholeNumbering);
  } else {
    h += first.faces ? "element face " + std::to_string(records) + "\nproperty list uchar uint vertex_indices\n"
                     : "element edge " + std::to_string(records) + "\nproperty uint vertex1\nproperty uint vertex2\n";
  }
  h += "end_header\n";
  out.write(h);
  std::vector<char> buffer(kMergeBufferBytes);
  if (wholeNumbering) {
    // The vertices each shard owns, in shard order, then the connectivity of the whole grid.
    for (size_t k = 1; k <= shards.size(); ++k) {
      const PlyShard& p = headers[k - 1];
      ShardFile f({shardField(k), shards[k - 1]});
      if (f.size() != p.fileBytes) refuse(f.where(), "changed while merging");
      f.seek(p.headerBytes);
      copyBytes(f, out, p.numbering->ownedCount() * p.vertexBytes, buffer);
    }
    writePlyConnectivity(out, *wholeNumbering, first.mesh->reversed);
    return {whole.totalItems, out.bytesWritten()};
  }
  // Pass 1: the vertex blocks, in shard order.
  for (size_t k = 1; k <= shards.size(); ++k) {
    const PlyShard& p = headers[k - 1];
    ShardFile f({shardField(k), shards[k - 1]});
    if (f.size() != p.fileBytes) refuse(f.where(), "changed while merging");
    f.seek(p.headerBytes);
    copyBytes(f, out, p.vertices * p.vertexBytes, buffer);
  }
  // Pass 2: faces/edges with the vertex offset of their shard, chunk by chunk.
  uint64_t offset = 0;
  for (size_t k = 1; k <= shards.size(); ++k) {
    const PlyShard& p = headers[k - 1];
    ShardFile f({shardField(k), shards[k - 1]});
    if (f.size() != p.fileBytes) refuse(f.where(), "changed while merging");
    f.seek(p.headerBytes + p.vertices * p.vertexBytes);
    const size_t per = buffer.size() / p.recordBytes;
    const size_t skip = p.faces ? 1 : 0, indices = p.faces ? 3 : 2;
    for (uint64_t done = 0; done < p.records;) {
      const size_t n = static_cast<size_t>(std::min<uint64_t>(per, p.records - done));
      f.readExact(buffer.data(), n * p.recordBytes);
      for (size_t r = 0; r < n; ++r) {
        char* rec = buffer.data() + r * p.recordBytes;
        if (p.faces && rec[0] != 3) {
          refuse(f.where(), "face " + std::to_string(done + r) + " has " +
                                std::to_string(static_cast<unsigned char>(rec[0])) +
                                " vertices (shapespline writes triangles)");
        }
        for (size_t i = 0; i < indices; ++i) {
          uint32_t idx;
          std::memcpy(&idx, rec + skip + 4 * i, 4);
          if (idx >= p.vertices) {
            refuse(f.where(), std::string(p.faces ? "face " : "edge ") + std::to_string(done + r) +
                                  " refers to vertex " + std::to_string(idx) + " of its " + std::to_string(p.vertices));
          }
          idx += static_cast<uint32_t>(offset);  // < 2^32 - 1 in total, checked above
          std::memcpy(rec + skip + 4 * i, &idx, 4);
        }
      }
      out.write(buffer.data(), n * p.recordBytes);
      done += n;
    }
    f.expectEnd();
    offset += p.vertices;
  }
  return {whole.totalItems, out.bytesWritten()};
}

// ---- OBJ ---------------------------------------------------------------------------------------

// "x y z" (count numbers) as the writer prints them: finite, single spaces.
bool numbers(std::string_view s, int count) {
  for (int i = 0; i < count; ++i) {
    const size_t sp = s.find(' ');
    if ((sp == std::string_view::npos) != (i == count - 1)) return false;
    const std::string_view tok = s.substr(0, sp);
    double v = 0;
    const auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (tok.empty() || ec != std::errc() || p != tok.data() + tok.size() || !std::isfinite(v)) return false;
    if (sp != std::string_view::npos) s.remove_prefix(sp + 1);
  }
  return true;
}

// The body of a welded OBJ shard after its header (`line` holds the first body line): its vertex
// lines (v, vt, vn per vertex; curves: v), of which the first ownedCount() are copied to `out`,
// then its triangles or its one polyline, which are checked for shape and count only: `merge`
// writes the whole grid's connectivity itself.
void mergeWeldedObjBody(ShardFile& f, const ShardInfo& s, const WeldedNumbering& n, std::string& line, bool more,
                        uint64_t lineNo, AtomicFile& out) {
  const Where& w = f.where();
  auto at = [&] { return "line " + std::to_string(lineNo) + " "; };
  bool complete = true;
  const int per = objLinesPerVertex(s.surface);
  static constexpr const char* kPrefix[3] = {"v ", "vt ", "vn "};
  const uint64_t lines = n.vertexCount() * static_cast<uint64_t>(per), copied = n.ownedCount() * static_cast<uint64_t>(per);
  for (uint64_t k = 0; k < lines; ++k) {
    if (k > 0) {
      more = f.line(line, kMaxLineBytes, &complete);
      ++lineNo;
    }
    if (!more) refuse(w, "ends after " + std::to_string(k / per) + " of its " + std::to_string(n.vertexCount()) + " vertices");
    if (!complete) refuse(w, at() + "does not end with a newline (truncated?)");
    const int slot = static_cast<int>(k % static_cast<uint64_t>(per));
    const std::string_view prefix = kPrefix[slot];
    if (!startsWith(line, prefix) || !numbers(std::string_view(line).substr(prefix.size()), slot == 1 ? 2 : 3)) {
      refuse(w, at() + "is not the " + std::string(prefix.substr(0, prefix.size() - 1)) +
                    " line of a vertex with finite numbers: " + snippet(line));
    }
    if (k < copied) {
      out.write(line);
      out.write("\n", 1);
    }
  }
  if (s.surface) {
    uint64_t faces = 0;
    while (f.line(line, kMaxLineBytes, &complete)) {
      ++lineNo;
      if (!complete) refuse(w, at() + "does not end with a newline (truncated?)");
      if (!startsWith(line, "f ")) refuse(w, at() + "is not a face line: " + snippet(line));
      ++faces;
    }
    if (faces != n.triangleCount()) {
      refuse(w, "has " + std::to_string(faces) + " faces, but its " + std::to_string(s.itemCount) + " items have " +
                    std::to_string(n.triangleCount()) + " (truncated or extended?)");
    }
    return;
  }
  // Curves: one `l` line to the end of the file, read in blocks (it has a number per vertex).
  char head[2] = {0, 0};
  const size_t got = f.read(head, 2);
  if (n.polylineLength() == 0 ? got != 0 : got != 2 || head[0] != 'l' || head[1] != ' ') {
    refuse(w, "line " + std::to_string(lineNo + 1) + " is not the curve's one 'l' polyline line");
  }
  if (got == 0) return;
  std::vector<char> block(kMergeBufferBytes);
  char last = ' ';
  while (true) {
    const size_t r = f.read(block.data(), block.size());
    if (r == 0) break;
    const void* nl = std::memchr(block.data(), '\n', r);
    if (nl && static_cast<const char*>(nl) != block.data() + r - 1) {
      refuse(w, "has more after its 'l' polyline line (extended?)");
    }
    last = block[r - 1];
  }
  if (last != '\n') refuse(w, "does not end its 'l' polyline line with a newline (truncated?)");
}

MergeResult mergeObj(const std::vector<std::string>& shards, AtomicFile& out) {
  uint64_t total[3] = {0, 0, 0};  // v, vt, vn written so far
  std::optional<ShardInfo> first;
  std::optional<MeshInfo> firstMesh;
  std::string firstComments;
  std::string line, o;
  for (size_t k = 1; k <= shards.size(); ++k) {
    ShardFile f({shardField(k), shards[k - 1]});
    const Where& w = f.where();
    const uint64_t start[3] = {total[0], total[1], total[2]};
    std::optional<ShardInfo> info;
    std::optional<std::string> source;
    std::optional<MeshInfo> mesh;
    std::string comments;  // the other header comments (job metadata), copied to the merged file
    bool header = true, complete = false;
    uint64_t lineNo = 0, faces = 0, polylines = 0;
    auto at = [&] { return "line " + std::to_string(lineNo) + " "; };
    auto endHeader = [&] {
      header = false;
      if (!source || !info) {
        refuse(w, "has no '# shapespline sample of' and '# shapespline job' lines (not written by this shapespline? "
                  "sample again)");
      }
      checkSequence(*info, first ? *first : *info, k, shards.size(), w);
      if (first && (mesh.has_value() != firstMesh.has_value() || (mesh && !sameMesh(*mesh, *firstMesh)))) {
        refuse(w, "has another mesh layout than SHARD[1] (another job)");
      }
      if (first && comments != firstComments) refuse(w, commentMismatch(comments, firstComments));
      if (mesh) {
        // Each item brings at least 2 (Su-1)(Sv-1) face lines of 12+ bytes or Su-1 indices of 2+
        // bytes: a header claiming more items than the file can hold is refused before the
        // numbering visits them.
        const uint64_t su = static_cast<uint64_t>(info->samplesU), sv = static_cast<uint64_t>(info->samplesV);
        const uint64_t least = perItem(*info, info->surface ? 24 * (su - 1) * (sv - 1) : 2 * (su - 1), w, "bytes");
        if (least > f.size()) refuse(w, "is too short for the " + std::to_string(info->itemCount) + " items its job line names");
      }
      if (!first) {
        first = info;
        firstMesh = mesh;
        firstComments = comments;
        std::string h = objHeader(wholeJobOf(*info), *source, mesh.has_value());
        if (mesh) h += std::string(kObjJobPrefix) + meshInfoLine(*mesh) + "\n";
        out.write(h + comments);
      }
    };
    // Index part `s` of vertex slot `slot` -> absolute index in the merged file.
    auto absolute = [&](std::string_view s, int slot) {
      const bool negative = !s.empty() && s[0] == '-';
      const auto v = parseCount(negative ? s.substr(1) : s, io::kMaxItemCount);
      if (!v || *v == 0) {
        refuse(w, at() + "has the index " + snippet(s) + " (expected a nonzero integer within the file)");
      }
      const uint64_t have = total[slot] - start[slot];
      if (*v > have) {
        refuse(w, at() + "refers to vertex " + snippet(s) + " outside the " + std::to_string(have) +
                      " of this shard before it");
      }
      return negative ? total[slot] - *v + 1 : start[slot] + *v;
    };
    bool welded = false;
    while (f.line(line, kMaxLineBytes, &complete)) {
      ++lineNo;
      if (!complete) refuse(w, at() + "does not end with a newline (truncated?)");
      if (header && !line.empty() && line[0] == '#') {
        if (startsWith(line, kObjSourcePrefix) && !source) {
          source = line.substr(kObjSourcePrefix.size());
        } else if (startsWith(line, "# shapespline job ")) {
          info = parseShardInfoLine(std::string_view(line).substr(kObjJobPrefix.size()));
          if (!info) refuse(w, at() + "is not a valid '# shapespline job' line");
        } else if (startsWith(std::string_view(line).substr(std::min<size_t>(line.size(), kObjJobPrefix.size())),
                              kMeshLinePrefix) &&
                   startsWith(line, kObjJobPrefix)) {
          if (mesh) refuse(w, at() + "is a second '# shapespline mesh' line");
          mesh = parseMeshInfoLine(std::string_view(line).substr(kObjJobPrefix.size()));
          if (!mesh) refuse(w, at() + "is not a valid '# shapespline mesh' line");
        } else if (!startsWith(line, "# patches ") && !startsWith(line, "# spans ")) {
          comments += line + "\n";  // the item-range line is regenerated, the rest copied
        }
        continue;
      }
      if (header) endHeader();
      if (mesh) {
        const std::unique_ptr<WeldedNumbering> n = weldedNumbering(*info, *mesh, w);
        mergeWeldedObjBody(f, *info, *n, line, true, lineNo, out);
        total[0] += n->ownedCount();
        welded = true;
        break;
      }
      const ShardInfo& s = *info;
      if (startsWith(line, "v ") || startsWith(line, "vn ") || startsWith(line, "vt ")) {
        const int slot = line[1] == ' ' ? 0 : line[1] == 't' ? 1 : 2;
        if (slot != 0 && !s.surface) refuse(w, at() + "is a " + snippet(line.substr(0, 2)) + " line in a curve");
        if (!numbers(std::string_view(line).substr(slot == 0 ? 2 : 3), slot == 1 ? 2 : 3)) {
          refuse(w, at() + "is not a vertex line with finite numbers: " + snippet(line));
        }
        ++total[slot];
        out.write(line);
        out.write("\n", 1);
      } else if (startsWith(line, "f ") || startsWith(line, "l ")) {
        const bool face = line[0] == 'f';
        if (face != s.surface) refuse(w, at() + "is " + (face ? "a face in a curve" : "a polyline in a surface"));
        o.assign(1, line[0]);
        size_t tokens = 0, pos = 2;
        while (pos <= line.size()) {
          const size_t sp = line.find(' ', pos);
          const std::string_view tok =
              std::string_view(line).substr(pos, sp == std::string::npos ? std::string::npos : sp - pos);
          o += ' ';
          if (face) {
            const size_t s1 = tok.find('/'), s2 = s1 == std::string_view::npos ? s1 : tok.find('/', s1 + 1);
            if (s2 == std::string_view::npos || tok.find('/', s2 + 1) != std::string_view::npos) {
              refuse(w, at() + "has the face vertex " + snippet(tok) + " (expected v/vt/vn)");
            }
            o += std::to_string(absolute(tok.substr(0, s1), 0)) + "/" +
                 std::to_string(absolute(tok.substr(s1 + 1, s2 - s1 - 1), 1)) + "/" +
                 std::to_string(absolute(tok.substr(s2 + 1), 2));
          } else {
            o += std::to_string(absolute(tok, 0));
          }
          ++tokens;
          if (sp == std::string::npos) break;
          pos = sp + 1;
        }
        const uint64_t expected = face ? 3 : static_cast<uint64_t>(s.samplesU);
        if (tokens != expected) {
          refuse(w, at() + "has " + std::to_string(tokens) + " vertices, expected " + std::to_string(expected));
        }
        (face ? faces : polylines) += 1;
        o += '\n';
        out.write(o);
      } else {
        refuse(w, at() + "is not a v, vt, vn, f or l line as shapespline writes them: " + snippet(line));
      }
    }
    if (header) endHeader();
    if (mesh && !welded) {  // a header without a body: an empty shard
      const std::unique_ptr<WeldedNumbering> n = weldedNumbering(*info, *mesh, w);
      if (n->vertexCount() != 0) refuse(w, "ends after its header, before its " + std::to_string(n->vertexCount()) + " vertices");
      welded = true;
    }
    if (welded) continue;
    const ShardInfo& s = *info;
    const uint64_t su = static_cast<uint64_t>(s.samplesU), sv = static_cast<uint64_t>(s.samplesV);
    const uint64_t v = perItem(s, s.pointsPerItem(), w, "vertices");
    const uint64_t cells = perItem(s, s.surface ? 2 * (su - 1) * (sv - 1) : 1, w, "faces");
    const uint64_t got[3] = {total[0] - start[0], total[1] - start[1], total[2] - start[2]};
    const uint64_t aux = s.surface ? v : 0;
    if (got[0] != v || got[1] != aux || got[2] != aux || (s.surface ? faces : polylines) != cells) {
      refuse(w, "has " + std::to_string(got[0]) + " v, " + std::to_string(got[1]) + " vt, " + std::to_string(got[2]) +
                    " vn and " + std::to_string(s.surface ? faces : polylines) + (s.surface ? " faces" : " polylines") +
                    ", but its " + std::to_string(s.itemCount) + " items have " + std::to_string(v) + " v and " +
                    std::to_string(cells) + " (truncated or extended?)");
    }
  }
  if (firstMesh) {
    const ShardInfo whole = wholeJobOf(*first);
    const std::unique_ptr<WeldedNumbering> n = weldedNumbering(whole, *firstMesh, {shardField(1), shards[0]});
    writeObjConnectivity(out, *n, firstMesh->reversed);
  }
  return {first->totalItems, out.bytesWritten()};
}

// ---- CSV ---------------------------------------------------------------------------------------

MergeResult mergeCsv(const std::vector<std::string>& shards, AtomicFile& out) {
  std::string header, line;
  size_t commas = 0, keys = 0;
  uint64_t rowsPerItem = 0, items = 0;
  size_t rowsShard = 0;
  bool haveKey = false;
  uint64_t prev[2] = {0, 0};
  for (size_t k = 1; k <= shards.size(); ++k) {
    ShardFile f({shardField(k), shards[k - 1]});
    const Where& w = f.where();
    bool complete = false;
    if (!f.line(line, kMaxLineBytes, &complete) || !complete) refuse(w, "has no complete header line");
    if (k == 1) {
      header = line;
      keys = startsWith(header, "patch_i,patch_j,u,v,U,V,") ? 2 : startsWith(header, "span,t,u,") ? 1 : 0;
      if (keys == 0) refuse(w, "is not a CSV written by shapespline (header " + snippet(header) + ")");
      commas = static_cast<size_t>(std::count(header.begin(), header.end(), ','));
      out.write(header);
      out.write("\n", 1);
    } else if (line != header) {
      refuse(w, "has another header line than SHARD[1] (another job: other fields, kind or dimension)");
    }
    const char* item = keys == 2 ? "patch" : "span";
    uint64_t lineNo = 1, groupRows = 0, cur[2] = {0, 0};
    bool inGroup = false;
    auto endGroup = [&] {
      if (rowsPerItem == 0) {
        rowsPerItem = groupRows;
        rowsShard = k;
      } else if (groupRows != rowsPerItem) {
        refuse(w, "has " + std::to_string(groupRows) + " rows per " + item + " (" + item + " " +
                      std::to_string(cur[0]) + (keys == 2 ? "," + std::to_string(cur[1]) : "") + "), SHARD[" +
                      std::to_string(rowsShard) + "] " + std::to_string(rowsPerItem) + " (another grid?)");
      }
      ++items;
    };
    while (f.line(line, kMaxLineBytes, &complete)) {
      ++lineNo;
      const std::string at = "line " + std::to_string(lineNo) + " ";
      if (!complete) refuse(w, at + "does not end with a newline (truncated?)");
      const size_t c = static_cast<size_t>(std::count(line.begin(), line.end(), ','));
      if (c != commas) {
        refuse(w, at + "has " + std::to_string(c + 1) + " columns, the header " + std::to_string(commas + 1));
      }
      uint64_t key[2] = {0, 0};
      size_t pos = 0;
      for (size_t i = 0; i < keys; ++i) {
        const size_t comma = line.find(',', pos);
        const auto v = parseCount(std::string_view(line).substr(pos, comma - pos), std::numeric_limits<int>::max());
        if (!v) refuse(w, at + "has a " + item + " index that is not a non-negative integer");
        key[i] = *v;
        pos = comma + 1;
      }
      if (!inGroup || key[0] != cur[0] || key[1] != cur[1]) {
        if (inGroup) endGroup();
        if (haveKey && !(key[0] > prev[0] || (key[0] == prev[0] && key[1] > prev[1]))) {
          refuse(w, at + "has " + item + " " + std::to_string(key[0]) +
                        (keys == 2 ? "," + std::to_string(key[1]) : "") + " after " + item + " " +
                        std::to_string(prev[0]) + (keys == 2 ? "," + std::to_string(prev[1]) : "") +
                        " (items out of order: give the shards in order 1..N, each once)");
        }
        cur[0] = prev[0] = key[0];
        cur[1] = prev[1] = key[1];
        haveKey = inGroup = true;
        groupRows = 0;
      }
      ++groupRows;
      out.write(line);
      out.write("\n", 1);
    }
    if (inGroup) endGroup();
  }
  return {items, out.bytesWritten()};
}

// ---- Raw ---------------------------------------------------------------------------------------


// Typed access to a sidecar with errors naming the key.
class SidecarReader {
 public:
  SidecarReader(const nlohmann::json& doc, const Where& w) : doc_(doc), w_(w) {}

  const nlohmann::json& at(const nlohmann::json& obj, const char* key, const std::string& path) const {
    if (!obj.is_object() || !obj.contains(key)) {
      refuse(w_, "sidecar lacks \"" + path + "\" (not a shapespline raw sidecar)");
    }
    return obj[key];
  }
  const nlohmann::json& at(const std::string& path) const {
    const nlohmann::json* j = &doc_;
    size_t pos = 0;
    while (true) {
      const size_t dot = path.find('.', pos);
      j = &at(*j, path.substr(pos, dot - pos).c_str(), path);
      if (dot == std::string::npos) return *j;
      pos = dot + 1;
    }
  }
  uint64_t u64(const std::string& path, uint64_t lo, uint64_t hi) const {
    const nlohmann::json& j = at(path);
    if (!j.is_number_unsigned() || j.get<uint64_t>() < lo || j.get<uint64_t>() > hi) {
      refuse(w_, "sidecar \"" + path + "\" must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "]");
    }
    return j.get<uint64_t>();
  }
  std::string str(const std::string& path) const {
    const nlohmann::json& j = at(path);
    if (!j.is_string()) refuse(w_, "sidecar \"" + path + "\" must be a string");
    return j.get<std::string>();
  }
  std::string oneOf(const std::string& path, std::initializer_list<const char*> allowed) const {
    const std::string s = str(path);
    std::string list;
    for (const char* a : allowed) {
      if (s == a) return s;
      list += std::string(list.empty() ? "" : " or ") + "\"" + a + "\"";
    }
    refuse(w_, "sidecar \"" + path + "\" must be " + list + " (got " + snippet(s) + ")");
  }
  std::vector<int> ints(const std::string& path) const {
    const nlohmann::json& j = at(path);
    if (!j.is_array()) refuse(w_, "sidecar \"" + path + "\" must be an array");
    std::vector<int> v;
    v.reserve(j.size());
    for (const auto& e : j) {
      if (!e.is_number_unsigned() || e.get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int>::max())) {
        refuse(w_, "sidecar \"" + path + "\" must hold non-negative integers");
      }
      v.push_back(static_cast<int>(e.get<uint64_t>()));
    }
    return v;
  }
  [[noreturn]] void inconsistent(const std::string& what) const { refuse(w_, "sidecar is inconsistent: " + what); }

 private:
  const nlohmann::json& doc_;
  const Where& w_;
};

// A sidecar's JSON object (grid and trimmed sidecars alike): at most kMaxSidecarBytes, nested at
// most kMaxSidecarDepth deep, or MergeError.
nlohmann::json readSidecarJson(const Where& w) {
  ShardFile f(w);
  if (f.size() > kMaxSidecarBytes) {
    refuse(w, "sidecar is larger than " + std::to_string(kMaxSidecarBytes >> 20) + " MiB");
  }
  std::string text(static_cast<size_t>(f.size()), '\0');
  f.readExact(text.data(), text.size());
  f.expectEnd();
  if (!jsonDepthWithin(text, kMaxSidecarDepth)) {
    refuse(w, "sidecar nests deeper than " + std::to_string(kMaxSidecarDepth) + " levels (not a shapespline sidecar)");
  }
  nlohmann::json doc = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded()) refuse(w, "sidecar is not valid JSON");
  if (!doc.is_object()) refuse(w, "sidecar is not a JSON object");
  return doc;
}

// `float64`: the dtype the data file's extension implies (nullopt for .npy, whose header says it).
RawSidecar readSidecar(const Where& w, std::optional<bool> float64) {
  const nlohmann::json doc = readSidecarJson(w);
  const SidecarReader r(doc, w);
  if (r.str("format") != "shapespline-raw") refuse(w, "sidecar \"format\" is not \"shapespline-raw\"");
  const uint64_t version = r.u64("format_version", 1, 1000);
  if (version != kRawSidecarVersion) {
    refuse(w, "sidecar has format_version " + std::to_string(version) + ", merge reads " +
                  std::to_string(kRawSidecarVersion) + " (written by another shapespline version? sample again)");
  }
  RawSidecar s;
  s.dataFile = r.str("data_file");
  s.float64 = r.oneOf("dtype", {"float64", "float32"}) == "float64";
  if (float64 && s.float64 != *float64) refuse(w, "sidecar dtype does not match the data file's extension");
  r.oneOf("byte_order", {"little"});
  ShardInfo& i = s.info;
  i.surface = r.oneOf("kind", {"curve", "surface"}) == "surface";
  if (r.oneOf("item", {"span", "patch"}) != (i.surface ? "patch" : "span")) r.inconsistent("\"item\" and \"kind\"");
  const nlohmann::json& fields = r.at("fields");
  if (!fields.is_array() || fields.empty() || fields.size() > static_cast<size_t>(kFieldCount)) {
    refuse(w, "sidecar \"fields\" must be an array of 1 to " + std::to_string(kFieldCount) + " field names");
  }
  for (const auto& f : fields) {
    bool known = false;
    for (int k = 0; k < kFieldCount && f.is_string(); ++k) {
      known |= f.get<std::string>() == fieldName(static_cast<Field>(k));
    }
    if (!known) refuse(w, "sidecar \"fields\" holds something that is not a field name");
    s.fields.push_back(f.get<std::string>());
  }
  if (r.u64("components", 0, 1000) != 3) r.inconsistent("\"components\" must be 3");
  if (r.u64("values_per_record", 0, 1000) != s.valuesPerRecord()) r.inconsistent("\"values_per_record\"");
  i.samplesU = static_cast<int>(r.u64("grid.samples_u", 2, 65536));
  i.samplesV = static_cast<int>(r.u64("grid.samples_v", i.surface ? 2 : 1, i.surface ? 65536 : 1));
  if (r.u64("grid.points_per_item", 0, uint64_t{1} << 40) != i.pointsPerItem()) {
    r.inconsistent("\"grid.points_per_item\"");
  }
  i.totalItems = r.u64("items.total", 0, io::kMaxItemCount);
  i.firstItem = r.u64("items.first", 0, i.totalItems);
  i.itemCount = r.u64("items.count", 0, i.totalItems - i.firstItem);
  s.itemsV = r.u64("items.items_v", 1, std::max<uint64_t>(1, i.totalItems));
  if (!i.surface && s.itemsV != 1) r.inconsistent("\"items.items_v\" of a curve must be 1");
  if (i.totalItems % s.itemsV != 0) r.inconsistent("\"items.total\" is not a multiple of \"items.items_v\"");
  i.shardCount = static_cast<int>(r.u64("shard.count", 1, io::kMaxShardCount));
  i.shardIndex = static_cast<int>(r.u64("shard.index", 1, static_cast<uint64_t>(i.shardCount)));
  i.job = r.str("job");
  if (i.job.size() != 16 || i.job.find_first_not_of("0123456789abcdef") != std::string::npos) {
    refuse(w, "sidecar \"job\" is not 16 hex digits");
  }
  s.computedDouble = r.oneOf("computed_precision", {"double", "float"}) == "double";
  s.device = r.str("device");
  s.source = r.str("source");
  try {
    s.metadata = metadataFromJson(r.at("metadata"));
  } catch (const MetadataError& e) {
    refuse(w, std::string("sidecar ") + e.what());
  }
  // Counts follow from the item range; every product overflow-checked.
  uint64_t points = 0, values = 0, bytes = 0;
  if (!mulOk(i.itemCount, i.pointsPerItem(), &points) || !mulOk(points, s.valuesPerRecord(), &values) ||
      !mulOk(values, s.valueSize(), &bytes)) {
    refuse(w, "sidecar counts overflow 64 bits");
  }
  constexpr uint64_t kAny = std::numeric_limits<uint64_t>::max();
  if (r.u64("counts.items", 0, kAny) != i.itemCount || r.u64("counts.points", 0, kAny) != points ||
      r.u64("counts.values", 0, kAny) != values || r.u64("counts.bytes", 0, kAny) != bytes) {
    r.inconsistent("\"counts\" do not follow from the item range, grid and fields");
  }
  const SpanWindow win = spanWindow(i.firstItem, i.itemCount, s.itemsV);
  s.spansUOffset = r.u64("items.spans_u_offset", 0, io::kMaxItemCount);
  s.spansVOffset = r.u64("items.spans_v_offset", 0, io::kMaxItemCount);
  s.spansU = r.ints("items.spans_u");
  s.spansV = r.ints("items.spans_v");
  if (s.spansUOffset != win.row0 || s.spansU.size() != win.row1 - win.row0 || s.spansVOffset != win.col0 ||
      s.spansV.size() != win.col1 - win.col0) {
    r.inconsistent("the span lists do not cover the rows and columns of the item range");
  }
  return s;
}

// Places `part` (starting at `offset`) into `merged`, which holds the rows/columns seen so far.
void placeSpans(std::vector<int>& merged, std::vector<char>& seen, uint64_t offset, const std::vector<int>& part,
                const Where& w, const char* name) {
  for (size_t k = 0; k < part.size(); ++k) {
    const uint64_t at = offset + k;
    if (at >= merged.size()) refuse(w, std::string("sidecar \"") + name + "\" reaches beyond the model");
    if (seen[at] && merged[at] != part[k]) {
      refuse(w, std::string("sidecar \"") + name + "\" differs from an earlier shard's at " + std::to_string(at) +
                    " (another job)");
    }
    merged[at] = part[k];
    seen[at] = 1;
  }
}

// Raw shards (`npy` false: the data file is the records) and .npy shards (`npy` true: each file is
// its .npy header, exactly as the sidecar's fields, dtype and item count give it, then the records;
// the merged file is the whole job's header and the records). Either way the merged sidecar is
// rebuilt: the unsharded job's, but for its data_file name.
MergeResult mergeRaw(const std::vector<std::string>& shards, bool npy, std::optional<bool> float64, AtomicFile& out,
                     AtomicFile& sidecar) {
  std::vector<RawSidecar> sides;
  std::vector<uint64_t> sizes, offsets;
  for (size_t k = 1; k <= shards.size(); ++k) {
    const Where sideWhere{shardField(k), shards[k - 1] + ".json"};
    ShardFile data({shardField(k), shards[k - 1]});
    RawSidecar s = readSidecar(sideWhere, float64);
    const RawSidecar& first = sides.empty() ? s : sides.front();
    checkSequence(s.info, first.info, k, shards.size(), sideWhere);
    // The device (and so the computed precision) may differ between shards: the data is the same job.
    if (s.fields != first.fields || s.itemsV != first.itemsV || s.float64 != first.float64) {
      refuse(sideWhere, "sidecar describes another job than SHARD[1]'s (fields, precision or grid differ)");
    }
    // The metadata is the job's, the same in every shard (device and computed precision aside, as above).
    JobMetadata meta = s.metadata;
    meta.device = first.metadata.device;
    meta.computedPrecision = first.metadata.computedPrecision;
    if (const std::string key = metadataDifference(meta, first.metadata); !key.empty()) {
      refuse(sideWhere, "sidecar \"metadata." + key + "\" differs from SHARD[1]'s (another model, job or build)");
    }
    const uint64_t points = s.info.itemCount * s.info.pointsPerItem();
    const uint64_t bytes = points * s.valuesPerRecord() * s.valueSize();
    uint64_t offset = 0;
    if (npy) {
      const std::string expected = npyHeader(s.fields, s.float64, points);
      std::string header(std::min<uint64_t>(data.size(), expected.size()), '\0');
      data.readExact(header.data(), header.size());
      if (header != expected) {
        refuse(data.where(), "does not start with the .npy header its sidecar describes (" +
                                 std::to_string(points) + " records of " + (s.float64 ? "<f8" : "<f4") +
                                 " fields; not a shard of this job, or changed after sampling)");
      }
      offset = expected.size();
    }
    if (data.size() != offset + bytes) {
      refuse(data.where(), "is " + std::to_string(data.size()) + " bytes, its sidecar says " +
                               std::to_string(offset + bytes) + (data.size() < offset + bytes ? " (truncated?)" : ""));
    }
    sizes.push_back(bytes);
    offsets.push_back(offset);
    sides.push_back(std::move(s));
  }
  // Every shard is verified, so the item total is backed by real data: the span lists fit.
  const RawSidecar& first = sides.front();
  const uint64_t total = first.info.totalItems, itemsV = first.itemsV;
  std::vector<int> spansU(total == 0 ? 0 : total / itemsV), spansV(total == 0 ? 0 : itemsV);
  std::vector<char> seenU(spansU.size()), seenV(spansV.size());
  for (size_t k = 1; k <= shards.size(); ++k) {
    const Where w{shardField(k), shards[k - 1] + ".json"};
    placeSpans(spansU, seenU, sides[k - 1].spansUOffset, sides[k - 1].spansU, w, "items.spans_u");
    placeSpans(spansV, seenV, sides[k - 1].spansVOffset, sides[k - 1].spansV, w, "items.spans_v");
    sides[k - 1].spansU.clear();
    sides[k - 1].spansV.clear();
  }
  if (std::find(seenU.begin(), seenU.end(), 0) != seenU.end() ||
      std::find(seenV.begin(), seenV.end(), 0) != seenV.end()) {
    refuse({shardField(1), shards[0] + ".json"}, "the shards' span lists leave rows or columns of the model out");
  }
  if (npy) {
    uint64_t points = 0;
    if (!mulOk(total, first.info.pointsPerItem(), &points)) {
      refuse({shardField(1), shards[0] + ".json"}, "the merged point count overflows 64 bits");
    }
    out.write(npyHeader(first.fields, first.float64, points));
  }
  std::vector<char> buffer(kMergeBufferBytes);
  for (size_t k = 1; k <= shards.size(); ++k) {
    ShardFile data({shardField(k), shards[k - 1]});
    if (data.size() != offsets[k - 1] + sizes[k - 1]) refuse(data.where(), "changed while merging");
    data.seek(offsets[k - 1]);
    copyBytes(data, out, sizes[k - 1], buffer);
    data.expectEnd();
  }
  RawSidecar merged = first;
  for (const RawSidecar& s : sides) {
    merged.computedDouble = merged.computedDouble && s.computedDouble;  // the least precise shard's
    if (s.device != first.device) merged.device = "mixed";
  }
  merged.metadata.device = merged.device;
  merged.metadata.computedPrecision = merged.computedDouble ? Precision::Double : Precision::Float;
  merged.info = wholeJobOf(first.info);
  merged.spansUOffset = merged.spansVOffset = 0;
  merged.spansU = std::move(spansU);
  merged.spansV = std::move(spansV);
  merged.dataFile = out.target().filename().string();
  writeRawSidecar(sidecar, merged);
  return {total, out.bytesWritten()};
}

// ---- Trimmed point clouds (sample --trim, sample part.json): records joined in shard order --------
//
// A shard carries io::TrimmedShard: in its raw sidecar as "shard", in its PLY header as a "comment
// shard: " line. Everything else in the sidecar or header is the whole job's, the same in every
// shard but for the record count; the merged file is shard 1's with the shard taken out and the
// count of all records put in, then every shard's records in order: the unsharded job's bytes.

constexpr std::string_view kTrimmedSidecarFormat = "shapespline-trimmed-points";
constexpr std::string_view kTrimmedPlyComment = "comment shapespline trimmed point cloud";

// What one trimmed shard holds: its identity, the whole job's header or sidecar without it, and
// where its records lie.
struct TrimmedPart {
  io::TrimmedShard shard;
  std::string header;        // PLY: the header without the shard line, its vertex count left out
  nlohmann::json sidecar;    // raw and .npy: the sidecar without "shard", "records" and "data"
  uint64_t dataOffset = 0;   // the first record's byte in the data file
  uint64_t recordBytes = 0;
};

io::TrimmedShard trimmedShardOf(const nlohmann::json& j, const Where& w) {
  const std::optional<io::TrimmedShard> s = io::TrimmedShard::fromJson(j);
  if (!s) refuse(w, "has a malformed trimmed shard description (" + snippet(j.dump()) + ")");
  return *s;
}

// A trimmed PLY shard's header, read up to end_header (at most kMaxPlyHeaderBytes).
TrimmedPart readTrimmedPly(ShardFile& f) {
  const Where& w = f.where();
  TrimmedPart p;
  std::string line;
  bool complete = false, shardSeen = false, vertexSeen = false;
  std::string type;
  uint64_t headerBytes = 0, vertices = 0;
  while (true) {
    if (!f.line(line, kMaxPlyHeaderBytes, &complete) || !complete) refuse(w, "has a PLY header that does not end");
    headerBytes += line.size() + 1;
    if (headerBytes > kMaxPlyHeaderBytes) refuse(w, "has a PLY header longer than 64 KiB");
    if (line == "end_header") break;
    if (startsWith(line, io::kTrimmedShardComment)) {
      const nlohmann::json j = nlohmann::json::parse(line.substr(io::kTrimmedShardComment.size()), nullptr, false);
      if (shardSeen) refuse(w, "has two 'comment shard:' lines");
      p.shard = trimmedShardOf(j, w);
      shardSeen = true;
      continue;
    }
    if (startsWith(line, "element vertex ")) {
      const auto v = parseCount(std::string_view(line).substr(15), io::kMaxItemCount);
      if (!v || vertexSeen) refuse(w, "has a malformed 'element vertex' line (" + snippet(line) + ")");
      vertices = *v;
      vertexSeen = true;
      p.header += "element vertex \n";
      continue;
    }
    if (startsWith(line, "property ")) {
      const std::string t = line.substr(9, line.find(' ', 9) - 9);  // npos - 9 still reads to the end
      if ((t != "float" && t != "double") || (!type.empty() && t != type)) refuse(w, "has a property that is not float or double, or mixes them");
      type = t;
      p.recordBytes += t == "float" ? 4 : 8;
    } else if (startsWith(line, "element ")) {
      refuse(w, "has another element than its vertices (a trimmed point cloud has none)");
    }
    p.header += line + "\n";
  }
  if (!shardSeen) refuse(w, "is a trimmed point cloud without a 'comment shard:' line (not a shard: sample it with --shard)");
  if (!vertexSeen || p.recordBytes == 0) refuse(w, "has no vertices with properties");
  if (vertices != p.shard.records) refuse(w, "has " + std::to_string(vertices) + " vertices, its shard line says " + std::to_string(p.shard.records));
  p.dataOffset = headerBytes;
  return p;
}

// A trimmed raw or .npy shard's sidecar (SHARD.json) and, for .npy, its header checked against it.
TrimmedPart readTrimmedRaw(ShardFile& data, const Where& sideWhere, bool npy, std::optional<bool> float64) {
  TrimmedPart p;
  nlohmann::json doc = readSidecarJson(sideWhere);
  if (stringOr(doc, "format") != kTrimmedSidecarFormat) refuse(sideWhere, "sidecar is not a trimmed point cloud's");
  if (!doc.contains("shard")) refuse(sideWhere, "sidecar has no \"shard\" (not a shard: sample it with --shard)");
  p.shard = trimmedShardOf(doc["shard"], sideWhere);
  const std::string dtype = stringOr(doc, "dtype");
  if ((dtype != "<f8" && dtype != "<f4") || (float64 && *float64 != (dtype == "<f8")))
    refuse(sideWhere, "sidecar \"dtype\" is not the data file's (\"<f8\" for .f64, \"<f4\" for .f32)");
  const nlohmann::json& fields = doc.contains("fields") ? doc["fields"] : nlohmann::json();
  if (!fields.is_array() || fields.empty() || fields.size() > 16) refuse(sideWhere, "sidecar \"fields\" is malformed");
  std::vector<std::pair<std::string, int>> npyFields;
  uint64_t components = 0;
  for (const nlohmann::json& f : fields) {
    if (!f.is_object() || !f.contains("name") || !f["name"].is_string() || !f.contains("components") ||
        !f["components"].is_number_unsigned() || f["components"].get<uint64_t>() > 3 || f["components"].get<uint64_t>() < 1)
      refuse(sideWhere, "sidecar \"fields\" is malformed");
    npyFields.emplace_back(f["name"].get<std::string>(), f["components"].get<int>());
    components += f["components"].get<uint64_t>();
  }
  const bool f64 = dtype == "<f8";
  p.recordBytes = components * (f64 ? 8 : 4);
  if (npy) {
    const std::string expected = io::npyHeader(npyFields, f64, p.shard.records);
    std::string head(expected.size(), '\0');
    if (data.size() < head.size() || data.read(head.data(), head.size()) != head.size() || head != expected)
      refuse(data.where(), "does not begin with the .npy header its sidecar describes");
    p.dataOffset = expected.size();
  }
  if (unsignedOr(doc, "records") != p.shard.records) refuse(sideWhere, "sidecar \"records\" differs from its shard's");
  doc.erase("shard");
  doc.erase("records");
  doc.erase("data");
  p.sidecar = std::move(doc);
  return p;
}

MergeResult mergeTrimmed(const std::vector<std::string>& shards, OutputFormat format, AtomicFile& out,
                         AtomicFile* sidecarOut) {
  const bool npy = format == OutputFormat::Npy, ply = format == OutputFormat::Ply;
  const std::optional<bool> float64 = format == OutputFormat::RawF64   ? std::optional<bool>(true)
                                      : format == OutputFormat::RawF32 ? std::optional<bool>(false)
                                                                       : std::nullopt;
  std::vector<TrimmedPart> parts;
  for (size_t k = 1; k <= shards.size(); ++k) {
    const Where where{shardField(k), shards[k - 1]}, sideWhere{shardField(k), shards[k - 1] + ".json"};
    ShardFile data(where);
    TrimmedPart p = ply ? readTrimmedPly(data) : readTrimmedRaw(data, sideWhere, npy, float64);
    const io::TrimmedShard& s = p.shard;
    uint64_t bytes = 0, size = 0;
    if (!mulOk(s.records, p.recordBytes, &bytes) || !addOk(bytes, p.dataOffset, &size) || data.size() != size)
      refuse(where, "is " + std::to_string(data.size()) + " bytes, its header and shard description say " + std::to_string(size));
    if (s.index != static_cast<int>(k) || s.count != static_cast<int>(shards.size()))
      refuse(where, "is shard " + std::to_string(s.index) + "/" + std::to_string(s.count) + ", expected " +
                        std::to_string(k) + "/" + std::to_string(shards.size()) + " (give the shards 1..N in order)");
    const uint64_t itemsBefore = parts.empty() ? 0 : parts.back().shard.firstItem + parts.back().shard.items;
    const uint64_t recordsBefore = parts.empty() ? 0 : parts.back().shard.firstRecord + parts.back().shard.records;
    if (!parts.empty()) {
      const TrimmedPart& first = parts.front();
      if (s.job != first.shard.job || s.totalItems != first.shard.totalItems || s.totalRecords != first.shard.totalRecords)
        refuse(where, "is a shard of another job than SHARD[1]'s (job " + s.job + ", SHARD[1]'s " + first.shard.job + ")");
      if (p.header != first.header || p.sidecar != first.sidecar)
        refuse(where, "describes its job otherwise than SHARD[1] (another device, build or model?)");
    }
    if (s.firstItem != itemsBefore || s.firstRecord != recordsBefore)
      refuse(where, "starts at item " + std::to_string(s.firstItem) + ", record " + std::to_string(s.firstRecord) +
                        "; the shards before it end at item " + std::to_string(itemsBefore) + ", record " +
                        std::to_string(recordsBefore));
    if (k == shards.size() && (s.firstItem + s.items != s.totalItems || s.firstRecord + s.records != s.totalRecords))
      refuse(where, "ends before the job's last item: a shard is missing");
    parts.push_back(std::move(p));
  }
  const io::TrimmedShard& last = parts.back().shard;
  if (ply) {
    std::string header = parts.front().header;
    const size_t at = header.find("element vertex \n") + 15;
    header.insert(at, std::to_string(last.totalRecords));
    out.write(header + "end_header\n");
  } else if (npy) {
    std::vector<std::pair<std::string, int>> fields;
    for (const nlohmann::json& f : parts.front().sidecar["fields"]) fields.emplace_back(f["name"], f["components"].get<int>());
    out.write(io::npyHeader(fields, parts.front().sidecar["dtype"] == "<f8", last.totalRecords));
  }
  std::vector<char> buffer(kMergeBufferBytes);
  for (size_t k = 1; k <= shards.size(); ++k) {
    ShardFile data({shardField(k), shards[k - 1]});
    data.seek(parts[k - 1].dataOffset);
    copyBytes(data, out, parts[k - 1].shard.records * parts[k - 1].recordBytes, buffer);
    data.expectEnd();
  }
  if (sidecarOut) {
    nlohmann::json side = parts.front().sidecar;
    side["records"] = last.totalRecords;
    side["data"] = out.target().filename().string();
    sidecarOut->write(side.dump(1) + "\n");
  }
  return {last.totalItems, out.bytesWritten()};
}

// Whether shard 1 is a trimmed point cloud (its sidecar's format, or its PLY header's third line).
bool isTrimmedShard(const std::string& shard, OutputFormat format) {
  if (format == OutputFormat::Ply) {
    ShardFile f({shardField(1), shard});
    std::string line;
    bool complete = false;
    for (int n = 0; n < 3; ++n)
      if (!f.line(line, kMaxPlyHeaderBytes, &complete)) return false;
    return startsWith(line, kTrimmedPlyComment);
  }
  if (format != OutputFormat::Npy && format != OutputFormat::RawF32 && format != OutputFormat::RawF64) return false;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(shard + ".json", ec)) return false;
  return stringOr(readSidecarJson({shardField(1), shard + ".json"}), "format") == kTrimmedSidecarFormat;
}

// ---- Projections (project --shard): each file its header, then its records ---------------------

// Shard 1's record when it is a projection's (`project` writes one beside every shard).
std::optional<ShardRecord> projectionRecord(const std::string& shard) {
  std::error_code ec;
  const std::filesystem::path path = shardRecordPath(shard);
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) return std::nullopt;
  try {
    ShardRecord r = readShardRecord(path);
    if (!r.projection.empty()) return r;
  } catch (const ShardRecordError&) {
    // mergeInputs has named it already; a sampling job's merge reports what it reads.
  }
  return std::nullopt;
}

io::ProjectionTarget projectionTargetOf(const std::string& name) {
  return name == "part" ? io::ProjectionTarget::Part : name == "curve" ? io::ProjectionTarget::Curve
                                                                         : io::ProjectionTarget::Surface;
}

// The shards' records say they are shards 1..N of one projection, in order, covering every point;
// each file is the header of its own count, then exactly its records, which are copied under the
// header of the whole count: the unsharded job's bytes.
MergeResult mergeProjection(const std::vector<std::string>& shards, AtomicFile& out) {
  std::vector<ShardRecord> records;
  for (size_t k = 1; k <= shards.size(); ++k) {
    const Where w{shardField(k), shards[k - 1]};
    std::error_code ec;
    if (!std::filesystem::exists(std::filesystem::symlink_status(shardRecordPath(w.path), ec)))
      refuse(w, "has no shard record beside it (" + shardRecordPath(w.path).filename().string() +
                    "), which `project --shard` writes; project the shard again");
    try {
      records.push_back(readShardRecord(shardRecordPath(w.path)));
    } catch (const ShardRecordError& e) {
      refuse(w, std::string("its shard record ") + e.what());
    }
  }
  const ShardRecord& first = records.front();
  uint64_t next = 0;
  for (size_t k = 1; k <= shards.size(); ++k) {
    const Where w{shardField(k), shards[k - 1]};
    const ShardRecord& r = records[k - 1];
    if (r.projection.empty()) refuse(w, "is a sampling job's shard, SHARD[1] a projection's");
    if (r.job != first.job || r.projection != first.projection || r.format != first.format ||
        r.totalItems != first.totalItems)
      refuse(w, "belongs to another projection than SHARD[1] (job " + r.job + ", SHARD[1]: job " + first.job + ")");
    if (static_cast<size_t>(r.shardCount) != shards.size())
      refuse(w, "is shard " + std::to_string(r.shardIndex) + "/" + std::to_string(r.shardCount) + ", but " +
                    std::to_string(shards.size()) + " shards were given (give all N, in order)");
    if (static_cast<size_t>(r.shardIndex) != k)
      refuse(w, "is shard " + std::to_string(r.shardIndex) + "/" + std::to_string(r.shardCount) + ", given as shard " +
                    std::to_string(k) + " (give the shards in order)");
    if (r.firstItem != next) refuse(w, "starts at point " + std::to_string(r.firstItem) + ", not " + std::to_string(next));
    next += r.itemCount;
  }
  if (next != first.totalItems)
    refuse({shardField(shards.size()), shards.back()},
           "ends at point " + std::to_string(next) + " of " + std::to_string(first.totalItems));

  const io::ProjectionFormat format = io::projectionFormat(shards.front(), shardField(1));
  const io::ProjectionTarget target = projectionTargetOf(first.projection);
  const uint64_t recordBytes = io::projectionRecordBytes(format, target);
  out.write(io::projectionHeader(format, target, first.totalItems));
  std::vector<char> buffer(kMergeBufferBytes);
  for (size_t k = 1; k <= shards.size(); ++k) {
    ShardFile data({shardField(k), shards[k - 1]});
    const uint64_t count = records[k - 1].itemCount;
    const std::string header = io::projectionHeader(format, target, count);
    std::string got(header.size(), '\0');
    if (data.read(got.data(), got.size()) != got.size() || got != header)
      refuse(data.where(), "does not start with the header of a projection of its " + std::to_string(count) + " points");
    const uint64_t body = data.size() - header.size();
    if (recordBytes == 0) {
      // CSV: whole lines, one per point.
      uint64_t lines = 0, left = body;
      char last = '\n';
      while (left > 0) {
        const size_t take = static_cast<size_t>(std::min<uint64_t>(left, buffer.size()));
        data.readExact(buffer.data(), take);
        lines += static_cast<uint64_t>(std::count(buffer.data(), buffer.data() + take, '\n'));
        last = buffer[take - 1];
        out.write(buffer.data(), take);
        left -= take;
      }
      if (lines != count || last != '\n')
        refuse(data.where(), "holds " + std::to_string(lines) + " whole lines, its record says " + std::to_string(count));
    } else {
      uint64_t want = 0;
      if (!mulOk(count, recordBytes, &want) || body != want)
        refuse(data.where(), "is " + std::to_string(data.size()) + " bytes, not its header and " + std::to_string(count) +
                                 " records of " + std::to_string(recordBytes) + " bytes");
      copyBytes(data, out, body, buffer);
    }
    data.expectEnd();
  }
  return {first.totalItems, out.bytesWritten()};
}

}  // namespace

MergeResult mergeShards(const std::vector<std::string>& shards, const std::string& output) {
  const OutputFormat format = outputFormatFromPath(output, "-o");
  io::requireGridFormat(format, output, "-o");
  if (format == OutputFormat::Svg) throw MergeError("-o", shown(output), "SVG files do not merge");
  if (isGltf(format)) throw MergeError("-o", shown(output), "glTF files do not merge (sample them unsharded)");
  if (shards.empty()) throw MergeError("SHARD", "", "give the shard files 1..N");
  for (size_t k = 1; k <= shards.size(); ++k) {
    if (outputFormatFromPath(shards[k - 1], shardField(k)) != format) {
      refuse({shardField(k), shards[k - 1]}, "must have the output's extension (." +
                                                 std::string(outputFormatName(format)) + ")");
    }
  }
  // Data and sidecar are one output set: both appear, or neither changes (io/output_set.h).
  OutputSet files;
  for (size_t k = 1; k <= shards.size(); ++k) {
    files.reads(shards[k - 1], shardField(k));
    files.reads(shards[k - 1] + ".json", shardField(k) + " sidecar");
    files.reads(shardRecordPath(shards[k - 1]), shardField(k) + " record");
  }
  AtomicFile& out = files.add(output, "-o");
  MergeResult result;
  if (projectionRecord(shards.front())) {
    result = mergeProjection(shards, out);
    files.commit();
    return result;
  }
  if (isTrimmedShard(shards.front(), format)) {
    AtomicFile* side = format == OutputFormat::Ply ? nullptr : &files.add(output + ".json", "-o");
    result = mergeTrimmed(shards, format, out, side);
    files.commit();
    return result;
  }
  switch (format) {
    case OutputFormat::Obj: result = mergeObj(shards, out); break;
    case OutputFormat::Ply: result = mergePly(shards, out); break;
    case OutputFormat::Csv: result = mergeCsv(shards, out); break;
    case OutputFormat::RawF32:
    case OutputFormat::RawF64:
      result = mergeRaw(shards, false, format == OutputFormat::RawF64, out, files.add(output + ".json", "-o"));
      break;
    case OutputFormat::Npy: result = mergeRaw(shards, true, std::nullopt, out, files.add(output + ".json", "-o")); break;
    case OutputFormat::Svg:
    case OutputFormat::Glb:
    case OutputFormat::Gltf:
    case OutputFormat::Stl: break;
  }
  files.commit();
  return result;
}

}  // namespace shapespline::jobs
