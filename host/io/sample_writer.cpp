#include "io/sample_writer.h"

#include <algorithm>
#include <cctype>

namespace shapespline::io {

OutputFormat outputFormatFromPath(const std::filesystem::path& path, const std::string& option) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return OutputFormat::Obj;
  if (ext == ".ply") return OutputFormat::Ply;
  if (ext == ".csv") return OutputFormat::Csv;
  if (ext == ".f32") return OutputFormat::RawF32;
  if (ext == ".f64") return OutputFormat::RawF64;
  if (ext == ".svg") return OutputFormat::Svg;
  throw OutputPathError(option, path.string(),
                        "unknown extension '" + ext + "' (expected .obj, .ply, .csv, .f32, .f64 or .svg)");
}

std::string_view outputFormatName(OutputFormat format) {
  switch (format) {
    case OutputFormat::Obj: return "obj";
    case OutputFormat::Ply: return "ply";
    case OutputFormat::Csv: return "csv";
    case OutputFormat::RawF32: return "f32";
    case OutputFormat::RawF64: return "f64";
    case OutputFormat::Svg: return "svg";
  }
  return "?";
}

std::string_view fieldName(Field field) {
  switch (field) {
    case Field::Point: return "point";
    case Field::D1: return "d1";
    case Field::D2: return "d2";
    case Field::Du: return "du";
    case Field::Dv: return "dv";
    case Field::Duu: return "duu";
    case Field::Duv: return "duv";
    case Field::Dvv: return "dvv";
    case Field::Normal: return "normal";
    case Field::Count: break;
  }
  return "?";
}

std::pair<int, int> SampleLayout::itemIndex(size_t item) const {
  const size_t row = item / itemsV, col = item % itemsV;
  return {spanU[row], spanV[col]};
}

std::pair<double, double> SampleLayout::parameter(size_t item, int a, int b) const {
  const auto& ru = paramU[item / itemsV];
  const auto& rv = paramV[item % itemsV];
  const double su = samplesU > 1 ? static_cast<double>(a) / (samplesU - 1) : 0.0;
  const double sv = samplesV > 1 ? static_cast<double>(b) / (samplesV - 1) : 0.0;
  return {ru.first + su * (ru.second - ru.first), rv.first + sv * (rv.second - rv.first)};
}

std::pair<double, double> SampleLayout::texCoord(size_t item, int a, int b) const {
  const auto [u, v] = parameter(item, a, b);
  const double u0 = paramU.front().first, u1 = paramU.back().second;
  const double v0 = paramV.front().first, v1 = paramV.back().second;
  return {u1 > u0 ? (u - u0) / (u1 - u0) : 0.0, v1 > v0 ? (v - v0) / (v1 - v0) : 0.0};
}

FieldMask requiredFields(OutputFormat format, bool surface) {
  FieldMask m = fieldBit(Field::Point);
  if (surface && (format == OutputFormat::Obj || format == OutputFormat::Ply)) m |= fieldBit(Field::Normal);
  return m;
}

std::unique_ptr<SampleWriter> makeSampleWriter(OutputFormat format, AtomicFile& out, AtomicFile* sidecar) {
  switch (format) {
    case OutputFormat::Obj: return makeObjWriter(out);
    case OutputFormat::Ply: return makePlyWriter(out);
    case OutputFormat::Csv: return makeCsvWriter(out);
    case OutputFormat::Svg: return makeSvgWriter(out);
    case OutputFormat::RawF32:
    case OutputFormat::RawF64:
      if (!sidecar) throw std::logic_error("raw output needs a sidecar file");
      return makeRawWriter(out, *sidecar, format == OutputFormat::RawF32 ? Precision::Float : Precision::Double);
  }
  throw std::logic_error("unknown output format");
}

}  // namespace shapespline::io
