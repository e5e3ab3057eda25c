#include <shapespline/io/projection_writer.h>

#include <shapespline/io/file_extension.h>
#include <shapespline/io/raw_records.h>

#include <charconv>

namespace shapespline::io {

std::vector<std::pair<std::string, int>> projectionFields(ProjectionTarget target) {
  std::vector<std::pair<std::string, int>> fields = {{"query", 3}, {"point", 3}};
  if (target == ProjectionTarget::Part) fields.emplace_back("face", 1);
  if (target == ProjectionTarget::Curve) {
    fields.emplace_back("t", 1);
    fields.emplace_back("distance", 1);
    return fields;
  }
  fields.emplace_back("uv", 2);
  fields.emplace_back("distance", 1);
  fields.emplace_back("signed_distance", 1);
  fields.emplace_back("normal", 3);
  return fields;
}

namespace {

std::string csvHeader(ProjectionTarget target) {
  std::string header;
  static const char* axes[] = {"x", "y", "z"};
  for (const auto& [name, width] : projectionFields(target)) {
    for (int k = 0; k < width; ++k) {
      if (!header.empty()) header += ',';
      header += width == 3 ? name + "_" + axes[k] : width == 2 ? std::string(k ? "v" : "u") : name;
    }
  }
  return header + "\n";
}

std::string plyHeader(ProjectionTarget target, std::uint64_t count) {
  std::string h = "ply\nformat binary_little_endian 1.0\ncomment shapespline project\nelement vertex " +
                  std::to_string(count) + "\nproperty double x\nproperty double y\nproperty double z\n";
  static const char* axes[] = {"x", "y", "z"};
  for (const auto& [name, width] : projectionFields(target)) {
    if (name == "query") continue;
    for (int k = 0; k < width; ++k) {
      const std::string property = name == "point"    ? std::string("foot_") + axes[k]
                                   : name == "normal" ? std::string("n") + axes[k]
                                   : width == 2       ? std::string(k ? "v" : "u")
                                                      : name;
      h += (name == "face" ? "property int " : "property double ") + property + "\n";
    }
  }
  return h + "end_header\n";
}

int valueCount(ProjectionTarget target) {
  int n = 0;
  for (const auto& field : projectionFields(target)) n += field.second;
  return n;
}

}  // namespace

ProjectionFormat projectionFormat(const std::filesystem::path& path, const std::string& option) {
  const std::string ext = lowercaseExtension(path);
  if (ext == ".npy") return ProjectionFormat::Npy;
  if (ext == ".f64") return ProjectionFormat::F64;
  if (ext == ".csv") return ProjectionFormat::Csv;
  if (ext == ".ply") return ProjectionFormat::Ply;
  throw OutputPathError(option, path.string(), "the projection's output is .npy, .f64, .csv or .ply");
}

std::string projectionHeader(ProjectionFormat format, ProjectionTarget target, std::uint64_t count) {
  switch (format) {
    case ProjectionFormat::Npy: return npyHeader(projectionFields(target), true, count);
    case ProjectionFormat::F64: return "";
    case ProjectionFormat::Csv: return csvHeader(target);
    case ProjectionFormat::Ply: return plyHeader(target, count);
  }
  return "";
}

std::uint64_t projectionRecordBytes(ProjectionFormat format, ProjectionTarget target) {
  if (format == ProjectionFormat::Csv) return 0;
  const std::uint64_t doubles = std::uint64_t(valueCount(target)) * 8;
  // PLY stores the face as a 4-byte int.
  return format == ProjectionFormat::Ply && target == ProjectionTarget::Part ? doubles - 4 : doubles;
}

namespace {

// A record's values in the order of projectionFields.
int valuesOf(const ProjectionRecord& r, ProjectionTarget target, double out[16]) {
  int n = 0;
  for (int k = 0; k < 3; ++k) out[n++] = r.query[k];
  for (int k = 0; k < 3; ++k) out[n++] = r.point[k];
  if (target == ProjectionTarget::Part) out[n++] = r.face;
  out[n++] = r.u;
  if (target == ProjectionTarget::Curve) {
    out[n++] = r.distance;
    return n;
  }
  out[n++] = r.v;
  out[n++] = r.distance;
  out[n++] = r.signedDistance;
  for (int k = 0; k < 3; ++k) out[n++] = r.normal[k];
  return n;
}

// .npy and .f64: the records as fp64 values (the .npy after its header).
class RecordWriter final : public ProjectionWriter {
 public:
  RecordWriter(AtomicFile& out, ProjectionTarget target) : out_(out), target_(target) {}
  void write(std::span<const ProjectionRecord> records) override {
    double values[16];
    for (const ProjectionRecord& r : records) out_.write(values, sizeof(double) * valuesOf(r, target_, values));
  }

 private:
  AtomicFile& out_;
  ProjectionTarget target_;
};

class CsvWriter final : public ProjectionWriter {
 public:
  CsvWriter(AtomicFile& out, ProjectionTarget target) : out_(out), target_(target) {}
  void write(std::span<const ProjectionRecord> records) override {
    double values[16];
    for (const ProjectionRecord& r : records) {
      const int n = valuesOf(r, target_, values);
      char* p = out_.space(n * 32 + 1);
      char* start = p;
      for (int k = 0; k < n; ++k) {
        if (k) *p++ = ',';
        p = std::to_chars(p, p + 32, values[k], std::chars_format::general, 17).ptr;
      }
      *p++ = '\n';
      out_.advance(static_cast<size_t>(p - start));
    }
  }

 private:
  AtomicFile& out_;
  ProjectionTarget target_;
};

// Binary PLY: x, y, z the query point, then every other field as double properties (`face` an int).
class PlyWriter final : public ProjectionWriter {
 public:
  PlyWriter(AtomicFile& out, ProjectionTarget target) : out_(out), target_(target) {}
  void write(std::span<const ProjectionRecord> records) override {
    double values[16];
    for (const ProjectionRecord& r : records) {
      const int n = valuesOf(r, target_, values);
      for (int k = 0; k < n; ++k) {
        if (target_ == ProjectionTarget::Part && k == 6) {
          const std::int32_t face = r.face;
          out_.write(&face, sizeof face);
        } else {
          out_.write(&values[k], sizeof(double));
        }
      }
    }
  }

 private:
  AtomicFile& out_;
  ProjectionTarget target_;
};

}  // namespace

std::unique_ptr<ProjectionWriter> makeProjectionWriter(AtomicFile& out, const std::filesystem::path& path,
                                                       const std::string& option, ProjectionTarget target,
                                                       std::uint64_t count) {
  const ProjectionFormat format = projectionFormat(path, option);
  out.write(projectionHeader(format, target, count));
  switch (format) {
    case ProjectionFormat::Npy:
    case ProjectionFormat::F64: return std::make_unique<RecordWriter>(out, target);
    case ProjectionFormat::Csv: return std::make_unique<CsvWriter>(out, target);
    case ProjectionFormat::Ply: return std::make_unique<PlyWriter>(out, target);
  }
  return nullptr;
}

}  // namespace shapespline::io
