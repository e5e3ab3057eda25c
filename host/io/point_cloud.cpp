#include <shapespline/io/point_cloud.h>

#include <shapespline/core/model.h>
#include <shapespline/core/value_text.h>
#include <shapespline/io/file_extension.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/npy_array.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace shapespline::io {

namespace {

// Points a cloud may hold: 2^40 (8 TiB of fp64 triples).
constexpr std::uint64_t kMaxCloudPoints = std::uint64_t{1} << 40;
// The longest line of a CSV or ASCII PLY file, and of a PLY header.
constexpr std::size_t kMaxLineChars = 4096;

// Reads one line (without '\n'), refusing an over-long one.
bool readLine(std::istream& in, std::string& line, const std::string& field) {
  if (!std::getline(in, line)) return false;
  if (line.size() > kMaxLineChars)
    throw ModelError(field, "", "a line longer than " + std::to_string(kMaxLineChars) + " characters");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

// The numbers of a line split by `separators`; false when a token is not a number.
bool numbersOf(const std::string& line, const char* separators, std::vector<double>& out) {
  out.clear();
  size_t at = 0;
  while (at < line.size()) {
    at = line.find_first_not_of(separators, at);
    if (at == std::string::npos) break;
    size_t end = line.find_first_of(separators, at);
    if (end == std::string::npos) end = line.size();
    // from_chars takes no leading '+'; a number may have one.
    const size_t start = line[at] == '+' ? at + 1 : at;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(line.data() + start, line.data() + end, v);
    if (ec != std::errc() || ptr != line.data() + end) return false;
    out.push_back(v);
    at = end;
  }
  return true;
}

std::ifstream openStream(const std::filesystem::path& path, const std::string& field) {
  { InputFd check(path, field); }  // a regular file, or the error that names what it is
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(field + ": cannot open " + path.string());
  return in;
}

}  // namespace

struct PointCloudReader::Format {
  virtual ~Format() = default;
  // Appends up to `max` points; the reader checks them.
  virtual void read(std::vector<glm::dvec3>& out, std::size_t max) = 0;
  // Passes over `count` points (there are that many left) without reading their values.
  virtual void skip(std::uint64_t count) = 0;
};

namespace {

struct NpyFormat final : PointCloudReader::Format {
  NpyReader reader;
  std::vector<double> values;
  NpyFormat(const std::filesystem::path& path, const std::string& field, std::uint64_t& count)
      : reader(path, std::numeric_limits<std::uint64_t>::max()) {
    const std::vector<std::uint64_t>& shape = reader.header().shape;
    if (shape.size() != 2 || shape[1] != 3) {
      std::string text = "(";
      for (size_t k = 0; k < shape.size(); ++k) text += (k ? ", " : "") + std::to_string(shape[k]);
      throw ModelError(field, text + (shape.size() == 1 ? ",)" : ")"), "a point cloud's array has shape (N, 3)");
    }
    count = shape[0];
  }
  void read(std::vector<glm::dvec3>& out, std::size_t max) override {
    values.resize(3 * max);
    reader.read(values.data(), values.size());
    for (std::size_t k = 0; k < max; ++k) out.emplace_back(values[3 * k], values[3 * k + 1], values[3 * k + 2]);
  }
  void skip(std::uint64_t count) override { reader.skip(3 * count); }
};

// Fixed-size records of `recordBytes`, x, y and z at byte offsets of the given scalar type.
enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

int bytesOf(Scalar s) {
  switch (s) {
    case Scalar::Int8: case Scalar::UInt8: return 1;
    case Scalar::Int16: case Scalar::UInt16: return 2;
    case Scalar::Int32: case Scalar::UInt32: case Scalar::Float32: return 4;
    case Scalar::Float64: return 8;
  }
  return 0;
}

double valueAt(const unsigned char* p, Scalar s) {
  switch (s) {
    case Scalar::Int8: return static_cast<std::int8_t>(p[0]);
    case Scalar::UInt8: return p[0];
    case Scalar::Int16: { std::int16_t v; std::memcpy(&v, p, 2); return v; }
    case Scalar::UInt16: { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
    case Scalar::Int32: { std::int32_t v; std::memcpy(&v, p, 4); return v; }
    case Scalar::UInt32: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
    case Scalar::Float32: { float v; std::memcpy(&v, p, 4); return v; }
    case Scalar::Float64: { double v; std::memcpy(&v, p, 8); return v; }
  }
  return 0.0;
}

static_assert(std::endian::native == std::endian::little, "binary clouds are read as little-endian");

struct RecordFormat final : PointCloudReader::Format {
  std::ifstream in;
  std::string field;
  int recordBytes = 0, offset[3] = {0, 0, 0};
  Scalar type[3] = {Scalar::Float64, Scalar::Float64, Scalar::Float64};
  std::vector<unsigned char> buffer;
  void read(std::vector<glm::dvec3>& out, std::size_t max) override {
    buffer.resize(max * static_cast<size_t>(recordBytes));
    in.read(reinterpret_cast<char*>(buffer.data()), static_cast<std::streamsize>(buffer.size()));
    if (static_cast<size_t>(in.gcount()) != buffer.size()) throw ModelError(field, "", "the file ends before its last point");
    for (std::size_t k = 0; k < max; ++k) {
      const unsigned char* r = buffer.data() + k * static_cast<size_t>(recordBytes);
      out.emplace_back(valueAt(r + offset[0], type[0]), valueAt(r + offset[1], type[1]), valueAt(r + offset[2], type[2]));
    }
  }
  void skip(std::uint64_t count) override {
    in.seekg(static_cast<std::streamoff>(count * static_cast<std::uint64_t>(recordBytes)), std::ios::cur);
    if (!in) throw ModelError(field, "", "the file ends before its last point");
  }
};

struct TextFormat final : PointCloudReader::Format {
  std::ifstream in;
  std::string field;
  const char* separators = ",";
  int column[3] = {0, 1, 2};
  bool skipHeader = false;  // CSV: a first line that is not numbers
  std::uint64_t line = 0;
  std::string text;
  std::vector<double> numbers;
  void read(std::vector<glm::dvec3>& out, std::size_t max) override {
    while (out.size() < max) {
      if (!readLine(in, text, field)) throw ModelError(field, "", "the file ends before its last point");
      ++line;
      if (skipHeader && line == 1) continue;
      if (text.find_first_not_of(" \t,") == std::string::npos) continue;  // blank
      const int needed = std::max({column[0], column[1], column[2]}) + 1;
      if (!numbersOf(text, separators, numbers) || static_cast<int>(numbers.size()) < needed)
        throw ModelError(field + " line " + std::to_string(line), shortText(text, kMaxValueChars),
                         "a point is " + std::to_string(needed) + " numbers");
      out.emplace_back(numbers[column[0]], numbers[column[1]], numbers[column[2]]);
    }
  }
  void skip(std::uint64_t count) override {
    while (count > 0) {
      if (!readLine(in, text, field)) throw ModelError(field, "", "the file ends before its last point");
      ++line;
      if (skipHeader && line == 1) continue;
      if (text.find_first_not_of(" \t,") != std::string::npos) --count;
    }
  }
};

std::unique_ptr<PointCloudReader::Format> openRaw(const std::filesystem::path& path, const std::string& field,
                                                   bool float64, std::uint64_t& count) {
  auto f = std::make_unique<RecordFormat>();
  f->field = field;
  f->in = openStream(path, field);
  const std::uint64_t bytes = std::filesystem::file_size(path);
  const int scalar = float64 ? 8 : 4;
  if (bytes % (3 * scalar) != 0)
    throw ModelError(field, std::to_string(bytes) + " bytes",
                     std::string("a raw ") + (float64 ? ".f64" : ".f32") + " cloud is whole x y z triples of " +
                         std::to_string(scalar) + "-byte values");
  f->recordBytes = 3 * scalar;
  for (int k = 0; k < 3; ++k) f->offset[k] = k * scalar, f->type[k] = float64 ? Scalar::Float64 : Scalar::Float32;
  count = bytes / (3 * scalar);
  return f;
}

std::unique_ptr<PointCloudReader::Format> openCsv(const std::filesystem::path& path, const std::string& field,
                                                   std::uint64_t& count) {
  auto f = std::make_unique<TextFormat>();
  f->field = field;
  f->in = openStream(path, field);
  // The first pass: the header line (if any) and the point count.
  std::string line;
  std::vector<double> numbers;
  std::uint64_t index = 0;
  count = 0;
  while (readLine(f->in, line, field)) {
    ++index;
    if (line.find_first_not_of(" \t,") == std::string::npos) continue;
    if (index == 1 && !numbersOf(line, ",", numbers)) {
      f->skipHeader = true;
      continue;
    }
    ++count;
  }
  f->in.clear();
  f->in.seekg(0);
  return f;
}

std::unique_ptr<PointCloudReader::Format> openPly(const std::filesystem::path& path, const std::string& field,
                                                   std::uint64_t& count) {
  std::ifstream in = openStream(path, field);
  std::string line;
  if (!readLine(in, line, field) || line != "ply") throw ModelError(field, "", "a PLY file starts with the line 'ply'");
  bool ascii = false, sawFormat = false, inVertex = false, vertexSeen = false;
  int offset = 0, index = 0, found[3] = {-1, -1, -1}, column[3] = {-1, -1, -1};
  Scalar type[3] = {Scalar::Float32, Scalar::Float32, Scalar::Float32};
  int offsets[3] = {0, 0, 0};
  count = 0;
  for (int lines = 0;; ++lines) {
    if (lines > 10000 || !readLine(in, line, field)) throw ModelError(field, "", "a PLY header ends with 'end_header'");
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "end_header") break;
    if (word == "comment" || word == "obj_info" || word.empty()) continue;
    if (word == "format") {
      std::string kind;
      words >> kind;
      if (kind == "ascii") ascii = true;
      else if (kind != "binary_little_endian")
        throw ModelError(field + " format", kind, "PLY clouds are ascii or binary_little_endian");
      sawFormat = true;
    } else if (word == "element") {
      std::string name;
      std::uint64_t n = 0;
      words >> name >> n;
      if (vertexSeen) {
        inVertex = false;
        continue;  // faces and the rest, after the vertices, are not read
      }
      if (name != "vertex") throw ModelError(field + " element", name, "the vertex element comes first");
      inVertex = vertexSeen = true;
      count = n;
    } else if (word == "property") {
      if (!inVertex) continue;
      std::string kind, name;
      words >> kind;
      if (kind == "list") throw ModelError(field + " property", line, "a vertex has no list properties");
      words >> name;
      static const std::pair<const char*, Scalar> kinds[] = {
          {"char", Scalar::Int8},     {"int8", Scalar::Int8},       {"uchar", Scalar::UInt8},   {"uint8", Scalar::UInt8},
          {"short", Scalar::Int16},   {"int16", Scalar::Int16},     {"ushort", Scalar::UInt16}, {"uint16", Scalar::UInt16},
          {"int", Scalar::Int32},     {"int32", Scalar::Int32},     {"uint", Scalar::UInt32},   {"uint32", Scalar::UInt32},
          {"float", Scalar::Float32}, {"float32", Scalar::Float32}, {"double", Scalar::Float64}, {"float64", Scalar::Float64}};
      Scalar s = Scalar::Float32;
      bool known = false;
      for (const auto& [text, value] : kinds)
        if (kind == text) s = value, known = true;
      if (!known) throw ModelError(field + " property " + name, kind, "a PLY scalar type");
      for (int k = 0; k < 3; ++k)
        if (name == std::string(1, static_cast<char>('x' + k))) found[k] = 1, type[k] = s, offsets[k] = offset, column[k] = index;
      offset += bytesOf(s);
      ++index;
    }
  }
  if (!sawFormat) throw ModelError(field, "", "a PLY header has a format line");
  for (int k = 0; k < 3; ++k)
    if (found[k] < 0)
      throw ModelError(field + " vertex", "", std::string("the vertex element has property ") + static_cast<char>('x' + k));
  if (ascii) {
    auto f = std::make_unique<TextFormat>();
    f->field = field;
    f->in = std::move(in);
    f->separators = " \t";
    for (int k = 0; k < 3; ++k) f->column[k] = column[k];
    return f;
  }
  auto f = std::make_unique<RecordFormat>();
  f->field = field;
  f->in = std::move(in);
  f->recordBytes = offset;
  for (int k = 0; k < 3; ++k) f->offset[k] = offsets[k], f->type[k] = type[k];
  return f;
}

}  // namespace

PointCloudReader::PointCloudReader(const std::filesystem::path& path, std::string field)
    : path_(path), field_(std::move(field)) {
  const std::string ext = lowercaseExtension(path);
  try {
    if (ext == ".npy") format_ = std::make_unique<NpyFormat>(path, field_, count_);
    else if (ext == ".f64" || ext == ".f32") format_ = openRaw(path, field_, ext == ".f64", count_);
    else if (ext == ".csv") format_ = openCsv(path, field_, count_);
    else if (ext == ".ply") format_ = openPly(path, field_, count_);
    else throw ModelError(field_, path.string(), "a point cloud is .npy, .ply, .csv, .f32 or .f64");
  } catch (const std::invalid_argument& e) {
    if (dynamic_cast<const ModelError*>(&e)) throw;
    throw ModelError(field_, path.string(), e.what());  // the .npy reader's rule
  } catch (const std::filesystem::filesystem_error& e) {
    throw ModelError(field_, path.string(), std::string("cannot be read: ") + e.code().message());
  } catch (const std::runtime_error& e) {
    // A missing or unreadable file is the argument's fault, like a missing model.
    throw ModelError(field_, path.string(), std::string("cannot be read: ") + e.what());
  }
  if (count_ == 0) throw ModelError(field_, path.string(), "the cloud has no points");
  if (count_ > kMaxCloudPoints)
    throw ModelError(field_, std::to_string(count_) + " points", "at most 2^40 points");
}

PointCloudReader::~PointCloudReader() = default;

void PointCloudReader::skip(std::uint64_t count) {
  if (count > count_ - done_) throw std::logic_error("PointCloudReader::skip: past the cloud's end");
  try {
    format_->skip(count);
  } catch (const std::invalid_argument& e) {
    if (dynamic_cast<const ModelError*>(&e)) throw;
    throw ModelError(field_, path_.string(), e.what());
  }
  done_ += count;
}

bool PointCloudReader::next(std::vector<glm::dvec3>& out, std::size_t max) {
  out.clear();
  const std::uint64_t n = std::min<std::uint64_t>(max, count_ - done_);
  if (n == 0) return false;
  try {
    format_->read(out, static_cast<size_t>(n));
  } catch (const std::invalid_argument& e) {
    if (dynamic_cast<const ModelError*>(&e)) throw;
    throw ModelError(field_, path_.string(), e.what());
  }
  for (std::size_t k = 0; k < out.size(); ++k)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(out[k][c]))
        throw ModelError(field_ + " point " + std::to_string(done_ + k), shortestText(out[k][c]),
                         "every coordinate is finite");
  done_ += n;
  return true;
}

}  // namespace shapespline::io
