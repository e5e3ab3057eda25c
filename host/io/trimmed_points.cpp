#include <shapespline/io/job_metadata.h>
#include <shapespline/io/number_text.h>
#include <shapespline/io/raw_records.h>
#include <shapespline/io/shard_info.h>
#include <shapespline/io/trimmed_points.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <stdexcept>

namespace shapespline::io {
namespace {

constexpr size_t kFlushBytes = size_t{1} << 20;

// PLY property names of a field's three components (the point and the normal as readers expect).
std::array<std::string, 3> plyNames(Field f) {
  if (f == Field::Point) return {"x", "y", "z"};
  if (f == Field::Normal) return {"nx", "ny", "nz"};
  const std::string n(fieldName(f));
  return {n + "_x", n + "_y", n + "_z"};
}

}  // namespace

std::string TrimmedPointWriter::columnName(const Column& c) {
  return c.kind == Column::Uv ? "uv" : c.kind == Column::Face ? "face" : std::string(fieldName(c.field));
}

int TrimmedPointWriter::columnWidth(const Column& c) { return c.kind == Column::Uv ? 2 : c.kind == Column::Face ? 1 : 3; }

bool trimmedPointFormat(OutputFormat f) {
  return f == OutputFormat::Npy || f == OutputFormat::RawF32 || f == OutputFormat::RawF64 || f == OutputFormat::Csv ||
         f == OutputFormat::Ply;
}

bool trimmedShardFormat(OutputFormat f) { return trimmedPointFormat(f) && f != OutputFormat::Csv; }

namespace {

// The samples inside `classifier`'s loops of each of the layout's items, in item order.
std::vector<uint64_t> insideByItem(const SampleLayout& layout, const TrimClassifier& classifier) {
  layout.checkDerivedValues();
  const auto sv = static_cast<size_t>(layout.samplesV);
  std::vector<uint64_t> kept;
  kept.reserve(layout.itemCount);
  for (size_t item = layout.firstItem; item < layout.firstItem + layout.itemCount; ++item) {
    uint64_t inside = 0;
    for (size_t p = 0; p < layout.pointsPerItem(); ++p) {
      const auto [u, v] = layout.parameter(item, static_cast<int>(p / sv), static_cast<int>(p % sv));
      inside += classifier.inside({u, v});
    }
    kept.push_back(inside);
  }
  return kept;
}

uint64_t countInside(const SampleLayout& layout, const TrimClassifier& classifier) {
  const std::vector<uint64_t> kept = insideByItem(layout, classifier);
  return std::accumulate(kept.begin(), kept.end(), uint64_t{0});
}

}  // namespace

std::vector<uint64_t> samplesInsideByItem(const SampleLayout& layout, const TrimLoops& trim) {
  return insideByItem(layout, TrimClassifier(trim));
}

nlohmann::json TrimmedShard::toJson() const {
  return {{"job", job},           {"index", index},     {"count", count},
          {"first_item", firstItem}, {"items", items},     {"total_items", totalItems},
          {"first_record", firstRecord}, {"records", records}, {"total_records", totalRecords}};
}

std::optional<TrimmedShard> TrimmedShard::fromJson(const nlohmann::json& j) {
  if (!j.is_object() || j.size() != 9) return std::nullopt;
  for (const char* key : {"index", "count", "first_item", "items", "total_items", "first_record", "records",
                          "total_records"})
    if (!j.contains(key) || !j[key].is_number_unsigned()) return std::nullopt;
  if (!j.contains("job") || !j["job"].is_string()) return std::nullopt;
  TrimmedShard s;
  s.job = j["job"].get<std::string>();
  const uint64_t index = j["index"].get<uint64_t>(), count = j["count"].get<uint64_t>();
  if (index < 1 || index > count || count > kMaxShardCount) return std::nullopt;
  s.index = static_cast<int>(index);
  s.count = static_cast<int>(count);
  s.firstItem = j["first_item"].get<uint64_t>();
  s.items = j["items"].get<uint64_t>();
  s.totalItems = j["total_items"].get<uint64_t>();
  s.firstRecord = j["first_record"].get<uint64_t>();
  s.records = j["records"].get<uint64_t>();
  s.totalRecords = j["total_records"].get<uint64_t>();
  const bool inRange = s.totalItems <= kMaxItemCount && s.totalRecords <= kMaxItemCount &&
                       s.firstItem <= s.totalItems && s.items <= s.totalItems - s.firstItem &&
                       s.firstRecord <= s.totalRecords && s.records <= s.totalRecords - s.firstRecord;
  if (!inRange || s.job.size() != 16 || s.job.find_first_not_of("0123456789abcdef") != std::string::npos)
    return std::nullopt;
  return s;
}

TrimmedShard balancedTrimmedShard(const std::vector<uint64_t>& kept, int k, int n) {
  __extension__ using Wide = unsigned __int128;  // records (< 2^62) times shards (<= 10^9)
  std::vector<uint64_t> before(kept.size() + 1, 0);  // records before item i
  for (size_t i = 0; i < kept.size(); ++i) before[i + 1] = before[i] + kept[i];
  const uint64_t items = kept.size(), records = before.back();
  // The first item whose records-before reach j/n of all (exact in 128 bits); by item count when
  // nothing is kept. The last shard always ends at the last item.
  auto cut = [&](int j) -> uint64_t {
    if (j >= n) return items;
    const auto jj = static_cast<Wide>(j), nn = static_cast<Wide>(n);
    if (records == 0) return static_cast<uint64_t>(jj * items / nn);
    const auto at = std::lower_bound(before.begin(), before.end(), jj * records,
                                     [&](uint64_t b, Wide target) { return b * nn < target; });
    return static_cast<uint64_t>(at - before.begin());
  };
  TrimmedShard s;
  s.firstItem = cut(k - 1);
  s.items = cut(k) - s.firstItem;
  s.totalItems = items;
  s.firstRecord = before[s.firstItem];
  s.records = before[s.firstItem + s.items] - s.firstRecord;
  s.totalRecords = records;
  return s;
}

TrimmedPointWriter::TrimmedPointWriter(OutputFormat format, AtomicFile& out, AtomicFile* sidecar, const TrimLoops& trim)
    : format_(format), out_(out), sidecar_(sidecar), trim_(trim), classifier_(trim) {
  if (!trimmedPointFormat(format)) throw std::logic_error("TrimmedPointWriter: not a point format");
}

TrimmedPointWriter::TrimmedPointWriter(OutputFormat format, AtomicFile& out, AtomicFile* sidecar)
    : TrimmedPointWriter(format, out, sidecar, TrimLoops{}) {}

void TrimmedPointWriter::setLayout(const SampleLayout& layout) {
  if (!layout.surface) throw std::logic_error("TrimmedPointWriter: surfaces only");
  layout_ = layout;
  fields_ = recordFields(layout.fields);
  float64_ = format_ == OutputFormat::RawF64 || (format_ != OutputFormat::RawF32 && layout.precision == Precision::Double);
}

void TrimmedPointWriter::begin(const SampleLayout& layout) {
  setLayout(layout);
  kept_ = countInside(layout, classifier_);
  gridPoints_ = layout.totalItems * layout.pointsPerItem();
  if (shard_ && shard_->records != kept_) throw std::logic_error("TrimmedPointWriter: the shard's records differ");
  header(false);
}

void TrimmedPointWriter::beginPart(const SampleLayout& anyFace, uint64_t total, uint64_t gridPoints,
                                   const nlohmann::json& part) {
  part_ = part;
  setLayout(anyFace);
  kept_ = total;
  gridPoints_ = gridPoints;
  if (shard_ && shard_->records != kept_) throw std::logic_error("TrimmedPointWriter: the shard's records differ");
  header(true);
}

void TrimmedPointWriter::nextFace(const SampleLayout& layout, const TrimLoops& trim, int faceId) {
  layout_ = layout;
  trim_ = trim;
  classifier_ = TrimClassifier(trim);
  faceId_ = faceId;
}

void TrimmedPointWriter::header(bool withFace) {
  // The record's columns: the face id (parts), (U, V), then the fields; in PLY the point and the
  // normal come first, where point-cloud readers look for them.
  columns_.clear();
  auto add = [&](Column::Kind kind, Field f = Field::Point) { columns_.push_back({kind, f}); };
  const bool ply = format_ == OutputFormat::Ply;
  if (ply)
    for (Field f : {Field::Point, Field::Normal})
      if (std::find(fields_.begin(), fields_.end(), f) != fields_.end()) add(Column::Vector, f);
  if (withFace) add(Column::Face);
  add(Column::Uv);
  for (Field f : fields_)
    if (!ply || (f != Field::Point && f != Field::Normal)) add(Column::Vector, f);
  const std::string property = float64_ ? "property double " : "property float ";
  if (format_ == OutputFormat::Npy) {
    std::vector<std::pair<std::string, int>> npyFields;
    for (const Column& c : columns_) npyFields.emplace_back(columnName(c), columnWidth(c));
    out_.write(npyHeader(npyFields, float64_, kept_));
  } else if (format_ == OutputFormat::Csv) {
    std::string h;
    for (const Column& c : columns_)
      if (c.kind == Column::Uv) h += ",U,V";
      else if (c.kind == Column::Face) h += ",face";
      else for (const std::string& n : plyNames(c.field)) h += "," + n;
    out_.write(h.substr(1) + "\n");
  } else if (format_ == OutputFormat::Ply) {
    std::string h = "ply\nformat binary_little_endian 1.0\ncomment shapespline trimmed point cloud: the grid samples "
                    "inside the face's trim loops\n" +
                    (part_.is_null() ? metadataComments(layout_.metadata, "comment ")
                                     : "comment part: " + part_.dump() + "\n") +
                    (shard_ ? std::string(kTrimmedShardComment) + shard_->toJson().dump() + "\n" : std::string()) +
                    "element vertex " + std::to_string(kept_) + "\n";
    for (const Column& c : columns_)
      if (c.kind == Column::Uv) h += property + "u\n" + property + "v\n";
      else if (c.kind == Column::Face) h += property + "face\n";
      else for (const std::string& n : plyNames(c.field)) h += property + n + "\n";
    out_.write(h + "end_header\n");
  }
}

void TrimmedPointWriter::appendRecord(const GridChunk& chunk, size_t p, std::pair<double, double> uv) {
  auto put = [&](double value) {
    if (format_ == OutputFormat::Csv) {
      char text[kMaxNumberChars];
      buffer_.append(text, writeValue(text, value, float64_ ? Precision::Double : Precision::Float));
      buffer_ += ',';
    } else if (float64_) {
      buffer_.append(reinterpret_cast<const char*>(&value), sizeof value);
    } else {
      const float f = static_cast<float>(value);
      buffer_.append(reinterpret_cast<const char*>(&f), sizeof f);
    }
  };
  for (const Column& c : columns_) {
    if (c.kind == Column::Uv) {
      put(uv.first);
      put(uv.second);
    } else if (c.kind == Column::Face) {
      put(faceId_);  // exact in fp32 up to 2^24 faces
    } else {
      for (int axis = 0; axis < 3; ++axis) put(chunk.coord(c.field, p, axis));
    }
  }
  if (format_ == OutputFormat::Csv) buffer_.back() = '\n';
  ++written_;
}

void TrimmedPointWriter::consume(const GridChunk& chunk) {
  const auto sv = static_cast<size_t>(layout_.samplesV);
  for (size_t p = 0; p < chunk.pointCount(); ++p) {
    const size_t item = chunk.itemOf(p), in = chunk.pointInItem(p);
    const auto uv = layout_.parameter(item, static_cast<int>(in / sv), static_cast<int>(in % sv));
    if (!classifier_.inside({uv.first, uv.second})) continue;
    appendRecord(chunk, p, uv);
    if (buffer_.size() >= kFlushBytes) flush();
  }
}

void TrimmedPointWriter::flush() {
  out_.write(buffer_);
  buffer_.clear();
}

void TrimmedPointWriter::finish() {
  flush();
  if (written_ != kept_) throw std::logic_error("TrimmedPointWriter: the chunks did not cover the job");
  if (!sidecar_) return;
  nlohmann::json fields = nlohmann::json::array();
  for (const Column& c : columns_) fields.push_back({{"name", columnName(c)}, {"components", columnWidth(c)}});
  nlohmann::json s = {
      {"format", "shapespline-trimmed-points"},
      {"data", out_.target().filename().string()},
      {"dtype", float64_ ? "<f8" : "<f4"},
      {"records", kept_},
      {"fields", fields},
      {"grid_points", gridPoints_},
      {"samples_per_patch", {layout_.samplesU, layout_.samplesV}},
      {"trim", part_.is_null() ? nlohmann::json{{"rule", "even-odd"}, {"tolerance", trim_.tolerance}}
                               : nlohmann::json{{"rule", "even-odd"}}}};
  if (part_.is_null()) s["metadata"] = metadataJson(layout_.metadata);
  else s["part"] = part_;
  if (shard_) s["shard"] = shard_->toJson();
  sidecar_->write(s.dump(1) + "\n");
}

}  // namespace shapespline::io
