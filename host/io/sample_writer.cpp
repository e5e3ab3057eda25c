#include <shapespline/io/sample_writer.h>

#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/core/value_text.h>
#include <shapespline/io/file_extension.h>
#include <shapespline/io/welded_mesh.h>

#include <shapespline/io/number_text.h>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace shapespline::io {

void setSurfaceItems(const SurfaceShape& sm, SampleLayout& layout) {
  SurfaceGridItems items = surfaceGridItems(sm);
  layout.totalItems = items.size();
  layout.spanU = std::move(items.u);
  layout.spanV = std::move(items.v);
  layout.itemsV = layout.spanV.size();
  layout.closedU = sm.closedU;
  layout.closedV = sm.closedV;
  const bool knotVector = parameterizationOf(sm) == Parameterization::KnotVector;
  auto interval = [&](int i, const std::vector<double>& knots) {
    return knotVector ? std::pair{knots[static_cast<size_t>(i)], knots[static_cast<size_t>(i) + 1]}
                      : std::pair{static_cast<double>(i), static_cast<double>(i) + 1.0};
  };
  for (int i : layout.spanU) layout.paramU.push_back(interval(i, sm.knotsU));
  for (int j : layout.spanV) layout.paramV.push_back(interval(j, sm.knotsV));
}

OutputFormat outputFormatFromPath(const std::filesystem::path& path, const std::string& option) {
  const std::string ext = lowercaseExtension(path);
  if (ext == ".obj") return OutputFormat::Obj;
  if (ext == ".ply") return OutputFormat::Ply;
  if (ext == ".csv") return OutputFormat::Csv;
  if (ext == ".f32") return OutputFormat::RawF32;
  if (ext == ".f64") return OutputFormat::RawF64;
  if (ext == ".npy") return OutputFormat::Npy;
  if (ext == ".svg") return OutputFormat::Svg;
  if (ext == ".glb") return OutputFormat::Glb;
  if (ext == ".gltf") return OutputFormat::Gltf;
  if (ext == ".stl") return OutputFormat::Stl;
  throw OutputPathError(option, path.string(),
                        "unknown extension '" + ext +
                            "' (expected .obj, .ply, .csv, .f32, .f64, .npy, .svg, .glb, .gltf or .stl)");
}

void requireGridFormat(OutputFormat format, const std::filesystem::path& path, const std::string& option) {
  if (format == OutputFormat::Stl) {
    throw OutputPathError(option, path.string(),
                          "STL is written for part meshes only (sample PART.json -o OUT.stl); use .ply, .obj, "
                          ".glb or .gltf for a curve or surface");
  }
}

std::string_view outputFormatName(OutputFormat format) {
  switch (format) {
    case OutputFormat::Obj: return "obj";
    case OutputFormat::Ply: return "ply";
    case OutputFormat::Csv: return "csv";
    case OutputFormat::RawF32: return "f32";
    case OutputFormat::RawF64: return "f64";
    case OutputFormat::Npy: return "npy";
    case OutputFormat::Svg: return "svg";
    case OutputFormat::Glb: return "glb";
    case OutputFormat::Gltf: return "gltf";
    case OutputFormat::Stl: return "stl";
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
  return {rowSpan(row), spanV[col]};
}

int SampleLayout::rowSpan(size_t row) const {
  return spanRows ? spanRows->first + static_cast<int>(row) : spanU[row];
}

std::pair<double, double> SampleLayout::rowParameter(size_t row) const {
  if (!spanRows) return paramU[row];
  const int s = rowSpan(row);
  return {uniformSpanParameter(spanKnots, *spanRows, s, 0.0), uniformSpanParameter(spanKnots, *spanRows, s, 1.0)};
}

namespace {

[[noreturn]] void nonFinite(const std::string& what, double value, size_t item) {
  throw DerivedValueError(what + " of item " + std::to_string(item) +
                          " is not finite; nothing was written (got " + shortestText(value) + ")");
}

// start + s (end - start), kept inside [start, end]: rounding may step past an end, and past
// DBL_MAX to inf for an interval that ends there.
double lerpInside(const std::pair<double, double>& r, double s) {
  const double x = r.first + s * (r.second - r.first);
  return std::clamp(x, std::min(r.first, r.second), std::max(r.first, r.second));
}

}  // namespace

std::pair<double, double> SampleLayout::parameter(size_t item, int a, int b) const {
  const auto ru = rowParameter(item / itemsV);
  const auto& rv = paramV[item % itemsV];
  const double su = samplesU > 1 ? static_cast<double>(a) / (samplesU - 1) : 0.0;
  const double sv = samplesV > 1 ? static_cast<double>(b) / (samplesV - 1) : 0.0;
  const double u = lerpInside(ru, su), v = lerpInside(rv, sv);
  if (!std::isfinite(u)) nonFinite(surface ? "U (global parameter)" : "u (global parameter)", u, item);
  if (!std::isfinite(v)) nonFinite("V (global parameter)", v, item);
  return {u, v};
}

WeldGrid SampleLayout::weldGrid() const {
  const uint64_t columns = surface ? itemsV : 1;
  return WeldGrid(totalItems / columns, columns, samplesU, surface ? samplesV : 1,
                  surface ? closedU : closed, surface && closedV);
}

std::pair<double, double> SampleLayout::texCoord(size_t item, int a, int b) const {
  const auto [u, v] = parameter(item, a, b);
  const double u0 = rowParameter(0).first, u1 = rowParameter(rowCount() - 1).second;
  const double v0 = paramV.front().first, v1 = paramV.back().second;
  // In [0, 1] by construction; the clamp absorbs rounding at the ends (u = u1 may give 1 + ulp).
  const double s = u1 > u0 ? std::clamp((u - u0) / (u1 - u0), 0.0, 1.0) : 0.0;
  const double t = v1 > v0 ? std::clamp((v - v0) / (v1 - v0), 0.0, 1.0) : 0.0;
  if (!std::isfinite(s)) nonFinite("texture coordinate s", s, item);
  if (!std::isfinite(t)) nonFinite("texture coordinate t", t, item);
  return {s, t};
}

void SampleLayout::checkDerivedValues() const {
  auto check = [&](size_t count, const auto& rangeOf, const char* name) {
    for (size_t k = 0; k < count; ++k) {
      const auto [a, b] = rangeOf(k);
      for (double x : {a, b, b - a})
        if (!std::isfinite(x)) nonFinite(std::string(name) + " interval [" + shortestText(a) + ", " + shortestText(b) + "]", x, k);
    }
    if (count > 0 && !std::isfinite(rangeOf(count - 1).second - rangeOf(0).first)) {
      const double range = rangeOf(count - 1).second - rangeOf(0).first;
      nonFinite(std::string(name) + " range (texture coordinates)", range, 0);
    }
  };
  check(rowCount(), [&](size_t k) { return rowParameter(k); }, surface ? "U" : "u");
  check(paramV.size(), [&](size_t k) { return paramV[k]; }, "V");
}

namespace {

// Every format's writer behind one check: the layout's derived values before the first byte, and a
// DerivedValueError of a later call (a value that slipped past the check) as an output failure.
class CheckedWriter final : public SampleWriter {
 public:
  CheckedWriter(std::unique_ptr<SampleWriter> inner, AtomicFile& out) : inner_(std::move(inner)), out_(out) {}
  void begin(const SampleLayout& layout) override {
    guard([&] {
      layout.checkDerivedValues();
      inner_->begin(layout);
    });
  }
  bool writeSlice(const GridChunk& chunk, size_t first, size_t count) override {
    return guard([&] { return inner_->writeSlice(chunk, first, count); });
  }
  void consume(const GridChunk& chunk) override { guard([&] { inner_->consume(chunk); }); }
  // Only positioned, encoded writes go through a sink: there is no derived value to guard.
  std::optional<RecordSink> recordSink() override { return inner_->recordSink(); }
  void setIdentity(const std::string& job, const JobMetadata& metadata) override { inner_->setIdentity(job, metadata); }
  void finish() override { guard([&] { inner_->finish(); }); }

 private:
  template <class F>
  auto guard(const F& f) -> decltype(f()) {
    try {
      return f();
    } catch (const DerivedValueError& e) {
      throw OutputWriteError(out_.option(), out_.target().string(), e.what());
    }
  }
  std::unique_ptr<SampleWriter> inner_;
  AtomicFile& out_;
};

std::unique_ptr<SampleWriter> makeUncheckedWriter(OutputFormat format, AtomicFile& out, AtomicFile* sidecar) {
  switch (format) {
    case OutputFormat::Obj: return makeObjWriter(out);
    case OutputFormat::Ply: return makePlyWriter(out);
    case OutputFormat::Csv: return makeCsvWriter(out);
    case OutputFormat::Svg: return makeSvgWriter(out);
    case OutputFormat::Npy: return makeNpyWriter(out, sidecar);
    case OutputFormat::Glb: return makeGltfWriter(out, nullptr);
    case OutputFormat::Gltf:
      if (!sidecar) throw std::logic_error(".gltf output needs its .bin file");
      return makeGltfWriter(out, sidecar);
    case OutputFormat::Stl: throw std::logic_error("STL is written for part meshes only (io/triangle_mesh.h)");
    case OutputFormat::RawF32:
    case OutputFormat::RawF64:
      if (!sidecar) throw std::logic_error("raw output needs a sidecar file");
      return makeRawWriter(out, *sidecar, format == OutputFormat::RawF32 ? Precision::Float : Precision::Double);
  }
  throw std::logic_error("unknown output format");
}

}  // namespace

FieldMask requiredFields(OutputFormat format, bool surface) {
  FieldMask m = fieldBit(Field::Point);
  if (surface && (format == OutputFormat::Obj || format == OutputFormat::Ply || isGltf(format))) {
    m |= fieldBit(Field::Normal);
  }
  return m;
}

std::unique_ptr<SampleWriter> makeSampleWriter(OutputFormat format, AtomicFile& out, AtomicFile* sidecar) {
  return std::make_unique<CheckedWriter>(makeUncheckedWriter(format, out, sidecar), out);
}

std::vector<std::pair<size_t, size_t>> streamedItemRanges(OutputFormat format, const SampleLayout& layout) {
  const std::pair<size_t, size_t> own{layout.firstItem, layout.firstItem + layout.itemCount};
  if (!isMesh(format) || !layout.welded || !layout.sharded() || layout.itemCount == 0) return {own};
  std::vector<std::pair<size_t, size_t>> ranges;
  const auto context = WeldedNumbering(layout.weldGrid(), own.first, own.second).contextItems();
  for (const auto& [a, b] : context) {
    if (a < own.first) ranges.emplace_back(a, b);
  }
  ranges.push_back(own);
  for (const auto& [a, b] : context) {
    if (a >= own.second) ranges.emplace_back(a, b);
  }
  return ranges;
}

}  // namespace shapespline::io
