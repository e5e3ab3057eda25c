// Issue 12, "every byte written is checked": the values the writers derive themselves (global
// parameters, texture coordinates, SVG pixel coordinates) never reach a file as NaN/Inf. Validation
// keeps valid models away from these layouts (knot differences must be finite); this is the
// writers' own guard behind it, and the SVG scaling that must hold for subnormal extents.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <string>
#include <unistd.h>

#include <shapespline/io/atomic_file.h>
#include <shapespline/io/sample_writer.h>
#include <shapespline/io/svg_writer.h>

namespace shapespline::io {
namespace {

namespace fs = std::filesystem;

class Folder {
 public:
  Folder() : path_(fs::temp_directory_path() / ("shapespline_derived_io_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  fs::path operator/(const std::string& f) const { return path_ / f; }
  bool empty() const { return fs::directory_iterator(path_) == fs::directory_iterator(); }

 private:
  fs::path path_;
};

// Two items of 2 x 2 samples (surfaces) or 2 samples (curves), every field value finite.
struct Job {
  SampleLayout layout;
  std::vector<double> points, normals;
  GridChunk chunk;
};

Job makeJob(bool surface, std::vector<std::pair<double, double>> paramU) {
  Job j;
  SampleLayout& l = j.layout;
  l.surface = surface;
  l.dimension = 3;
  l.samplesU = 2;
  l.samplesV = surface ? 2 : 1;
  l.itemCount = l.totalItems = paramU.size();
  l.itemsV = 1;
  for (size_t k = 0; k < paramU.size(); ++k) l.spanU.push_back(static_cast<int>(k));
  l.spanV = {0};
  l.paramU = std::move(paramU);
  l.paramV = surface ? std::vector<std::pair<double, double>>{{0.0, 1.0}} : std::vector<std::pair<double, double>>{{0.0, 0.0}};
  l.fields = fieldBit(Field::Point) | (surface ? fieldBit(Field::Normal) : 0);
  l.source = "test";
  l.controlPoints = {{0, 0, 0}, {1, 1, 0}};
  const size_t n = l.pointCount();
  for (size_t i = 0; i < n; ++i) {
    j.points.insert(j.points.end(), {double(i), double(i % 3), 0.5});
    j.normals.insert(j.normals.end(), {0.0, 0.0, 1.0});
  }
  j.chunk.firstItem = 0;
  j.chunk.itemCount = l.itemCount;
  j.chunk.pointsPerItem = l.pointsPerItem();
  j.chunk.pointsPerRow = static_cast<size_t>(l.samplesV);
  j.chunk.planes[static_cast<size_t>(Field::Point)] = j.points.data();
  if (surface) j.chunk.planes[static_cast<size_t>(Field::Normal)] = j.normals.data();
  return j;
}

// Runs the whole writer; returns the exception text, or "" when it wrote.
std::string writeAll(OutputFormat format, const Job& job, const fs::path& file) {
  AtomicFile out(file, "-o");
  AtomicFile sidecar(fs::path(file.string() + ".json"), "-o");
  const auto writer = makeSampleWriter(format, out, &sidecar);
  try {
    writer->begin(job.layout);
    writer->consume(job.chunk);
    writer->finish();
  } catch (const OutputWriteError& e) {
    EXPECT_EQ(e.option(), "-o");
    EXPECT_EQ(e.path(), file.string());
    return e.reason();
  }
  out.commit();
  sidecar.commit();
  return "";
}

TEST(DerivedValuesWriter, AParameterIntervalBeyondFp64FailsTheOutputInsteadOfWritingNan) {
  Folder dir;
  const double big = 1.7e308;
  // One interval whose width overflows: every interior global parameter is NaN (CSV U, OBJ vt,
  // PLY s t, the raw sidecar's ranges).
  const Job wide = makeJob(true, {{-big, big}});
  for (const auto& [format, name] : {std::pair{OutputFormat::Csv, "s.csv"}, std::pair{OutputFormat::Obj, "s.obj"},
                                     std::pair{OutputFormat::Ply, "s.ply"}, std::pair{OutputFormat::RawF64, "s.f64"}}) {
    const std::string reason = writeAll(format, wide, dir / name);
    EXPECT_NE(reason.find("is not finite; nothing was written"), std::string::npos) << name << ": '" << reason << "'";
    EXPECT_NE(reason.find("U interval"), std::string::npos) << name << ": " << reason;
  }
  // Finite intervals whose union overflows: texture coordinates (u - u0) / (u1 - u0) are NaN.
  const Job range = makeJob(true, {{-big, 0.0}, {0.0, big}});
  for (const auto& [format, name] : {std::pair{OutputFormat::Obj, "r.obj"}, std::pair{OutputFormat::Ply, "r.ply"}}) {
    const std::string reason = writeAll(format, range, dir / name);
    EXPECT_NE(reason.find("range (texture coordinates)"), std::string::npos) << name << ": '" << reason << "'";
  }
  EXPECT_TRUE(dir.empty()) << "a failed writer left a file";
}

TEST(DerivedValuesWriter, ParametersAtTheEdgeOfFp64StayInsideTheirInterval) {
  // a + s (b - a) may round past b; for b = DBL_MAX that is inf. Clamped: every u of [0, DBL_MAX]
  // and every texture coordinate in [0, 1].
  const double top = std::numeric_limits<double>::max();
  SampleLayout l = makeJob(true, {{0.0, top}}).layout;
  l.samplesU = 7;
  for (int a = 0; a < 7; ++a) {
    const auto [u, v] = l.parameter(0, a, 1);
    EXPECT_TRUE(u >= 0.0 && u <= top) << a << ": " << u;
    EXPECT_EQ(v, 1.0);
    const auto [s, t] = l.texCoord(0, a, 1);
    EXPECT_TRUE(s >= 0.0 && s <= 1.0) << a << ": " << s;
  }
  EXPECT_EQ(l.parameter(0, 6, 0).first, top);
  EXPECT_NO_THROW(l.checkDerivedValues());
}

TEST(DerivedValuesWriter, SvgOfASubnormalExtentIsFiniteAndANonFinitePointFailsTheOutput) {
  Folder dir;
  // A curve 4e-320 wide: the power-of-two scaling factor 2^1063 does not exist in fp64 (it was inf,
  // and every coordinate NaN); the exponent does.
  SvgPolyline unit, small;
  for (int i = 0; i < 9; ++i) {
    unit.points.emplace_back(i, i % 3);
    small.points.emplace_back(0x1p-1064 * i, 0x1p-1064 * (i % 3));  // 4e-320 wide, exact
  }
  SvgPlot tiny(true), one(true);
  tiny.add(small);
  one.add(unit);
  const std::string a = tiny.render(), b = one.render();
  EXPECT_EQ(a.find("nan"), std::string::npos) << a;
  EXPECT_EQ(a.find("inf"), std::string::npos) << a;
  // The tiny points are the unit ones times 2^-1064 (exact), so the drawing is the same.
  EXPECT_EQ(a, b);

  // A NaN point: an error, never "nan" in the file; through write(), an output failure naming -o.
  SvgPlot bad(true);
  SvgPolyline l2;
  l2.points = {{0.0, 0.0}, {std::nan(""), 1.0}, {1.0, 1.0}};
  bad.add(l2);
  EXPECT_THROW(bad.render(), SvgValueError);
  {
    AtomicFile out(dir / "bad.svg", "--svg");
    try {
      bad.write(out);
      ADD_FAILURE() << "write() accepted a NaN point";
    } catch (const OutputWriteError& e) {
      EXPECT_EQ(e.option(), "--svg");
      EXPECT_NE(e.reason().find("not finite"), std::string::npos) << e.reason();
    }
  }
  EXPECT_TRUE(dir.empty());
}

}  // namespace
}  // namespace shapespline::io
