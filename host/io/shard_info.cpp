#include <shapespline/io/shard_info.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace shapespline::io {
namespace {

uint64_t loadWord(const unsigned char* p) {
  uint64_t w;
  std::memcpy(&w, p, 8);
  return w;
}

}  // namespace

// Arrays (a net can hold 10^8 values) go a word at a time, 8 times faster than byte-wise FNV:
// each word is xored in, multiplied, and its high half folded down so that the next multiply
// carries every bit of it (a multiply alone moves bits only upwards). Four words are mixed into
// four independent lanes (the multiply's latency, not its throughput, bounded a single chain),
// which then enter the hash in order; the words past a multiple of four follow one by one. Given
// in pieces, the words hash as one sequence: a group of four may span two pieces.
void FingerprintWords::begin(uint64_t h) {
  lane_[0] = h, lane_[1] = h ^ 1, lane_[2] = h ^ 2, lane_[3] = h ^ 3;
  carried_ = 0;
}

void FingerprintWords::add(const unsigned char* data, size_t count) {
  size_t i = 0;
  while (carried_ > 0 && i < count) {
    carry_[carried_++] = loadWord(data + 8 * i++);
    if (carried_ == 4) {
      for (int k = 0; k < 4; ++k) lane_[k] = mix(lane_[k], carry_[k]);
      carried_ = 0;
    }
  }
  // The lanes in locals: as members they could alias `data` (bytes), and would go to memory each step.
  uint64_t lane[4] = {lane_[0], lane_[1], lane_[2], lane_[3]};
  for (; i + 4 <= count; i += 4) {
    for (int k = 0; k < 4; ++k) lane[k] = mix(lane[k], loadWord(data + 8 * (i + size_t(k))));
  }
  std::copy(lane, lane + 4, lane_);
  for (; i < count; ++i) carry_[carried_++] = loadWord(data + 8 * i);
}

uint64_t FingerprintWords::end(uint64_t h) const {
  for (int k = 0; k < 4; ++k) h = mix(h, lane_[k]);
  for (int k = 0; k < carried_; ++k) h = mix(h, carry_[k]);
  return h;
}

namespace {

// 64-bit FNV-1a (Fowler, Noll, Vo): offset basis 14695981039346656037, prime 1099511628211.
class Fnv1a {
 public:
  Fnv1a() = default;
  explicit Fnv1a(uint64_t h) : h_(h) {}
  uint64_t value() const { return h_; }
  void bytes(const void* data, size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) {
      h_ ^= p[i];
      h_ *= 1099511628211ull;
    }
  }
  // Every value is hashed with a fixed width (and every sequence with its length), so that two
  // different inputs never produce the same byte stream.
  void u64(uint64_t v) {
    unsigned char b[8];
    for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
    bytes(b, 8);
  }
  void f64(double v) { u64(std::bit_cast<uint64_t>(v)); }
  void text(std::string_view s) {
    u64(s.size());
    bytes(s.data(), s.size());
  }
  void f64s(const std::vector<double>& v) {
    u64(v.size());
    words(reinterpret_cast<const unsigned char*>(v.data()), v.size());
  }
  // `count` 8-byte words as one sequence (FingerprintWords).
  void words(const unsigned char* data, size_t count) {
    FingerprintWords w;
    w.begin(h_);
    w.add(data, count);
    h_ = w.end(h_);
  }
  std::string hex() const {
    static const char* digits = "0123456789abcdef";
    std::string s(16, '0');
    for (int i = 0; i < 16; ++i) s[static_cast<size_t>(i)] = digits[(h_ >> (60 - 4 * i)) & 0xf];
    return s;
  }

 private:
  uint64_t h_ = 14695981039346656037ull;
};

void family(Fnv1a& h, const FamilySpec& f) {
  h.u64(static_cast<uint64_t>(f.construction));
  h.u64(static_cast<uint64_t>(f.degree));
  h.u64(static_cast<uint64_t>(f.order));
  h.f64(f.lambda);
  h.f64s(f.mu);
}

void job(Fnv1a& h, const SampleLayout& l, OutputFormat format) {
  h.text("shapespline-job-1");
  h.text(outputFormatName(format));
  h.u64(l.surface ? 1 : 0);
  h.u64(static_cast<uint64_t>(l.dimension));
  h.u64(static_cast<uint64_t>(l.samplesU));
  h.u64(static_cast<uint64_t>(l.samplesV));
  h.u64(l.fields);
  h.u64(l.precision == Precision::Double ? 1 : 0);
  h.u64(l.totalItems);
  h.u64(l.itemsV);
  // Mesh formats: a welded and a per-item file of one model are different jobs.
  if (format == OutputFormat::Obj || format == OutputFormat::Ply) {
    h.u64(l.welded ? 1 : 0);
    h.u64(l.reversed ? 1 : 0);
  }
}

// Digits only, no sign, at most `limit`.
std::optional<uint64_t> parseU64(std::string_view s, uint64_t limit) {
  if (s.empty() || s.size() > 20) return std::nullopt;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
  }
  if (s.size() > 1 && s[0] == '0') return std::nullopt;
  uint64_t v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size() || v > limit) return std::nullopt;
  return v;
}

// Splits at single spaces; false when a token is empty (two spaces, leading/trailing space).
bool splitSpaces(std::string_view s, std::vector<std::string_view>& out) {
  out.clear();
  size_t pos = 0;
  while (true) {
    const size_t sp = s.find(' ', pos);
    const std::string_view tok = s.substr(pos, sp == std::string_view::npos ? std::string_view::npos : sp - pos);
    if (tok.empty()) return false;
    out.push_back(tok);
    if (sp == std::string_view::npos) return true;
    pos = sp + 1;
  }
}

// "A<sep>B" -> (A, B) with each <= limit.
std::optional<std::pair<uint64_t, uint64_t>> parsePair(std::string_view s, std::string_view sep, uint64_t limit) {
  const size_t at = s.find(sep);
  if (at == std::string_view::npos) return std::nullopt;
  const auto a = parseU64(s.substr(0, at), limit), b = parseU64(s.substr(at + sep.size()), limit);
  if (!a || !b) return std::nullopt;
  return std::pair{*a, *b};
}

}  // namespace

void NetFingerprint::alphas(const double* values, size_t count) {
  if (phase_ == Phase::Points) {
    Fnv1a h(afterPoints());
    h.u64(alphaCount_);
    hash_ = h.value();
    words_.begin(hash_);
    phase_ = Phase::Alpha;
  }
  words_.add(reinterpret_cast<const unsigned char*>(values), count);
}

void NetFingerprint::weights(const double* values, size_t count) {
  if (phase_ != Phase::Weights) {
    alphas(nullptr, 0);
    Fnv1a h(withKnots(words_.end(hash_)));
    // Rational only (weightCount > 0): other jobs keep their fingerprints.
    if (weightCount_ > 0) h.u64(weightCount_);
    hash_ = h.value();
    words_.begin(hash_);
    phase_ = Phase::Weights;
  }
  words_.add(reinterpret_cast<const unsigned char*>(values), count);
}

std::string NetFingerprint::finish() {
  weights(nullptr, 0);
  Fnv1a h(weightCount_ > 0 ? words_.end(hash_) : hash_);
  return h.hex();
}

CurveFingerprint::CurveFingerprint(const CurveModel& m, size_t pointCount, size_t alphaCount, size_t weightCount,
                                   const SampleLayout& layout, OutputFormat format)
    : NetFingerprint(alphaCount, weightCount), shape_(m) {
  Fnv1a h;
  job(h, layout, format);
  h.text("curve");
  family(h, m.family);
  h.u64(m.closed ? 1 : 0);
  h.u64(static_cast<uint64_t>(m.dimension));
  h.u64(pointCount);
  hash_ = h.value();
  words_.begin(hash_);
}

void CurveFingerprint::points(const glm::dvec3* p, size_t count) {
  static_assert(sizeof(glm::dvec3) == 3 * sizeof(double));
  words_.add(reinterpret_cast<const unsigned char*>(p), 3 * count);
}

uint64_t CurveFingerprint::withKnots(uint64_t hash) const {
  Fnv1a h(hash);
  h.f64s(shape_.knots);
  return h.value();
}

std::string jobFingerprint(const CurveModel& m, const SampleLayout& layout, OutputFormat format) {
  CurveFingerprint f(m, m.points.size(), m.alpha.size(), m.weights.size(), layout, format);
  f.points(m.points.data(), m.points.size());
  f.alphas(m.alpha.data(), m.alpha.size());
  f.weights(m.weights.data(), m.weights.size());
  return f.finish();
}

SurfaceFingerprint::SurfaceFingerprint(const SurfaceShape& m, size_t alphaCount, size_t weightCount,
                                       const SampleLayout& layout, OutputFormat format)
    : NetFingerprint(alphaCount, weightCount), shape_(m) {
  Fnv1a h;
  job(h, layout, format);
  h.text("surface");
  family(h, m.family);
  h.u64(static_cast<uint64_t>(m.orderV));
  h.u64(m.closedU ? 1 : 0);
  h.u64(m.closedV ? 1 : 0);
  h.u64(static_cast<uint64_t>(m.rows));
  h.u64(static_cast<uint64_t>(m.cols));
  // The points' words in model order, each row one sequence (the surface reads them from its net
  // a row at a time).
  h.u64(static_cast<uint64_t>(m.rows) * static_cast<uint64_t>(m.cols));
  hash_ = h.value();
}

void SurfaceFingerprint::points(const glm::dvec3* p, size_t count) {
  const size_t cols = static_cast<size_t>(shape_.cols);
  if (count > 0 && shape_.cols <= 0) throw std::logic_error("SurfaceFingerprint::points: a shape without columns");
  while (count > 0) {
    if (rowDone_ == 0) words_.begin(hash_);
    const size_t n = std::min(count, cols - rowDone_);
    words_.add(reinterpret_cast<const unsigned char*>(p), 3 * n);
    p += n, count -= n, rowDone_ += n;
    if (rowDone_ == cols) hash_ = words_.end(hash_), rowDone_ = 0;
  }
}

uint64_t SurfaceFingerprint::withKnots(uint64_t hash) const {
  Fnv1a h(hash);
  h.f64s(shape_.knotsU);
  h.f64s(shape_.knotsV);
  return h.value();
}

std::string jobFingerprint(const Surface& surface, const SampleLayout& layout, OutputFormat format) {
  const SurfaceShape& m = surface.model();
  const std::vector<double>& w = surface.weights();
  SurfaceFingerprint f(m, m.alpha.size(), w.size(), layout, format);
  surface.forEachControlRow([&f](const glm::dvec3* row, int cols) { f.points(row, static_cast<size_t>(cols)); });
  f.alphas(m.alpha.data(), m.alpha.size());
  f.weights(w.data(), w.size());
  return f.finish();
}

std::string trimmedJobFingerprint(const std::string& faceJob, const TrimLoops& trim) {
  Fnv1a h;
  h.text("shapespline trimmed job");
  h.text(faceJob);
  h.f64(trim.tolerance);
  h.u64(trim.loops.size());
  for (const auto& loop : trim.loops) {
    h.u64(loop.size());
    for (const glm::dvec2& p : loop) {
      h.f64(p.x);
      h.f64(p.y);
    }
  }
  return h.hex();
}

std::string partJobFingerprint(const std::vector<std::pair<int, std::string>>& faces) {
  Fnv1a h;
  h.text("shapespline part job");
  h.u64(faces.size());
  for (const auto& [id, job] : faces) {
    h.u64(static_cast<uint64_t>(id));
    h.text(job);
  }
  return h.hex();
}

ShardInfo shardInfoOf(const SampleLayout& l) {
  ShardInfo s;
  s.job = l.job;
  s.surface = l.surface;
  s.shardIndex = l.shardIndex;
  s.shardCount = l.shardCount;
  s.firstItem = l.firstItem;
  s.itemCount = l.itemCount;
  s.totalItems = l.totalItems;
  s.samplesU = l.samplesU;
  s.samplesV = l.surface ? l.samplesV : 1;
  return s;
}

ShardInfo wholeJobOf(const ShardInfo& shard) {
  ShardInfo w = shard;
  w.shardIndex = w.shardCount = 1;
  w.firstItem = 0;
  w.itemCount = w.totalItems;
  return w;
}

std::string shardInfoLine(const ShardInfo& s) {
  return "shapespline job " + s.job + (s.surface ? " surface" : " curve") + " shard " + std::to_string(s.shardIndex) +
         "/" + std::to_string(s.shardCount) + " items " + std::to_string(s.firstItem) + ".." +
         std::to_string(s.endItem()) + " of " + std::to_string(s.totalItems) + " grid " + std::to_string(s.samplesU) +
         "x" + std::to_string(s.samplesV);
}

std::optional<ShardInfo> parseShardInfoLine(std::string_view line) {
  std::vector<std::string_view> t;
  if (!splitSpaces(line, t) || t.size() != 12) return std::nullopt;
  if (t[0] != "shapespline" || t[1] != "job" || t[4] != "shard" || t[6] != "items" || t[8] != "of" ||
      t[10] != "grid") {
    return std::nullopt;
  }
  ShardInfo s;
  if (t[2].size() != 16 || t[2].find_first_not_of("0123456789abcdef") != std::string_view::npos) return std::nullopt;
  s.job = std::string(t[2]);
  if (t[3] != "curve" && t[3] != "surface") return std::nullopt;
  s.surface = t[3] == "surface";
  const auto kn = parsePair(t[5], "/", kMaxShardCount);
  const auto range = parsePair(t[7], "..", kMaxItemCount);
  const auto total = parseU64(t[9], kMaxItemCount);
  const auto grid = parsePair(t[11], "x", 65536);
  if (!kn || !range || !total || !grid) return std::nullopt;
  if (kn->first < 1 || kn->first > kn->second || range->first > range->second || range->second > *total) {
    return std::nullopt;
  }
  if (grid->first < 2 || (s.surface ? grid->second < 2 : grid->second != 1)) return std::nullopt;
  s.shardIndex = static_cast<int>(kn->first);
  s.shardCount = static_cast<int>(kn->second);
  s.firstItem = range->first;
  s.itemCount = range->second - range->first;
  s.totalItems = *total;
  s.samplesU = static_cast<int>(grid->first);
  s.samplesV = static_cast<int>(grid->second);
  return s;
}

std::string plyInfoComments(const ShardInfo& info, std::string_view escapedSource) {
  return std::string(kPlySourcePrefix) + std::string(escapedSource) + "\n" + std::string(kPlyJobPrefix) +
         shardInfoLine(info) + "\n";
}

std::string objHeader(const ShardInfo& s, std::string_view escapedSource, bool welded) {
  const bool relative = s.shardCount > 1 && !welded;
  return std::string(kObjSourcePrefix) + std::string(escapedSource) + "\n# " + (s.surface ? "patches " : "spans ") +
         std::to_string(s.firstItem) + ".." + std::to_string(s.endItem()) + " of " + std::to_string(s.totalItems) +
         ", grid " + std::to_string(s.samplesU) + (s.surface ? "x" + std::to_string(s.samplesV) : std::string()) +
         (s.shardCount > 1 ? ", shard " + std::to_string(s.shardIndex) + "/" + std::to_string(s.shardCount) +
                                 (relative ? " (relative indices: concatenate shards)" : " (merge with shapespline merge)")
                           : std::string()) +
         "\n" + std::string(kObjJobPrefix) + shardInfoLine(s) + "\n";
}

MeshInfo meshInfoOf(const SampleLayout& l) {
  MeshInfo m;
  m.patchesV = l.surface ? (l.itemsV == 0 ? 1 : l.itemsV) : 1;
  m.patchesU = l.totalItems / m.patchesV;
  m.closedU = l.surface ? l.closedU : l.closed;
  m.closedV = l.surface && l.closedV;
  m.reversed = l.reversed;
  return m;
}

std::string meshInfoLine(const MeshInfo& m) {
  const char* closed = m.closedU && m.closedV ? "uv" : m.closedU ? "u" : m.closedV ? "v" : "none";
  return "shapespline mesh welded items " + std::to_string(m.patchesU) + "x" + std::to_string(m.patchesV) +
         " closed " + closed + " orientation " + (m.reversed ? "reversed" : "du-x-dv");
}

std::optional<MeshInfo> parseMeshInfoLine(std::string_view line) {
  std::vector<std::string_view> t;
  if (!splitSpaces(line, t) || t.size() != 9 || t[0] != "shapespline" || t[1] != "mesh" || t[2] != "welded" ||
      t[3] != "items" || t[5] != "closed" || t[7] != "orientation") {
    return std::nullopt;
  }
  const auto items = parsePair(t[4], "x", kMaxItemCount);
  if (!items || items->first == 0 || items->second == 0 || items->first > kMaxItemCount / items->second) return std::nullopt;
  MeshInfo m;
  m.patchesU = items->first;
  m.patchesV = items->second;
  if (t[6] == "uv") {
    m.closedU = m.closedV = true;
  } else if (t[6] == "u") {
    m.closedU = true;
  } else if (t[6] == "v") {
    m.closedV = true;
  } else if (t[6] != "none") {
    return std::nullopt;
  }
  if (t[8] == "reversed") {
    m.reversed = true;
  } else if (t[8] != "du-x-dv") {
    return std::nullopt;
  }
  return m;
}

SpanWindow spanWindow(uint64_t first, uint64_t count, uint64_t itemsV) {
  if (itemsV == 0) itemsV = 1;
  SpanWindow w;
  w.row0 = first / itemsV;
  w.row1 = count == 0 ? w.row0 : (first + count - 1) / itemsV + 1;
  if (count == 0) {
    w.col0 = w.col1 = first % itemsV;
  } else if (w.row1 - w.row0 == 1) {
    w.col0 = first % itemsV;
    w.col1 = w.col0 + count;
  } else {
    w.col0 = 0;
    w.col1 = itemsV;
  }
  return w;
}

RawSidecar rawSidecarOf(const SampleLayout& l, const std::string& job, bool float64, const std::string& dataFile) {
  RawSidecar s;
  s.dataFile = dataFile;
  s.float64 = float64;
  for (int f = 0; f < kFieldCount; ++f) {
    if (l.fields & fieldBit(static_cast<Field>(f))) s.fields.emplace_back(fieldName(static_cast<Field>(f)));
  }
  s.info = shardInfoOf(l);
  s.info.job = job;
  s.itemsV = l.itemsV == 0 ? 1 : l.itemsV;
  const SpanWindow w = spanWindow(l.firstItem, l.itemCount, s.itemsV);
  s.spansUOffset = w.row0;
  s.spansVOffset = w.col0;
  for (uint64_t r = w.row0; r < w.row1 && r < l.rowCount(); ++r) s.spansU.push_back(l.rowSpan(r));
  for (uint64_t c = w.col0; c < w.col1 && c < l.spanV.size(); ++c) s.spansV.push_back(l.spanV[c]);
  s.computedDouble = l.computedPrecision == Precision::Double;
  s.device = l.device;
  s.source = l.source;
  s.metadata = l.metadata;
  return s;
}

void writeRawSidecar(AtomicFile& out, const RawSidecar& s) {
  const ShardInfo& i = s.info;
  const uint64_t points = i.itemCount * i.pointsPerItem(), values = points * s.valuesPerRecord();
  std::string t = "{\n";
  auto key = [&](const char* k, const std::string& value, bool last = false) {
    t += "  \"" + std::string(k) + "\": " + value + (last ? "\n" : ",\n");
  };
  // Appended, not `"\"" + escapeText(v) + ...`: GCC 12 warns falsely (-Wstringop-overflow) about that
  // form once escapeText is inlined (unity builds).
  auto str = [](std::string_view v) {
    std::string quoted(1, '"');
    quoted += escapeText(v);
    quoted += '"';
    return quoted;
  };
  key("format", str("shapespline-raw"));
  key("format_version", std::to_string(kRawSidecarVersion));
  key("data_file", str(s.dataFile));
  key("dtype", str(s.float64 ? "float64" : "float32"));
  key("byte_order", str("little"));
  key("kind", str(i.surface ? "surface" : "curve"));
  key("item", str(i.surface ? "patch" : "span"));
  std::string names = "[";
  for (size_t k = 0; k < s.fields.size(); ++k) names += (k ? ", " : "") + str(s.fields[k]);
  key("fields", names + "]");
  key("components", "3");
  key("values_per_record", std::to_string(s.valuesPerRecord()));
  key("order", str(i.surface ? "item, then u sample a, then v sample b; record = fields in order, xyz each"
                             : "item (span), then sample s; record = fields in order, xyz each"));
  key("grid", "{\"samples_u\": " + std::to_string(i.samplesU) + ", \"samples_v\": " + std::to_string(i.samplesV) +
                  ", \"points_per_item\": " + std::to_string(i.pointsPerItem()) +
                  ", \"local_parameters\": \"s/(S-1), both ends included\"}");
  key("counts", "{\"items\": " + std::to_string(i.itemCount) + ", \"points\": " + std::to_string(points) +
                    ", \"values\": " + std::to_string(values) +
                    ", \"bytes\": " + std::to_string(values * s.valueSize()) + "}");
  t += "  \"items\": {\n    \"first\": " + std::to_string(i.firstItem) + ",\n    \"count\": " +
       std::to_string(i.itemCount) + ",\n    \"total\": " + std::to_string(i.totalItems) + ",\n    \"items_v\": " +
       std::to_string(s.itemsV) + ",\n    \"spans_u_offset\": " + std::to_string(s.spansUOffset) +
       ",\n    \"spans_v_offset\": " + std::to_string(s.spansVOffset) + ",\n    \"spans_u\": ";
  out.write(t);
  t.clear();
  // The span lists may be long: written in pieces through the file's buffer.
  for (const auto* list : {&s.spansU, &s.spansV}) {
    std::string piece;
    out.write("[", 1);
    for (size_t k = 0; k < list->size(); k += 4096) {
      piece.clear();
      for (size_t e = std::min(list->size(), k + 4096), j = k; j < e; ++j) {
        if (j) piece += ", ";
        piece += std::to_string((*list)[j]);
      }
      out.write(piece);
    }
    out.write(list == &s.spansU ? "],\n    \"spans_v\": " : "],\n");
  }
  t += "    \"mapping\": " +
       str(i.surface ? "item k (0-based over the whole model) is patch (spans_u[k / items_v - spans_u_offset], "
                       "spans_v[k % items_v - spans_v_offset])"
                     : "item k (0-based over the whole model) is span spans_u[k - spans_u_offset]") +
       "\n  },\n";
  key("shard", "{\"index\": " + std::to_string(i.shardIndex) + ", \"count\": " + std::to_string(i.shardCount) + "}");
  key("job", str(i.job));
  key("computed_precision", str(s.computedDouble ? "double" : "float"));
  key("device", str(s.device));
  // One line; text that is not UTF-8 was replaced by U+FFFD in metadataJson.
  key("metadata", metadataJson(s.metadata).dump());
  key("source", str(s.source), true);
  t += "}\n";
  out.write(t);
}

}  // namespace shapespline::io
