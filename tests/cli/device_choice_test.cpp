// The sampling layer seen from the command line: knot-vector B-splines sample and evaluate on the
// GPU (--device vulkan --require-device) with the CPU fp64 path's results, the report lands in the
// raw sidecar ("device", "computed_precision": the CPU path computes fp64 even for .f32 output),
// and --device auto is the default.
//
// Tolerances (tests/support/tolerances.h; tests/gpu/gpu_bspline_test.cpp derives them), scale =
// bounding-box diagonal of the net, k = order, h = smallest non-empty knot interval: points
// 4 rel * scale, first derivatives times 8 k / h, second derivatives times 64 k^2 / h^2; rel =
// kFp32Rel for fp32 kernels, kFp64Rel for fp64.
#include "output_checks.h"
#include "support/tolerances.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct KnotModel {
  const char* file;
  bool surface;
  int order;
  double scale, h;  // net diagonal, smallest non-empty knot interval (from the file, below)
};

// clamped_bspline.json: points span [0,8] x [0,4]; knots 0 0 0 0 .25 .5 1 1 1 1.
// bspline_surface.json: points span [0,3] x [0,3] x [0,2]; knots 0 0 0 .5 1 1 1 both ways.
const KnotModel kCurve{"clamped_bspline.json", false, 4, std::sqrt(8.0 * 8.0 + 4.0 * 4.0), 0.25};
const KnotModel kSurface{"bspline_surface.json", true, 3, std::sqrt(3.0 * 3.0 + 3.0 * 3.0 + 2.0 * 2.0), 0.5};

double tolerance(const std::string& field, const KnotModel& m, bool fp32) {
  const double base = 4 * (fp32 ? kFp32Rel : kFp64Rel) * m.scale, r1 = 8.0 * m.order / m.h;
  if (field == "point") return base;
  if (field == "d1" || field == "du" || field == "dv") return base * r1;
  if (field == "normal") return 1e-3;  // unit vectors; not compared near degenerate corners here
  return base * r1 * r1;
}

std::vector<double> readValues(const fs::path& file, bool fp32) {
  const std::string bytes = readText(file);
  std::vector<double> v;
  const size_t size = fp32 ? 4 : 8;
  for (size_t i = 0; i + size <= bytes.size(); i += size) {
    if (fp32) {
      float x;
      std::memcpy(&x, bytes.data() + i, 4);
      v.push_back(x);
    } else {
      double x;
      std::memcpy(&x, bytes.data() + i, 8);
      v.push_back(x);
    }
  }
  return v;
}

TEST(CliDeviceChoice, KnotVectorSampleOnTheGpuMatchesTheCpu) {
  REQUIRE_VULKAN();
  ScratchDir dir("device_knots_sample");
  for (const KnotModel& m : {kCurve, kSurface}) {
    for (const bool fp32 : {true, false}) {
      const std::string file = fp32 ? "s.f32" : "s.f64";
      const std::string common = std::string(" --derivatives -q --precision ") + (fp32 ? "float" : "double") +
                                 (m.surface ? " --grid 7" : " --samples 9");
      const std::string what = std::string(m.file) + " " + file;
      const CliResult gpu = runCli("sample " + quote(exampleModel(m.file)) + " -o gpu_" + file +
                                       " --device vulkan --require-device" + common, dir.path(), dir.path());
      ASSERT_EQ(gpu.rc, 0) << what << ": " << gpu.err;
      const CliResult cpu = runCli("sample " + quote(exampleModel(m.file)) + " -o cpu_" + file + " --device cpu" + common,
                                   dir.path(), dir.path());
      ASSERT_EQ(cpu.rc, 0) << what << ": " << cpu.err;

      const json gpuSide = json::parse(readText(dir / ("gpu_" + file + ".json")));
      const json cpuSide = json::parse(readText(dir / ("cpu_" + file + ".json")));
      EXPECT_NE(gpuSide.at("device").get<std::string>(), "cpu") << what;
      EXPECT_EQ(gpuSide.at("computed_precision"), fp32 ? "float" : "double") << what;
      EXPECT_EQ(cpuSide.at("device"), "cpu") << what;
      EXPECT_EQ(cpuSide.at("computed_precision"), "double") << what;  // the CPU path computes fp64
      EXPECT_EQ(gpuSide.at("job"), cpuSide.at("job")) << what << ": the device is not part of the job";

      const auto fields = cpuSide.at("fields").get<std::vector<std::string>>();
      const std::vector<double> expect = readValues(dir / ("cpu_" + file), fp32);
      const std::vector<double> got = readValues(dir / ("gpu_" + file), fp32);
      ASSERT_EQ(expect.size(), got.size()) << what;
      ASSERT_GT(expect.size(), 0u) << what;
      int failures = 0;
      for (size_t i = 0; i < expect.size(); ++i) {
        const std::string& field = fields[(i / 3) % fields.size()];
        const double tol = tolerance(field, m, fp32);
        if (!(std::abs(expect[i] - got[i]) <= tol) && failures++ < 5)
          ADD_FAILURE() << what << " value " << i << " (" << field << "): cpu " << expect[i] << " gpu " << got[i]
                        << " tol " << tol;
      }
    }
  }
}

TEST(CliDeviceChoice, KnotVectorEvalOnTheGpuMatchesTheCpu) {
  REQUIRE_VULKAN();
  ScratchDir dir("device_knots_eval");
  writeText(dir / "curve_at.json", R"({"samples": [{"u": 0}, {"u": 0.1}, {"u": 0.25}, {"u": 0.7}, {"u": 1}]})");
  writeText(dir / "surface_at.json",
            R"({"samples": [{"patch": [2, 2], "uv": [0.2, 0.7]}, {"patch": [3, 2], "uv": [1, 0.5]},
                            {"patch": [3, 3], "uv": [0.5, 0]}]})");  // patches: knot intervals 2..3
  for (const KnotModel& m : {kCurve, kSurface}) {
    const bool curve = !m.surface;
    for (const bool fp32 : {true, false}) {
      const std::string at = curve ? "curve_at.json" : "surface_at.json";
      const std::string common = std::string(" --at ") + at + " -q --precision " + (fp32 ? "float" : "double");
      const std::string what = std::string(m.file) + (fp32 ? " fp32" : " fp64");
      const CliResult gpu = runCli("eval " + quote(exampleModel(m.file)) + common + " --device vulkan --require-device",
                                   dir.path(), dir.path());
      ASSERT_EQ(gpu.rc, 0) << what << ": " << gpu.err;
      const CliResult cpu = runCli("eval " + quote(exampleModel(m.file)) + common + " --device cpu", dir.path(), dir.path());
      ASSERT_EQ(cpu.rc, 0) << what << ": " << cpu.err;
      const json g = json::parse(gpu.out).at("samples"), c = json::parse(cpu.out).at("samples");
      ASSERT_EQ(g.size(), c.size()) << what;
      const std::vector<std::string> fields = curve ? std::vector<std::string>{"point", "d1", "d2"}
                                                    : std::vector<std::string>{"point", "du", "dv", "duu", "duv", "dvv"};
      for (size_t i = 0; i < c.size(); ++i) {
        for (const auto& f : fields) {
          const auto e = c[i].at(f).get<std::vector<double>>(), x = g[i].at(f).get<std::vector<double>>();
          ASSERT_EQ(e.size(), x.size()) << what;
          for (size_t a = 0; a < e.size(); ++a)
            EXPECT_NEAR(e[a], x[a], tolerance(f, m, fp32)) << what << " sample " << i << " " << f << "[" << a << "]";
        }
      }
    }
  }
}

TEST(CliDeviceChoice, AutoIsTheDefaultAndABadDeviceNamesTheChoices) {
  ScratchDir dir("device_auto");
  const std::string model = quote(exampleModel("open_aeb.json"));
  const CliResult byDefault = runCli("sample " + model + " -o d.f64 --samples 5 -q", dir.path(), dir.path());
  const CliResult byAuto = runCli("sample " + model + " -o a.f64 --samples 5 -q --device auto", dir.path(), dir.path());
  ASSERT_EQ(byDefault.rc, 0) << byDefault.err;
  ASSERT_EQ(byAuto.rc, 0) << byAuto.err;
  EXPECT_EQ(readText(dir / "d.f64"), readText(dir / "a.f64"));
  json d = json::parse(readText(dir / "d.f64.json")), a = json::parse(readText(dir / "a.f64.json"));
  d.erase("data_file");
  a.erase("data_file");
  EXPECT_EQ(d, a);
  const CliResult bad = runCli("sample " + model + " -o b.f64 --device tpu", dir.path(), dir.path());
  EXPECT_EQ(bad.rc, 2);
  EXPECT_TRUE(contains(bad.err, "--device: expected auto, vulkan or cpu (got tpu)")) << bad.err;
}

}  // namespace
}  // namespace shapespline::test
