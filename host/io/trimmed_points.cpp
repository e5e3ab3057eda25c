#include <shapespline/io/job_metadata.h>
#include <shapespline/io/number_text.h>
#include <shapespline/io/raw_records.h>
#include <shapespline/io/trimmed_points.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
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

bool trimmedPointFormat(OutputFormat f) {
  return f == OutputFormat::Npy || f == OutputFormat::RawF32 || f == OutputFormat::RawF64 || f == OutputFormat::Csv ||
         f == OutputFormat::Ply;
}

TrimmedPointWriter::TrimmedPointWriter(OutputFormat format, AtomicFile& out, AtomicFile* sidecar, const TrimLoops& trim)
    : format_(format), out_(out), sidecar_(sidecar), classifier_(trim), tolerance_(trim.tolerance) {
  if (!trimmedPointFormat(format)) throw std::logic_error("TrimmedPointWriter: not a point format");
}

bool TrimmedPointWriter::inside(size_t item, size_t pointInItem) const {
  const auto sv = static_cast<size_t>(layout_.samplesV);
  const auto [u, v] = layout_.parameter(item, static_cast<int>(pointInItem / sv), static_cast<int>(pointInItem % sv));
  return classifier_.inside({u, v});
}

void TrimmedPointWriter::begin(const SampleLayout& layout) {
  if (!layout.surface) throw std::logic_error("TrimmedPointWriter: surfaces only");
  layout_ = layout;
  layout_.checkDerivedValues();
  fields_ = recordFields(layout.fields);
  float64_ = format_ == OutputFormat::RawF64 || (format_ != OutputFormat::RawF32 && layout.precision == Precision::Double);
  for (size_t item = layout.firstItem; item < layout.firstItem + layout.itemCount; ++item)
    for (size_t p = 0; p < layout.pointsPerItem(); ++p) kept_ += inside(item, p);
  header();
}

void TrimmedPointWriter::header() {
  // The record's columns: (U, V) first, except in PLY, where point-cloud readers want the point
  // and the normal first.
  columns_.clear();
  if (format_ == OutputFormat::Ply) {
    for (Field f : {Field::Point, Field::Normal})
      if (std::find(fields_.begin(), fields_.end(), f) != fields_.end()) columns_.emplace_back(f);
    columns_.emplace_back(std::nullopt);
    for (Field f : fields_)
      if (f != Field::Point && f != Field::Normal) columns_.emplace_back(f);
  } else {
    columns_.emplace_back(std::nullopt);
    for (Field f : fields_) columns_.emplace_back(f);
  }
  const std::string property = float64_ ? "property double " : "property float ";
  if (format_ == OutputFormat::Npy) {
    std::vector<std::pair<std::string, int>> npyFields;
    for (const auto& c : columns_) npyFields.emplace_back(c ? std::string(fieldName(*c)) : "uv", c ? 3 : 2);
    out_.write(npyHeader(npyFields, float64_, kept_));
  } else if (format_ == OutputFormat::Csv) {
    std::string h;
    for (const auto& c : columns_)
      if (!c) h += ",U,V";
      else for (const std::string& n : plyNames(*c)) h += "," + n;
    out_.write(h.substr(1) + "\n");
  } else if (format_ == OutputFormat::Ply) {
    std::string h = "ply\nformat binary_little_endian 1.0\ncomment shapespline trimmed point cloud: the grid samples "
                    "inside the face's trim loops\n" +
                    metadataComments(layout_.metadata, "comment ") + "element vertex " + std::to_string(kept_) + "\n";
    for (const auto& c : columns_)
      if (!c) h += property + "u\n" + property + "v\n";
      else for (const std::string& n : plyNames(*c)) h += property + n + "\n";
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
  for (const auto& c : columns_) {
    if (!c) {
      put(uv.first);
      put(uv.second);
    } else {
      for (int axis = 0; axis < 3; ++axis) put(chunk.coord(*c, p, axis));
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
  for (const auto& c : columns_)
    fields.push_back({{"name", c ? std::string(fieldName(*c)) : "uv"}, {"components", c ? 3 : 2}});
  const nlohmann::json s = {
      {"format", "shapespline-trimmed-points"},
      {"data", out_.target().filename().string()},
      {"dtype", float64_ ? "<f8" : "<f4"},
      {"records", kept_},
      {"fields", fields},
      {"grid_points", layout_.pointCount()},
      {"samples_per_patch", {layout_.samplesU, layout_.samplesV}},
      {"trim", {{"rule", "even-odd"}, {"tolerance", tolerance_}}},
      {"metadata", metadataJson(layout_.metadata)}};
  sidecar_->write(s.dump(1) + "\n");
}

}  // namespace shapespline::io
