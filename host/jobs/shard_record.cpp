#include <shapespline/jobs/shard_record.h>

#include <shapespline/io/json_depth.h>
#include <shapespline/io/shard_info.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <limits>

namespace shapespline::jobs {

using io::JobMetadata;
using io::MetadataError;
using io::jsonDepthWithin;
using io::metadataFromJson;
using io::metadataJson;
using io::sha256OfFile;

namespace fs = std::filesystem;

namespace {

constexpr int kMaxRecordDepth = 16;
constexpr uint64_t kMaxCount = std::numeric_limits<uint64_t>::max();

bool isHex(std::string_view s, size_t n) {
  return s.size() == n && s.find_first_not_of("0123456789abcdef") == std::string_view::npos;
}


const nlohmann::json& member(const nlohmann::json& obj, const char* key, const std::string& path) {
  if (!obj.is_object()) throw ShardRecordError(path, "must be a JSON object");
  const auto it = obj.find(key);
  if (it == obj.end()) throw ShardRecordError(path.empty() ? key : path + "." + key, "is missing");
  return *it;
}

std::string keyOf(const std::string& path, const char* key) { return path.empty() ? key : path + "." + key; }

uint64_t u64(const nlohmann::json& obj, const char* key, uint64_t lo, uint64_t hi, const std::string& path = "") {
  const nlohmann::json& v = member(obj, key, path);
  if (!v.is_number_unsigned() || v.get<uint64_t>() < lo || v.get<uint64_t>() > hi) {
    throw ShardRecordError(keyOf(path, key),
                           "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return v.get<uint64_t>();
}

std::string str(const nlohmann::json& obj, const char* key, const std::string& path = "") {
  const nlohmann::json& v = member(obj, key, path);
  if (!v.is_string()) throw ShardRecordError(keyOf(path, key), "must be a string");
  return v.get<std::string>();
}

bool plainFileName(const std::string& name) {
  return !name.empty() && name.size() <= 255 && name != "." && name != ".." &&
         name.find('/') == std::string::npos && name.find('\0') == std::string::npos;
}

const char* kKeys[] = {"format", "format_version", "job", "kind", "target", "output_format", "shard",
                       "items", "points", "vertices", "files", "metadata"};

}  // namespace

fs::path shardRecordPath(const fs::path& dataPath) {
  fs::path p = dataPath;
  p += std::string(kShardRecordSuffix);
  return p;
}

std::string shardRecordJson(const ShardRecord& r) {
  nlohmann::ordered_json j;
  j["format"] = "shapespline-shard";
  j["format_version"] = kShardRecordVersion;
  j["job"] = r.job;
  j["kind"] = !r.projection.empty() ? "projection" : r.surface ? "surface" : "curve";
  if (!r.projection.empty()) j["target"] = r.projection;
  j["output_format"] = r.format;
  j["shard"] = {{"index", r.shardIndex}, {"count", r.shardCount}};
  j["items"] = {{"first", r.firstItem}, {"count", r.itemCount}, {"total", r.totalItems}};
  j["points"] = r.points;
  j["vertices"] = r.vertices;
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const auto& f : r.files) {
    files.push_back({{"name", f.name}, {"role", f.role}, {"bytes", f.bytes}, {"sha256", f.sha256}});
  }
  j["files"] = std::move(files);
  // metadataJson is a plain (sorted) json; its text parses back to the same object. A projection's
  // shard has none: what it projects and onto what is in its job fingerprint.
  if (r.projection.empty()) j["metadata"] = nlohmann::ordered_json::parse(metadataJson(r.metadata).dump());
  return j.dump(2, ' ', /*ensure_ascii=*/false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

ShardRecord parseShardRecord(std::string_view text) {
  if (!jsonDepthWithin(text, kMaxRecordDepth)) {
    throw ShardRecordError("", "nests deeper than " + std::to_string(kMaxRecordDepth) + " levels (not a shard record)");
  }
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded()) throw ShardRecordError("", "is not valid JSON");
  if (!doc.is_object()) throw ShardRecordError("", "is not a JSON object");
  for (const auto& [key, value] : doc.items()) {
    bool known = false;
    for (const char* k : kKeys) known |= key == k;
    if (!known) throw ShardRecordError(key.substr(0, 60), "is not a key of a shard record");
  }
  if (str(doc, "format") != "shapespline-shard") throw ShardRecordError("format", "must be \"shapespline-shard\"");
  const uint64_t version = u64(doc, "format_version", 1, 1000);
  if (version != kShardRecordVersion) {
    throw ShardRecordError("format_version", "is " + std::to_string(version) + ", this shapespline reads " +
                                                 std::to_string(kShardRecordVersion));
  }
  ShardRecord r;
  r.job = str(doc, "job");
  if (!isHex(r.job, 16)) throw ShardRecordError("job", "must be 16 lowercase hex digits");
  const std::string kind = str(doc, "kind");
  if (kind != "curve" && kind != "surface" && kind != "projection")
    throw ShardRecordError("kind", "must be \"curve\", \"surface\" or \"projection\"");
  if (kind == "projection") {
    r.projection = str(doc, "target");
    if (r.projection != "surface" && r.projection != "part" && r.projection != "curve")
      throw ShardRecordError("target", "must be \"surface\", \"part\" or \"curve\"");
  } else if (doc.contains("target")) {
    throw ShardRecordError("target", "belongs to a projection's shard only");
  }
  r.surface = kind == "surface" || (kind == "projection" && r.projection != "curve");
  r.format = str(doc, "output_format");
  static const char* kFormats[] = {"obj", "ply", "csv", "f32", "f64", "npy", "svg", "glb", "gltf"};
  bool known = false;
  for (const char* f : kFormats) known |= r.format == f;
  if (!known) throw ShardRecordError("output_format", "must be one of obj ply csv f32 f64 npy svg glb gltf");
  const nlohmann::json& shard = member(doc, "shard", "");
  r.shardCount = static_cast<int>(u64(shard, "count", 1, 1'000'000'000, "shard"));
  r.shardIndex = static_cast<int>(u64(shard, "index", 1, static_cast<uint64_t>(r.shardCount), "shard"));
  const nlohmann::json& items = member(doc, "items", "");
  r.totalItems = u64(items, "total", 0, io::kMaxItemCount, "items");
  r.firstItem = u64(items, "first", 0, r.totalItems, "items");
  r.itemCount = u64(items, "count", 0, r.totalItems - r.firstItem, "items");
  r.points = u64(doc, "points", 0, kMaxCount);
  r.vertices = u64(doc, "vertices", 0, kMaxCount);
  const nlohmann::json& files = member(doc, "files", "");
  if (!files.is_array() || files.empty() || files.size() > kMaxShardRecordFiles) {
    throw ShardRecordError("files", "must be an array of 1 to " + std::to_string(kMaxShardRecordFiles) + " files");
  }
  for (size_t i = 0; i < files.size(); ++i) {
    const std::string at = "files[" + std::to_string(i) + "]";
    ShardRecordFile f;
    f.name = str(files[i], "name", at);
    if (!plainFileName(f.name)) {
      throw ShardRecordError(at + ".name", "must be a file name in the record's folder (no '/', at most 255 bytes)");
    }
    for (const auto& g : r.files) {
      if (g.name == f.name) throw ShardRecordError(at + ".name", "names a file listed before");
    }
    f.role = str(files[i], "role", at);
    if (f.role != "data" && f.role != "sidecar" && f.role != "buffer") {
      throw ShardRecordError(at + ".role", "must be \"data\", \"sidecar\" or \"buffer\"");
    }
    if ((f.role == "data") != (i == 0)) throw ShardRecordError(at + ".role", "the data file must be first, and once");
    f.bytes = u64(files[i], "bytes", 0, kMaxCount, at);
    f.sha256 = str(files[i], "sha256", at);
    if (!isHex(f.sha256, 64)) throw ShardRecordError(at + ".sha256", "must be 64 lowercase hex digits");
    r.files.push_back(std::move(f));
  }
  if (!r.projection.empty()) {
    if (doc.contains("metadata")) throw ShardRecordError("metadata", "belongs to a sampling job's shard only");
    return r;
  }
  try {
    r.metadata = metadataFromJson(member(doc, "metadata", ""));
  } catch (const MetadataError& e) {
    throw ShardRecordError(e.key(), std::string(e.what()).substr(e.key().size() + 3));
  }
  return r;
}

ShardRecord readShardRecord(const fs::path& path) {
  // O_NONBLOCK: a FIFO in the record's place never blocks the open (it is refused below).
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw ShardRecordError("", std::string("cannot be opened: ") + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw ShardRecordError("", std::string("cannot be read: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw ShardRecordError("", "is not a regular file");
  if (static_cast<uint64_t>(st.st_size) > kMaxShardRecordBytes) {
    throw ShardRecordError("", "is larger than " + std::to_string(kMaxShardRecordBytes >> 20) + " MiB");
  }
  std::string text(static_cast<size_t>(st.st_size), '\0');
  size_t got = 0;
  while (got < text.size()) {
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw ShardRecordError("", std::string("cannot be read: ") + std::strerror(errno));
    if (n == 0) break;
    got += static_cast<size_t>(n);
  }
  text.resize(got);
  return parseShardRecord(text);
}

ShardRecordFile describeShardFile(const fs::path& path, std::string role) {
  ShardRecordFile f;
  f.name = path.filename().string();
  f.role = std::move(role);
  std::error_code ec;
  f.sha256 = sha256OfFile(path);
  f.bytes = fs::file_size(path, ec);
  if (ec) throw std::runtime_error("cannot stat: " + ec.message());
  return f;
}

std::string verifyShardFile(const ShardRecordFile& f, const fs::path& path) {
  const std::string name = "'" + path.filename().string() + "'";
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (!fs::exists(st)) return name + " is missing";
  if (!fs::is_regular_file(st)) return name + " is not a regular file";
  const uint64_t size = fs::file_size(path, ec);
  if (ec) return name + " cannot be read: " + ec.message();
  if (size != f.bytes) return name + " is " + std::to_string(size) + " bytes, the record says " + std::to_string(f.bytes);
  std::string sha;
  try {
    sha = sha256OfFile(path);
  } catch (const std::exception& e) {
    return name + " cannot be read: " + e.what();
  }
  if (sha != f.sha256) return name + " has another SHA-256 than the record's (changed since it was written)";
  return "";
}

}  // namespace shapespline::jobs
