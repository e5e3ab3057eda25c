// Issue 12, "NaN written" and the extreme-value exit codes: values the writers derive themselves
// (CSV u/U/V, PLY s t, OBJ vt, SVG coordinates, eval u/UV) are finite or the model is refused up
// front naming the field; subnormal nets evaluate on the default GPU path as on the CPU; knot
// intervals near 1e-310 and α near 1e-310 write finite values or fail with a documented exit code
// and message, never "internal error", never a file.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <regex>
#include <sstream>
#include <tuple>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// `sample MODEL -o folder/file opts` in a fresh folder.
CliResult sample(const fs::path& model, const fs::path& folder, const std::string& file, const std::string& opts) {
  fs::remove_all(folder);
  fs::create_directories(folder);
  return runCli("sample " + quote(model.string()) + " -o " + quote((folder / file).string()) + " " + opts, folder);
}

// Exit `rc`, the message names every part, and the folder holds no file at all.
void expectRefused(const CliResult& r, int rc, const std::vector<std::string>& parts, const fs::path& folder,
                   const std::string& what) {
  EXPECT_EQ(r.rc, rc) << what << ": " << r.err;
  EXPECT_TRUE(contains(r.err, "shapespline: error: ")) << what << ": " << r.err;
  EXPECT_FALSE(contains(r.err, "internal error")) << what << ": " << r.err;
  for (const auto& p : parts) EXPECT_TRUE(contains(r.err, p)) << what << ": missing '" << p << "' in " << r.err;
  const auto left = entries(folder);
  EXPECT_TRUE(left.empty()) << what << ": left " << (left.empty() ? "" : left[0]);
}

// Six-point curve nets, scaled.
std::string curvePoints(double scale) {
  const double xy[6][2] = {{0, 0}, {1, 2}, {3, 3}, {5, 1}, {6, 4}, {8, 3}};
  std::string s = "[";
  char buf[64];
  for (int i = 0; i < 6; ++i) {
    std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g]", i ? ", " : "", xy[i][0] * scale, xy[i][1] * scale);
    s += buf;
  }
  return s + "]";
}

std::string surfacePoints(double scale) {
  std::string s = "[";
  char buf[96];
  for (int i = 0; i < 4; ++i) {
    s += i ? ", [" : "[";
    for (int j = 0; j < 4; ++j) {
      const double z = std::sin(0.9 * i + 0.3) * std::cos(0.7 * j);
      std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g, %.17g]", j ? ", " : "", i * scale, j * scale, z * scale);
      s += buf;
    }
    s += "]";
  }
  return s + "]";
}

const std::vector<std::string> kCurveFiles = {"c.csv", "c.obj", "c.ply", "c.f64", "c.svg"};
const std::vector<std::string> kSurfaceFiles = {"s.csv", "s.obj", "s.ply", "s.f64"};

double readDouble(const std::string& bytes, size_t i) {
  double v;
  std::memcpy(&v, bytes.data() + i * 8, 8);
  return v;
}

// ---- 1. Knot differences beyond fp64: refused up front, naming the knot ---------------------------

TEST(CliDerivedValues, KnotDifferencesBeyondFp64AreRefusedNamingTheKnot) {
  ScratchDir dir("derived_knots");
  // Each knot is finite; t_2 - t_0 (the span [-1e308, 1e308] and the parameter range) is not. Before
  // the fix `sample` wrote "-nan" into the CSV u column (and eval printed "u": inf) with exit 0.
  struct Case {
    std::string tag, json, field;
    bool surface;
  };
  const std::string open = R"({"kind": "curve", "closed": false, "points": )" + curvePoints(1.0);
  const std::vector<Case> cases = {
      {"gb", open + R"(, "construction": "gb", "lambda": 0, "knots": [-1.7e308, -1e308, 1e308, 1.7e308]})", "knots[2]",
       false},
      {"xw", open + R"(, "construction": "extended_bspline", "degree": 5, "lambda": 0, "knots": [-1.7e308, -1e308, 0, 1.7e308]})",
       "knots[3]", false},
      {"bspline", open + R"(, "construction": "bspline", "order": 4, "knots": [-1.7e308, -1.7e308, -1.7e308, -1.7e308, 0, 1e308, 1.7e308, 1.7e308, 1.7e308, 1.7e308]})",
       "knots[5]", false},
      {"bspline_surface",
       R"({"kind": "surface", "construction": "bspline", "order": [3, 3], "closed": [false, false], "points": )" +
           surfacePoints(1.0) + R"(, "knots": [[0, 0, 0, 0.5, 1, 1, 1], [-1e308, -1e308, -1e308, 0, 1e308, 1e308, 1e308]]})",
       "knots[1][4]", true},
  };
  for (const auto& c : cases) {
    const fs::path m = dir / (c.tag + ".json");
    writeText(m, c.json);
    for (const auto& file : c.surface ? kSurfaceFiles : kCurveFiles) {
      for (const char* dev : {"--device cpu", "--device vulkan"}) {
        const fs::path out = dir / ("o_" + c.tag);
        const CliResult r = sample(m, out, file, std::string(dev) + (c.surface ? " --grid 3" : " --samples 4"));
        expectRefused(r, 2, {c.field + ": knot differences must be finite"}, out, c.tag + " " + file + " " + dev);
      }
    }
    writeText(dir / "at.json", c.surface ? R"({"samples": [{"patch": [2, 3], "uv": [0.5, 0.5]}]})"
                                         : c.tag == "bspline" ? R"({"samples": [{"u": 0}]})"
                                                              : R"({"samples": [{"span": 2, "t": 0.5}]})");
    const CliResult e = runCli("eval " + quote(m.string()) + " --at " + quote((dir / "at.json").string()), dir.path());
    EXPECT_EQ(e.rc, 2) << c.tag << ": " << e.err;
    EXPECT_TRUE(contains(e.err, c.field + ": ")) << c.tag << ": " << e.err;
    EXPECT_TRUE(e.out.empty()) << c.tag << ": " << e.out;
  }
}

TEST(CliDerivedValues, KnotsNearTheFp64LimitWithFiniteDifferencesStillWrite) {
  // The rule is the difference, not the magnitude: knots up to 1.7e308 of one sign are fine, and
  // every derived column (u, texture coordinates) is finite.
  ScratchDir dir("derived_knots_ok");
  const fs::path m = dir / "gb.json";
  writeText(m, R"({"kind": "curve", "closed": false, "construction": "gb", "lambda": 0, "points": )" + curvePoints(1.0) +
                   R"(, "knots": [0, 1e308, 1.5e308, 1.7e308]})");
  for (const auto& file : kCurveFiles) {
    const CliResult r = sample(m, dir / "o", file, "--device cpu --samples 4 -q");
    ASSERT_EQ(r.rc, 0) << file << ": " << r.err;
    expectFiniteOutput(dir / "o" / file, "gb near 1.7e308 " + file);
  }
  const fs::path s = dir / "s.json";
  writeText(s, R"({"kind": "surface", "construction": "bspline", "order": [3, 3], "closed": [false, false], "points": )" +
                   surfacePoints(1.0) + R"(, "knots": [[0, 0, 0, 0.5, 1, 1, 1], [0, 0, 0, 1e308, 1.7e308, 1.7e308, 1.7e308]]})");
  for (const auto& file : kSurfaceFiles) {
    const CliResult r = sample(s, dir / "so", file, "--device cpu --grid 3 -q");
    ASSERT_EQ(r.rc, 0) << file << ": " << r.err;
    expectFiniteOutput(dir / "so" / file, "bspline surface near 1.7e308 " + file);
  }
}

// ---- 2. Subnormal nets: SVG scaling and the default GPU path --------------------------------------

TEST(CliDerivedValues, ACurveFourE320WideWritesAFiniteSvg) {
  // The SVG viewBox scaling took 2^-ilogb(extent) as a factor, which overflows for a subnormal
  // extent: every coordinate came out NaN with exit 0.
  ScratchDir dir("derived_svg");
  const fs::path m = dir / "c.json";
  writeText(m, R"({"kind": "curve", "construction": "ubp", "order": 4, "lambda": 0, "points": )" + curvePoints(5e-321) + "}");
  const CliResult r = sample(m, dir / "o", "c.svg", "--device cpu --samples 8 -q");
  ASSERT_EQ(r.rc, 0) << r.err;
  expectFiniteOutput(dir / "o" / "c.svg", "4e-320 wide svg");
  // The plot fills the frame as it does at scale 1 (the drawing is scale-free): same polylines.
  const fs::path one = dir / "one.json";
  writeText(one, R"({"kind": "curve", "construction": "ubp", "order": 4, "lambda": 0, "points": )" + curvePoints(1.0) + "}");
  const CliResult r1 = sample(one, dir / "o1", "c.svg", "--device cpu --samples 8 -q");
  ASSERT_EQ(r1.rc, 0) << r1.err;
  auto polylines = [](const std::string& svg) {
    std::string s;
    static const std::regex pl(R"re(<polyline[^>]*points="([^"]*)")re");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), pl); it != std::sregex_iterator(); ++it) s += (*it)[1].str();
    return s;
  };
  const std::string a = polylines(readText(dir / "o" / "c.svg")), b = polylines(readText(dir / "o1" / "c.svg"));
  EXPECT_FALSE(a.empty());
  // 5e-321 carries only a few significant bits, so the shape is close to, not equal to, scale 1:
  // compare the number of vertices drawn.
  EXPECT_EQ(std::count(a.begin(), a.end(), ','), std::count(b.begin(), b.end(), ','));
}

TEST(CliDerivedValues, SubnormalNetsEvaluateOnTheDefaultGpuPathAsOnTheCpu) {
  if (!vulkanDevice()) GTEST_SKIP() << "no Vulkan device";
  // netScale returned the factor 2^1063 (inf) for a net 1e-310 wide, and the scaled copy of the
  // net was refused as "points[0][0]: coordinates must be finite numbers (got nan)" (exit 2).
  ScratchDir dir("derived_gpu_subnormal");
  const fs::path c = dir / "c.json", s = dir / "s.json";
  writeText(c, R"({"kind": "curve", "construction": "gb", "lambda": 0, "points": )" + curvePoints(1e-310) + "}");
  writeText(s, R"({"kind": "surface", "construction": "ubp", "order": 4, "lambda": 0, "points": )" + surfacePoints(1e-310) + "}");
  for (const auto& [m, opts, values] : {std::tuple{c, std::string("--samples 5 --derivatives"), size_t{9}},
                                        std::tuple{s, std::string("--grid 3 --derivatives --normals"), size_t{21}}}) {
    const CliResult cpu = sample(m, dir / "cpu", "x.f64", opts + " --device cpu -q");
    ASSERT_EQ(cpu.rc, 0) << m << ": " << cpu.err;
    const CliResult gpu = sample(m, dir / "gpu", "x.f64", opts + " --require-device -q");  // default device
    ASSERT_EQ(gpu.rc, 0) << m << ": " << gpu.err;
    const std::string a = readText(dir / "cpu" / "x.f64"), b = readText(dir / "gpu" / "x.f64");
    ASSERT_EQ(a.size(), b.size()) << m;
    expectFiniteBinary<double>(b.data(), b.size(), m.string());
    // Per field, relative to the field's largest magnitude: positions and derivatives of a 1e-310
    // net are subnormal on the CPU (about 40 significant bits), so 1e-9 of the field's extent.
    std::vector<double> scale(values / 3, 0.0);
    for (size_t i = 0; i < a.size() / 8; ++i)
      scale[(i % values) / 3] = std::max(scale[(i % values) / 3], std::abs(readDouble(a, i)));
    for (size_t i = 0; i < a.size() / 8; ++i) {
      const double sc = scale[(i % values) / 3];
      ASSERT_GT(sc, 0.0) << m << " field " << (i % values) / 3;
      EXPECT_LE(std::abs(readDouble(a, i) - readDouble(b, i)), 1e-9 * sc)
          << m << " value " << i << ": cpu " << readDouble(a, i) << " gpu " << readDouble(b, i);
    }
  }
  // eval on the default path agrees too, and prints finite numbers only.
  writeText(dir / "at.json", R"({"samples": [{"span": 2, "t": 0.25}, {"span": 3, "t": 1}]})");
  const CliResult ec = runCli("eval " + quote(c.string()) + " --at " + quote((dir / "at.json").string()) + " --device cpu", dir.path());
  const CliResult eg = runCli("eval " + quote(c.string()) + " --at " + quote((dir / "at.json").string()) + " --require-device", dir.path());
  ASSERT_EQ(ec.rc, 0) << ec.err;
  ASSERT_EQ(eg.rc, 0) << eg.err;
  expectFiniteText(eg.out, "eval gpu");
  const json jc = json::parse(ec.out), jg = json::parse(eg.out);
  for (size_t i = 0; i < 2; ++i)
    for (int k = 0; k < 2; ++k) {
      const double x = jc["samples"][i]["point"][k], y = jg["samples"][i]["point"][k];
      EXPECT_LE(std::abs(x - y), 1e-9 * 8e-310) << "sample " << i << ": cpu " << x << " gpu " << y;
    }
}

// ---- 3. Knot intervals near 1e-310 ---------------------------------------------------------------

TEST(CliDerivedValues, KnotIntervalsOfE310WarnAndWriteEveryFormat) {
  // The B-spline recurrence divides basis values by knot differences: 1 / 1e-310 overflowed and every
  // point was NaN ("point: evaluation produced a non-finite value (internal error)", exit 3); surface
  // normals need du x dv, whose factors overflow fp64 while their direction does not.
  ScratchDir dir("derived_tiny_knots");
  const fs::path c = dir / "c.json", s = dir / "s.json", g = dir / "g.json";
  writeText(c, R"({"kind": "curve", "construction": "bspline", "order": 4, "closed": false, "points": )" + curvePoints(1.0) +
                   R"(, "knots": [0, 0, 0, 0, 1e-310, 2e-310, 3e-310, 3e-310, 3e-310, 3e-310]})");
  writeText(s, R"({"kind": "surface", "construction": "bspline", "order": [3, 3], "closed": [false, false], "points": )" +
                   surfacePoints(1.0) + R"(, "knots": [[0, 0, 0, 1e-310, 2e-310, 2e-310, 2e-310], [0, 0, 0, 0.5, 1, 1, 1]]})");
  writeText(g, R"({"kind": "curve", "construction": "gb", "lambda": 0, "closed": false, "points": )" + curvePoints(1.0) +
                   R"(, "knots": [0, 1e-310, 2e-310, 3e-310]})");
  // The same models with ordinary knots (the parametrisation is affine in the knots, so points agree).
  const fs::path c1 = dir / "c1.json", s1 = dir / "s1.json";
  writeText(c1, R"({"kind": "curve", "construction": "bspline", "order": 4, "closed": false, "points": )" + curvePoints(1.0) +
                    R"(, "knots": [0, 0, 0, 0, 1, 2, 3, 3, 3, 3]})");
  writeText(s1, R"({"kind": "surface", "construction": "bspline", "order": [3, 3], "closed": [false, false], "points": )" +
                    surfacePoints(1.0) + R"(, "knots": [[0, 0, 0, 1, 2, 2, 2], [0, 0, 0, 0.5, 1, 1, 1]]})");
  for (const char* dev : {"--device cpu", "--device vulkan"}) {
    for (const auto& [m, files] : {std::pair{c, kCurveFiles}, std::pair{g, kCurveFiles}, std::pair{s, kSurfaceFiles}}) {
      for (const auto& file : files) {
        const CliResult r = sample(m, dir / "o", file, std::string(dev) + (m == s ? " --grid 4" : " --samples 5"));
        const std::string what = m.filename().string() + " " + file + " " + dev;
        ASSERT_EQ(r.rc, 0) << what << ": " << r.err;
        EXPECT_TRUE(contains(r.err, "shapespline: warning: knots")) << what << ": " << r.err;
        expectFiniteOutput(dir / "o" / file, what);
      }
    }
  }
  // Their derivatives (1/h ~ 1e310) are beyond fp64: exit 3 saying so, not "internal error".
  for (const auto& m : {c, g}) {
    const CliResult r = sample(m, dir / "d", "c.f64", "--device cpu --samples 5 --derivatives -q");
    expectRefused(r, 3, {"d1: exceeds the fp64 range of the output"}, dir / "d", m.filename().string() + " derivatives");
  }
  // Points and normals equal those of the 1e10-times wider knot vectors (up to rounding).
  for (const auto& [tiny, wide, opts, values] :
       {std::tuple{c, c1, std::string("--samples 5"), size_t{3}}, std::tuple{s, s1, std::string("--grid 4 --normals"), size_t{6}}}) {
    ASSERT_EQ(sample(tiny, dir / "t", "x.f64", opts + " --device cpu -q").rc, 0);
    ASSERT_EQ(sample(wide, dir / "w", "x.f64", opts + " --device cpu -q").rc, 0);
    const std::string a = readText(dir / "t" / "x.f64"), b = readText(dir / "w" / "x.f64");
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size() / 8; ++i)
      EXPECT_NEAR(readDouble(a, i), readDouble(b, i), 1e-9 * 8) << tiny.filename() << " value " << i % values;
  }
}

TEST(CliDerivedValues, EvalOfE310KnotIntervalsIsExit3BeyondFp64NotInternal) {
  // eval prints d1 and d2, which scale with 1/h and 1/h^2: beyond fp64 for h = 1e-310 and unit
  // points. Refused with exit 3 (a value beyond the output precision, as for fp32 files), nothing on
  // stdout; the point itself is no longer NaN.
  ScratchDir dir("derived_tiny_eval");
  writeText(dir / "c.json", R"({"kind": "curve", "construction": "bspline", "order": 4, "closed": false, "points": )" +
                                curvePoints(1.0) + R"(, "knots": [0, 0, 0, 0, 1e-310, 2e-310, 3e-310, 3e-310, 3e-310, 3e-310]})");
  writeText(dir / "at.json", R"({"samples": [{"u": 1.5e-310}]})");
  const CliResult r = runCli("eval c.json --at at.json -q", dir.path(), dir.path());
  EXPECT_EQ(r.rc, 3) << r.err;
  EXPECT_TRUE(contains(r.err, "shapespline: error: d1: exceeds the fp64 range")) << r.err;
  EXPECT_FALSE(contains(r.err, "internal error")) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  // With a net whose derivatives fit (points 1e-300 apart: d1 ~ 1e10, d2 = 0 for a line), it prints.
  writeText(dir / "line.json", R"({"kind": "curve", "construction": "bspline", "order": 2, "closed": false, "points": [[0, 0], [1e-300, 2e-300], [2e-300, 4e-300]], "knots": [0, 0, 1e-310, 2e-310, 2e-310]})");
  writeText(dir / "at2.json", R"({"samples": [{"u": 0.5e-310}, {"u": 1.5e-310}]})");
  const CliResult l = runCli("eval line.json --at at2.json -q", dir.path(), dir.path());
  ASSERT_EQ(l.rc, 0) << l.err;
  expectFiniteText(l.out, "eval line");
  const json j = json::parse(l.out);
  EXPECT_NEAR(j["samples"][0]["d1"][0].get<double>(), 1e10, 1e-3 * 1e10) << l.out;
  EXPECT_NEAR(j["samples"][1]["d1"][1].get<double>(), 2e10, 1e-3 * 2e10) << l.out;
  EXPECT_NEAR(j["samples"][0]["point"][0].get<double>(), 0.5e-300, 1e-3 * 1e-300) << l.out;
}

// ---- 4. α near 1e-310 ------------------------------------------------------------------------------

TEST(CliDerivedValues, AlphaWhoseVertexExceedsFp64IsRefusedNamingAlpha) {
  // V = P + ((1-α)/α)(P - node) is ~1e310 for α = 1e-310: every point of the spans at that vertex
  // was NaN ("internal error", exit 3). Such a model cannot be represented: exit 2 naming alpha[j].
  ScratchDir dir("derived_alpha_refused");
  const fs::path c = dir / "c.json", s = dir / "s.json";
  writeText(c, R"({"kind": "curve", "construction": "alpha_eb", "degree": 4, "lambda": 0, "alpha": [1, 1e-310, 1, 1, 1, 1], "points": )" +
                   curvePoints(1.0) + "}");
  writeText(s, R"({"kind": "surface", "construction": "alpha_eb", "degree": 4, "lambda": 0, "alpha": 1e-310, "points": )" +
                   surfacePoints(1.0) + "}");
  for (const char* dev : {"--device cpu", "--device vulkan"}) {
    for (const auto& file : kCurveFiles) {
      const CliResult r = sample(c, dir / "o", file, std::string(dev) + " --samples 4");
      expectRefused(r, 2, {"alpha[1]: ", "exceeds the fp64 range", "(got 1e-310)"}, dir / "o", std::string("curve ") + file);
    }
    for (const auto& file : kSurfaceFiles) {
      const CliResult r = sample(s, dir / "o", file, std::string(dev) + " --grid 3");
      expectRefused(r, 2, {"alpha[", "][", "exceeds the fp64 range"}, dir / "o", std::string("surface ") + file);
    }
  }
  writeText(dir / "at.json", R"({"samples": [{"span": 1, "t": 0.5}]})");
  const CliResult e = runCli("eval c.json --at at.json", dir.path(), dir.path());
  EXPECT_EQ(e.rc, 2) << e.err;
  EXPECT_TRUE(contains(e.err, "alpha[1]: ")) << e.err;
}

TEST(CliDerivedValues, TinyAlphaWritesOnEveryPathTheGpuCannotRepresentFallsBack) {
  // α = 1e-300 has a finite V in fp64 (and with one α everywhere the curve stays near the net, R13).
  // The fp32 kernels turned α into 0 (V = NaN, "internal error", exit 3): they now hand such models
  // to the CPU with a notice, or refuse with --require-device.
  ScratchDir dir("derived_alpha_small");
  const fs::path c = dir / "c.json";
  writeText(c, R"({"kind": "curve", "construction": "alpha_eb", "degree": 4, "lambda": 0, "alpha": 1e-300, "points": )" +
                   curvePoints(1.0) + "}");
  const CliResult cpu = sample(c, dir / "cpu", "c.f64", "--device cpu --precision float --samples 5 --derivatives -q");
  ASSERT_EQ(cpu.rc, 0) << cpu.err;
  expectFiniteOutput(dir / "cpu" / "c.f64", "cpu");
  for (const auto& file : kCurveFiles) {
    for (const char* dev : {"--device cpu", "--device vulkan"}) {
      const CliResult r = sample(c, dir / "o", file, std::string(dev) + " --samples 5");
      ASSERT_EQ(r.rc, 0) << file << " " << dev << ": " << r.err;
      EXPECT_TRUE(contains(r.err, "warning: alpha[")) << r.err;
      expectFiniteOutput(dir / "o" / file, "alpha 1e-300 " + file + " " + dev);
    }
  }
  writeText(dir / "at.json", R"({"samples": [{"span": 1, "t": 0.5}, {"span": 4, "t": 0.25}]})");
  for (const char* dev : {"--device cpu", "--device vulkan", "--device vulkan --precision float"}) {
    const CliResult e = runCli("eval c.json --at at.json -q " + std::string(dev), dir.path(), dir.path());
    ASSERT_EQ(e.rc, 0) << dev << ": " << e.err;
    EXPECT_GT(expectFiniteText(e.out, std::string("eval ") + dev), 10u) << e.out;
  }
  if (!vulkanDevice()) return;
  const CliResult f = sample(c, dir / "f", "c.f64", "--precision float --samples 5 --derivatives");
  ASSERT_EQ(f.rc, 0) << f.err;
  EXPECT_TRUE(contains(f.err, "notice: alpha = 1e-300 is below 1e-30")) << f.err;
  EXPECT_EQ(readText(dir / "f" / "c.f64"), readText(dir / "cpu" / "c.f64"));  // the CPU result
  const CliResult req = sample(c, dir / "r", "c.f32", "--precision float --samples 5 --require-device");
  expectRefused(req, 3, {"--require-device: alpha = 1e-300"}, dir / "r", "require-device fp32");
  // fp64 kernels represent it: no fallback, finite, the CPU result to 1e-9 of its extent.
  const CliResult d = sample(c, dir / "d", "c.f64", "--precision double --samples 5 --derivatives --require-device -q");
  ASSERT_EQ(d.rc, 0) << d.err;
  expectFiniteOutput(dir / "d" / "c.f64", "gpu fp64");
}

}  // namespace
}  // namespace shapespline::test
