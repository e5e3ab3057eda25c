#include <shapespline/io/job_metadata.h>

#include <shapespline/core/family.h>
#include <shapespline/core/value_scan.h>
#include <shapespline/io/number_text.h>
#include <shapespline/io/text_escape.h>
#include <shapespline/version.h>

#include <openssl/evp.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace shapespline::io {
namespace {

using json = nlohmann::json;

const char* precisionName(Precision p) { return p == Precision::Double ? "double" : "float"; }

std::string number(double v) {
  char buf[kMaxNumberChars];
  return std::string(buf, writeNumber(buf, v));
}

std::string hexOf(const unsigned char* digest, unsigned size) {
  static const char* digits = "0123456789abcdef";
  std::string s;
  s.reserve(2 * size);
  for (unsigned i = 0; i < size; ++i) {
    s += digits[digest[i] >> 4];
    s += digits[digest[i] & 0xf];
  }
  return s;
}

// One SHA-256 computation through OpenSSL's EVP interface.
class Sha256 {
 public:
  Sha256() : ctx_(EVP_MD_CTX_new(), &EVP_MD_CTX_free) {
    if (!ctx_ || EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr) != 1) {
      throw std::runtime_error("OpenSSL SHA-256 is not available");
    }
  }
  void update(const void* data, size_t size) {
    if (size && EVP_DigestUpdate(ctx_.get(), data, size) != 1) throw std::runtime_error("OpenSSL SHA-256 failed");
  }
  std::string hex() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned size = 0;
    if (EVP_DigestFinal_ex(ctx_.get(), digest, &size) != 1) throw std::runtime_error("OpenSSL SHA-256 failed");
    return hexOf(digest, size);
  }

 private:
  std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> ctx_;
};

class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

// Traits of a family, with curves' single order even for families of two orders.
bool twoOrders(const JobMetadata& m) { return m.surface && familyOf(m.construction).twoOrders; }

// A list in comment text: "[a, b, c]".
template <class T, class F>
std::string listText(const std::vector<T>& v, F&& item) {
  std::string s = "[";
  for (size_t k = 0; k < v.size(); ++k) s += (k ? ", " : "") + item(v[k]);
  return s + "]";
}

// `s` as valid UTF-8 (invalid sequences replaced by U+FFFD), so that every dump() of the JSON works.
std::string utf8(const std::string& s) {
  if (std::all_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x80; })) return s;
  return json::parse(json(s).dump(-1, ' ', false, json::error_handler_t::replace)).get<std::string>();
}

[[noreturn]] void bad(const std::string& key, const std::string& rule) {
  throw MetadataError(key.empty() ? "metadata" : "metadata." + key, rule);
}

const json& member(const json& j, const char* key) {
  if (!j.contains(key)) bad(key, "is missing");
  return j[key];
}

std::string text(const json& j, const char* key) {
  const json& v = member(j, key);
  if (!v.is_string()) bad(key, "must be a string");
  return v.get<std::string>();
}

int integer(const json& j, const char* key, int lo, int hi) {
  const json& v = member(j, key);
  if (!v.is_number_integer() || v.get<int64_t>() < lo || v.get<int64_t>() > hi) {
    bad(key, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return static_cast<int>(v.get<int64_t>());
}

double real(const json& v, const std::string& key) {
  if (!v.is_number()) bad(key, "must be a number");
  return v.get<double>();
}

std::vector<double> reals(const json& v, const std::string& key) {
  if (!v.is_array()) bad(key, "must be an array of numbers");
  std::vector<double> out;
  out.reserve(v.size());
  for (const json& e : v) out.push_back(real(e, key));
  return out;
}

Precision precision(const json& j, const char* key) {
  const std::string s = text(j, key);
  if (s != "double" && s != "float") bad(key, "must be \"double\" or \"float\"");
  return s == "double" ? Precision::Double : Precision::Float;
}

// The grid "UxV" / "S" of the kind, each count in [2, 65536].
void parseGrid(const std::string& g, JobMetadata& m) {
  auto count = [&](std::string_view s) {
    if (s.empty() || s.size() > 5 || s.find_first_not_of("0123456789") != std::string_view::npos || s[0] == '0') {
      bad("grid", m.surface ? "must be \"UxV\"" : "must be \"S\"");
    }
    const int v = std::stoi(std::string(s));
    if (v < 2 || v > 65536) bad("grid", "counts must be in [2, 65536]");
    return v;
  };
  const size_t x = g.find('x');
  if (m.surface != (x != std::string::npos)) bad("grid", m.surface ? "must be \"UxV\"" : "must be \"S\"");
  m.samplesU = count(std::string_view(g).substr(0, x));
  m.samplesV = m.surface ? count(std::string_view(g).substr(x + 1)) : 1;
}

// The summary form of "alpha" and "singular_vertices" (more than kMetadataAlphaListMax values).
void readAlphaSummary(const json& a, const json& singular, JobMetadata& m) {
  auto nonNegative = [](const json& n) { return n.is_number_integer() && (n.is_number_unsigned() || n.get<int64_t>() >= 0); };
  auto count = [&](const json& j, const char* key, const std::string& name) {
    if (!j.contains(key) || !nonNegative(j[key])) bad(name, "must be a count");
    return j[key].get<uint64_t>();
  };
  if (a.size() != 4) bad("alpha", "must be {\"values\", \"shape\", \"min\", \"max\"}");
  JobMetadata::AlphaSummary& s = m.alphaSummary;
  s.count = count(a, "values", "alpha.values");
  const json& shape = member(a, "shape");
  if (!shape.is_array() || shape.size() != (m.surface ? 2u : 1u)) bad("alpha.shape", m.surface ? "must be [rows, cols]" : "must be [count]");
  for (const json& n : shape) {
    if (!nonNegative(n) || n.get<uint64_t>() == 0 || n.get<uint64_t>() > std::numeric_limits<int>::max()) {
      bad("alpha.shape", "must hold positive integers");
    }
  }
  if (m.surface) {
    m.rows = shape[0].get<int>();
    m.cols = shape[1].get<int>();
  }
  const uint64_t shapeCount = m.surface ? static_cast<uint64_t>(m.rows) * static_cast<uint64_t>(m.cols) : shape[0].get<uint64_t>();
  if (s.count != shapeCount || s.count <= kMetadataAlphaListMax) {
    bad("alpha.values", "must be the shape's count and more than " + std::to_string(kMetadataAlphaListMax));
  }
  s.min = real(member(a, "min"), "alpha.min");
  s.max = real(member(a, "max"), "alpha.max");
  if (!(s.min <= s.max)) bad("alpha", "min must not exceed max");
  if (!singular.is_object() || singular.size() != 1) bad("singular_vertices", "must be {\"count\": K} with a summarised alpha");
  s.singular = count(singular, "count", "singular_vertices.count");
  // What the range allows: no α = 1 unless 1 is in it, every vertex when the range is just 1.
  const bool oneInRange = s.min <= 1.0 && 1.0 <= s.max;
  if (s.singular > s.count || (!oneInRange && s.singular) || (s.min == 1.0 && s.max == 1.0 && s.singular != s.count)) {
    bad("singular_vertices.count", "must count the vertices whose alpha is 1");
  }
}

}  // namespace

bool JobMetadata::usesAlpha() const { return familyOf(construction).usesAlpha; }

std::string JobMetadata::grid() const {
  return surface ? std::to_string(samplesU) + "x" + std::to_string(samplesV) : std::to_string(samplesU);
}

void AlphaTally::add(const double* values, size_t count) {
  if (count == 0) return;
  const ValueRange r = valueRange(values, count);
  summary_.min = summary_.count == 0 ? r.min : std::min(summary_.min, r.min);
  summary_.max = summary_.count == 0 ? r.max : std::max(summary_.max, r.max);
  summary_.count += count;
  summary_.singular += static_cast<uint64_t>(std::count(values, values + count, 1.0));
  if (summary_.count <= kMetadataAlphaListMax) listed_.insert(listed_.end(), values, values + count);
  else listed_.clear();
}

void JobMetadata::setAlpha(const AlphaTally& values, int netRows, int netCols) {
  rows = netRows;
  cols = netCols;
  alphaSummary = values.summary();
  alpha = values.listed();
}

void JobMetadata::setAlpha(const std::vector<double>& values, int netRows, int netCols) {
  AlphaTally tally;
  tally.add(values.data(), values.size());
  setAlpha(tally, netRows, netCols);
}

std::vector<std::pair<int, int>> JobMetadata::singularVertices() const {
  std::vector<std::pair<int, int>> v;
  if (!usesAlpha()) return v;
  const size_t c = surface && cols > 0 ? static_cast<size_t>(cols) : 1;
  for (size_t k = 0; k < alpha.size(); ++k) {
    if (alpha[k] == 1.0) {
      v.emplace_back(surface ? static_cast<int>(k / c) : static_cast<int>(k), surface ? static_cast<int>(k % c) : 0);
    }
  }
  return v;
}

std::string metadataComments(const JobMetadata& m, std::string_view linePrefix) {
  const FamilyTraits& f = familyOf(m.construction);
  std::string s;
  auto line = [&](std::string_view key, const std::string& value) {
    s.append(linePrefix);
    s.append(key);
    s += ": ";
    s += value;
    s += '\n';
  };
  line("tool_version", "shapespline " + escapeText(m.toolVersion) + " (commit " + escapeText(m.toolCommit) + ")");
  line("model_file", escapeText(m.modelFile));
  line("model_sha256", m.modelSha256.empty() ? std::string("unknown") : escapeText(m.modelSha256));
  line("kind", m.surface ? "surface" : "curve");
  line("construction", std::string(f.name));
  if (f.usesDegree) line("degree", std::to_string(m.degree));
  if (f.usesOrder) {
    line("order", twoOrders(m) ? "[" + std::to_string(m.order) + ", " + std::to_string(m.orderV) + "]"
                               : std::to_string(m.order));
  }
  if (m.rational) line("rational", "true");
  if (f.usesLambda) line("lambda", number(m.lambda));
  if (f.usesMu) line("mu", listText(m.mu, number));
  if (f.usesAlpha) {
    const std::string shape = m.surface ? " (" + std::to_string(m.rows) + "x" + std::to_string(m.cols) + ")" : "";
    if (m.alphaSummary.count <= kMetadataCommentListMax) {
      if (m.surface && m.cols > 0) {
        std::string rows = "[";
        for (size_t r = 0; r * static_cast<size_t>(m.cols) < m.alpha.size(); ++r) {
          const auto first = m.alpha.begin() + static_cast<std::ptrdiff_t>(r * static_cast<size_t>(m.cols));
          const auto last = first + std::min<std::ptrdiff_t>(m.cols, m.alpha.end() - first);
          rows += (r ? ", " : "") + listText(std::vector<double>(first, last), number);
        }
        line("alpha", rows + "]");
      } else {
        line("alpha", listText(m.alpha, number));
      }
    } else {
      line("alpha", std::to_string(m.alphaSummary.count) + " values" + shape + ", min " + number(m.alphaSummary.min) +
                        ", max " + number(m.alphaSummary.max));
    }
    const auto singular = m.singularVertices();
    if (m.alphaListed() && singular.size() <= kMetadataCommentListMax) {
      // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "[" + std::string.
      line("singular_vertices", listText(singular, [&](const std::pair<int, int>& v) {
             std::string t;
             if (m.surface) t += '[';
             t += std::to_string(v.first);
             if (m.surface) {
               t += ", ";
               t += std::to_string(v.second);
               t += ']';
             }
             return t;
           }));
    } else {
      line("singular_vertices", std::to_string(m.alphaSummary.singular) + " vertices with alpha = 1");
    }
  }
  line("device", escapeText(m.device));
  line("computed_precision", precisionName(m.computedPrecision));
  line("output_precision", precisionName(m.outputPrecision));
  line("grid", m.grid());
  return s;
}

json metadataJson(const JobMetadata& m) {
  const FamilyTraits& f = familyOf(m.construction);
  json j = json::object();
  j["tool"] = "shapespline";
  j["tool_version"] = utf8(m.toolVersion);
  j["tool_commit"] = utf8(m.toolCommit);
  j["model_file"] = utf8(m.modelFile);
  j["model_sha256"] = utf8(m.modelSha256);
  j["kind"] = m.surface ? "surface" : "curve";
  j["construction"] = std::string(f.name);
  if (f.usesDegree) j["degree"] = m.degree;
  if (f.usesOrder) j["order"] = twoOrders(m) ? json::array({m.order, m.orderV}) : json(m.order);
  if (m.rational) j["rational"] = true;
  if (f.usesLambda) j["lambda"] = m.lambda;
  if (f.usesMu) j["mu"] = m.mu;
  if (f.usesAlpha && !m.alphaListed()) {
    j["alpha"] = {{"values", m.alphaSummary.count},
                  {"shape", m.surface ? json::array({m.rows, m.cols}) : json::array({m.alphaSummary.count})},
                  {"min", m.alphaSummary.min},
                  {"max", m.alphaSummary.max}};
    j["singular_vertices"] = {{"count", m.alphaSummary.singular}};
  } else if (f.usesAlpha) {
    if (m.surface) {
      json rows = json::array();
      const size_t c = m.cols > 0 ? static_cast<size_t>(m.cols) : 1;
      for (size_t k = 0; k < m.alpha.size(); k += c) {
        const auto first = m.alpha.begin() + static_cast<std::ptrdiff_t>(k);
        rows.push_back(std::vector<double>(first, first + static_cast<std::ptrdiff_t>(std::min(c, m.alpha.size() - k))));
      }
      j["alpha"] = std::move(rows);
    } else {
      j["alpha"] = m.alpha;
    }
    json singular = json::array();
    for (const auto& [i, k] : m.singularVertices()) {
      if (m.surface) singular.push_back(json::array({i, k}));
      else singular.push_back(i);
    }
    j["singular_vertices"] = std::move(singular);
  }
  j["device"] = utf8(m.device);
  j["computed_precision"] = precisionName(m.computedPrecision);
  j["output_precision"] = precisionName(m.outputPrecision);
  j["grid"] = m.grid();
  return j;
}

JobMetadata metadataFromJson(const json& j) {
  if (!j.is_object()) throw MetadataError("metadata", "must be an object");
  JobMetadata m;
  if (text(j, "tool") != "shapespline") bad("tool", "must be \"shapespline\"");
  m.toolVersion = text(j, "tool_version");
  m.toolCommit = text(j, "tool_commit");
  m.modelFile = text(j, "model_file");
  m.modelSha256 = text(j, "model_sha256");
  if (!m.modelSha256.empty() &&
      (m.modelSha256.size() != 64 || m.modelSha256.find_first_not_of("0123456789abcdef") != std::string::npos)) {
    bad("model_sha256", "must be 64 lowercase hex digits (or empty)");
  }
  const std::string kind = text(j, "kind");
  if (kind != "curve" && kind != "surface") bad("kind", "must be \"curve\" or \"surface\"");
  m.surface = kind == "surface";
  const FamilyTraits* f = familyNamed(text(j, "construction"));
  if (!f) bad("construction", "must name a construction (docs/format.md)");
  m.construction = f->construction;
  size_t keys = 11;  // tool ... construction, device ... grid
  if (f->usesDegree) m.degree = integer(j, "degree", 0, 1000), ++keys;
  if (f->usesOrder) {
    ++keys;
    if (twoOrders(m)) {
      const json& o = member(j, "order");
      if (!o.is_array() || o.size() != 2) bad("order", "must be [order_u, order_v]");
      for (const json& k : o) {
        if (!k.is_number_integer() || k.get<int64_t>() < 0 || k.get<int64_t>() > 1000) {
          bad("order", "must hold integers in [0, 1000]");
        }
      }
      m.order = static_cast<int>(o[0].get<int64_t>());
      m.orderV = static_cast<int>(o[1].get<int64_t>());
    } else {
      m.order = integer(j, "order", 0, 1000);
    }
  }
  if (j.contains("rational")) {
    if (m.construction != Construction::BSpline || j["rational"] != json(true))
      bad("rational", "must be true, and only for a bspline with weights");
    m.rational = true;
    ++keys;
  }
  if (f->usesLambda) m.lambda = real(member(j, "lambda"), "lambda"), ++keys;
  if (f->usesMu) m.mu = reals(member(j, "mu"), "mu"), ++keys;
  if (f->usesAlpha) {
    keys += 2;
    const json& a = member(j, "alpha");
    if (a.is_object()) {
      readAlphaSummary(a, member(j, "singular_vertices"), m);
    } else {
      if (!a.is_array()) bad("alpha", "must be an array");
      std::vector<double> values;
      int rows = 0, cols = 0;
      if (m.surface) {
        rows = static_cast<int>(std::min<size_t>(a.size(), std::numeric_limits<int>::max()));
        for (const json& row : a) {
          const std::vector<double> r = reals(row, "alpha");
          if (&row == &a.front()) cols = static_cast<int>(std::min<size_t>(r.size(), std::numeric_limits<int>::max()));
          if (r.size() != static_cast<size_t>(cols) || r.empty()) bad("alpha", "rows must be equally long, not empty");
          values.insert(values.end(), r.begin(), r.end());
        }
      } else {
        values = reals(a, "alpha");
      }
      if (values.size() > kMetadataAlphaListMax) {
        bad("alpha", "lists more than " + std::to_string(kMetadataAlphaListMax) + " values (larger nets are summarised)");
      }
      m.setAlpha(values, rows, cols);
      // The singular vertices follow from α; a list that does not is not what this tool wrote.
      if (metadataJson(m)["singular_vertices"] != member(j, "singular_vertices")) {
        bad("singular_vertices", "must list the vertices whose alpha is 1");
      }
    }
  }
  m.device = text(j, "device");
  m.computedPrecision = precision(j, "computed_precision");
  m.outputPrecision = precision(j, "output_precision");
  parseGrid(text(j, "grid"), m);
  if (j.size() != keys) bad("", "holds keys the construction does not use");
  return m;
}

std::string metadataDifference(const JobMetadata& a, const JobMetadata& b) {
  if (a.toolVersion != b.toolVersion) return "tool_version";
  if (a.toolCommit != b.toolCommit) return "tool_commit";
  if (a.modelFile != b.modelFile) return "model_file";
  if (a.modelSha256 != b.modelSha256) return "model_sha256";
  if (a.surface != b.surface) return "kind";
  if (a.construction != b.construction) return "construction";
  if (a.degree != b.degree) return "degree";
  if (a.order != b.order || a.orderV != b.orderV) return "order";
  if (a.rational != b.rational) return "rational";
  // Bitwise: -0 and 0 are different models' values; NaN cannot occur (validated models).
  if (std::memcmp(&a.lambda, &b.lambda, sizeof a.lambda) != 0) return "lambda";
  if (a.mu != b.mu) return "mu";
  if (a.alpha != b.alpha || a.alphaSummary != b.alphaSummary || a.rows != b.rows || a.cols != b.cols) return "alpha";
  if (a.device != b.device) return "device";
  if (a.computedPrecision != b.computedPrecision) return "computed_precision";
  if (a.outputPrecision != b.outputPrecision) return "output_precision";
  if (a.samplesU != b.samplesU || a.samplesV != b.samplesV) return "grid";
  return {};
}

std::string sha256Of(std::string_view bytes) {
  Sha256 h;
  h.update(bytes.data(), bytes.size());
  return h.hex();
}

namespace {

// Feeds a regular file's bytes to `h`, read in 64 KiB pieces; returns early once `stop` is set.
void hashFile(Sha256& h, const std::filesystem::path& path, const std::atomic<bool>* stop = nullptr) {
  // O_NONBLOCK: a FIFO put in the file's place never blocks the open (it is refused below).
  Fd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (fd.get() < 0) throw std::runtime_error(std::string("cannot open: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) throw std::runtime_error(std::string("cannot stat: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw std::runtime_error("not a regular file");
  std::vector<char> buffer(size_t{64} << 10);
  while (true) {
    const ssize_t n = ::read(fd.get(), buffer.data(), buffer.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("read failed: ") + std::strerror(errno));
    }
    if (n == 0 || (stop && *stop)) break;
    h.update(buffer.data(), static_cast<size_t>(n));
  }
}

}  // namespace

std::string sha256OfFile(const std::filesystem::path& path) {
  Sha256 h;
  hashFile(h, path);
  return h.hex();
}

namespace {

// Files hashed by ModelDigest::get() itself while they add up to at most this (0.15 ms at 1.7 GB/s):
// a thread's start and wake-ups cost about as much (a batch of small models started one per model).
constexpr uintmax_t kInlineDigestBytes = 256 << 10;

}  // namespace

struct ModelDigest::State {
  uintmax_t queuedBytes = 0;  // of the files added before the worker started
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<std::filesystem::path> files;  // added, not yet hashed
  bool closed = false;                      // get(): no more files
  std::atomic<bool> cancelled = false;      // destroyed without get()
  std::string digits;
  std::exception_ptr error;
  std::thread worker;

  std::optional<std::filesystem::path> next() {
    std::unique_lock lock(mutex);
    changed.wait(lock, [&] { return !files.empty() || closed || cancelled; });
    if (cancelled || files.empty()) return std::nullopt;
    std::filesystem::path file = std::move(files.front());
    files.pop_front();
    return file;
  }
  void run() {
    try {
      Sha256 h;
      while (const auto file = next()) hashFile(h, *file, &cancelled);
      digits = h.hex();
    } catch (...) {
      error = std::current_exception();
    }
  }
  void finish(bool cancel) {
    {
      std::lock_guard lock(mutex);
      closed = true;
      cancelled = cancel;
    }
    changed.notify_one();
    if (worker.joinable()) worker.join();
    else if (!cancel) run();  // everything was small: hashed here
  }
  // Queues `file`; starts the worker once the files are worth a thread (a size that cannot be read
  // counts as large: hashFile reports the error).
  void add(std::filesystem::path file) {
    if (!worker.joinable()) {  // sizes matter only until the worker runs
      std::error_code ec;
      const uintmax_t bytes = std::filesystem::file_size(file, ec);
      queuedBytes += ec ? kInlineDigestBytes + 1 : bytes;
    }
    {
      std::lock_guard lock(mutex);
      files.push_back(std::move(file));
    }
    if (worker.joinable()) changed.notify_one();
    else if (queuedBytes > kInlineDigestBytes) worker = std::thread([this] { run(); });
  }
};

ModelDigest::ModelDigest(std::filesystem::path modelFile) : state_(std::make_unique<State>()) {
  state_->add(std::move(modelFile));
}

ModelDigest::~ModelDigest() {
  if (state_->worker.joinable()) state_->finish(true);
}

void ModelDigest::add(const std::filesystem::path& arrayFile) { state_->add(arrayFile); }

std::string ModelDigest::get() {
  state_->finish(false);
  if (state_->error) std::rethrow_exception(state_->error);
  return std::move(state_->digits);
}

std::string modelSha256(const std::filesystem::path& modelPath, const std::vector<std::filesystem::path>& arrayFiles) {
  ModelDigest digest(modelPath);
  for (const std::filesystem::path& array : arrayFiles) digest.add(array);
  return digest.get();
}

namespace {

JobMetadata common(const FamilySpec& f, const std::string& modelPath, std::string modelSha256, std::string_view device,
                   Precision computed, Precision output) {
  JobMetadata m;
  m.toolVersion = SHAPESPLINE_VERSION_STRING;
  m.toolCommit = SHAPESPLINE_GIT_COMMIT;
  m.modelFile = modelPath;
  m.modelSha256 = std::move(modelSha256);
  // Only what the family uses, so that metadataFromJson(metadataJson(m)) == m.
  const FamilyTraits& t = familyOf(f.construction);
  m.construction = f.construction;
  if (t.usesDegree) m.degree = f.degree;
  if (t.usesOrder) m.order = f.order;
  if (t.usesLambda) m.lambda = f.lambda;
  if (t.usesMu) m.mu = f.mu;
  m.device = std::string(device);
  m.computedPrecision = computed;
  m.outputPrecision = output;
  return m;
}

}  // namespace

JobMetadata jobMetadataOf(const CurveModel& model, const std::string& modelPath, std::string modelSha256,
                          std::string_view device, Precision computedPrecision, Precision outputPrecision,
                          int samplesU) {
  AlphaTally alpha;
  alpha.add(model.alpha.data(), model.alpha.size());
  return jobMetadataOf(model, alpha, !model.weights.empty(), modelPath, std::move(modelSha256), device,
                       computedPrecision, outputPrecision, samplesU);
}

JobMetadata jobMetadataOf(const CurveModel& shape, const AlphaTally& alpha, bool rational, const std::string& modelPath,
                          std::string modelSha256, std::string_view device, Precision computedPrecision,
                          Precision outputPrecision, int samplesU) {
  JobMetadata m =
      common(shape.family, modelPath, std::move(modelSha256), device, computedPrecision, outputPrecision);
  m.surface = false;
  m.rational = rational;
  if (m.usesAlpha()) m.setAlpha(alpha, 0, 0);
  m.samplesU = samplesU;
  m.samplesV = 1;
  return m;
}

JobMetadata jobMetadataOf(const SurfaceShape& model, const AlphaTally& alpha, bool rational,
                          const std::string& modelPath, std::string modelSha256, std::string_view device,
                          Precision computedPrecision, Precision outputPrecision, int samplesU, int samplesV) {
  JobMetadata m =
      common(model.family, modelPath, std::move(modelSha256), device, computedPrecision, outputPrecision);
  m.surface = true;
  m.rational = rational;
  if (twoOrders(m)) m.orderV = model.orderV;
  if (m.usesAlpha()) m.setAlpha(alpha, model.rows, model.cols);
  m.samplesU = samplesU;
  m.samplesV = samplesV;
  return m;
}

JobMetadata jobMetadataOf(const Surface& surface, const std::string& modelPath, std::string modelSha256,
                          std::string_view device, Precision computedPrecision, Precision outputPrecision,
                          int samplesU, int samplesV) {
  const SurfaceShape& model = surface.model();
  AlphaTally alpha;
  alpha.add(model.alpha.data(), model.alpha.size());
  return jobMetadataOf(model, alpha, !surface.weights().empty(), modelPath, std::move(modelSha256), device,
                       computedPrecision, outputPrecision, samplesU, samplesV);
}

}  // namespace shapespline::io
