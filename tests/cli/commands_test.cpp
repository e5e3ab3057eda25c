// Every other subcommand end to end on the example models: eval, basis (+ SVG), gb-fit, extend
// (curve and surface), info, demo.
#include "cli_runner.h"
#include <shapespline/core/curve.h>
#include <shapespline/core/gb_tools.h>
#include <shapespline/core/span_basis.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/model_json.h>
#include "support/golden.h"

#include <gtest/gtest.h>

#include <cmath>

namespace shapespline::test {
namespace {

TEST(CliEval, CurveFieldsAtSeventeenDigits) {
  ScratchDir dir("eval_curve");
  writeText(dir / "at.json", R"({"samples": [{"span": 0, "t": 0.1}, {"span": 4, "t": 1}]})");
  const CliResult r = runCli("eval " + quote(examplesDir() + "/open_aeb.json") + " --at " +
                                 quote((dir / "at.json").string()) + " --device cpu",
                             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  const json out = json::parse(r.out);
  ASSERT_EQ(out["samples"].size(), 2u);
  const Curve curve = Curve::create(std::get<CurveModel>(io::loadModelFile(examplesDir() + "/open_aeb.json")));
  const CurvePoint cp = curve.evaluate(0, 0.1);
  const json& s = out["samples"][0];
  EXPECT_EQ(s["span"], 0);
  EXPECT_EQ(s["point"][0].get<double>(), cp.point.x);  // 17 digits round-trip exactly
  EXPECT_EQ(s["d1"][1].get<double>(), cp.d1.y);
  EXPECT_EQ(s["d2"][0].get<double>(), cp.d2.x);
  EXPECT_EQ(s["point"].size(), 2u);  // a 2-D curve prints 2 coordinates
}

TEST(CliBasis, CsvPartitionOfUnityAndSvg) {
  ScratchDir dir("basis");
  const CliResult r = runCli("basis --family ubp --order 5 --lambda 0.5 --samples 11 --svg " +
                                 quote((dir / "b.svg").string()),
                             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("t,B0,B1,B2,B3,B4,d1_B0", 0), 0u) << line;
  const SpanBasis basis = ubpSpanBasis(5, 0.5);
  int rows = 0;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::istringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 1u + 3 * 5);
    double b[kMaxBasisCount], d1[kMaxBasisCount], d2[kMaxBasisCount];
    evalSpanBasis(basis, v[0], b, d1, d2);
    double sum = 0;
    for (int k = 0; k < 5; ++k) {
      EXPECT_EQ(v[1 + k], b[k]);
      EXPECT_EQ(v[6 + k], d1[k]);
      EXPECT_EQ(v[11 + k], d2[k]);
      sum += v[1 + k];
    }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    ++rows;
  }
  EXPECT_EQ(rows, 11);
  const std::string svg = readText(dir / "b.svg");
  EXPECT_NE(svg.find("<polyline"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  for (const char* family : {"--family xuwang --degree 6 --lambda -3", "--family gb --lambda 2",
                             "--family gubp --order 5 --mu 0.25,0.5,0.25", "--family bspline --order 4",
                             "--family singular_blend"}) {
    EXPECT_EQ(runCli(std::string("basis ") + family, dir.path()).rc, 0) << family;
  }
}

TEST(CliGbFit, GoldenCasesPrintSolutionsAndWriteModel) {
  ScratchDir dir("gbfit");
  int cases = 0;
  for (const auto& file : loadGoldenFiles()) {
    for (const auto& c : file.doc["cases"]) {
      if (c["family"] != "gb_modify") continue;
      ++cases;
      const std::string id = c["id"];
      writeText(dir / "model.json", c["model"].dump());
      const json& in = c["inputs"];
      char through[128];
      std::snprintf(through, sizeof through, "%.17g,%.17g", in["target"][0].get<double>(), in["target"][1].get<double>());
      const int span = in["span"].get<int>();
      const CliResult r = runCli("gb-fit " + quote((dir / "model.json").string()) + " --span " + std::to_string(span) +
                                     " --through " + through + " -o " + quote((dir / "fit.json").string()) + " --svg " +
                                     quote((dir / "fit.svg").string()),
                                 dir.path());
      ASSERT_EQ(r.rc, 0) << id << ": " << r.err;
      const json out = json::parse(r.out);
      const json& tol = c["tolerance"];
      auto tolFor = [&](const char* field) {
        return tol.contains("fields") && tol["fields"].contains(field) ? number(tol["fields"][field]["fp64"])
                                                                       : number(tol["fp64"]);
      };
      EXPECT_NEAR(out["t0"].get<double>(), number(c["expected"]["t0"]), tolFor("t0")) << id;
      EXPECT_NEAR(out["lambda0"].get<double>(), number(c["expected"]["lambda0"]), tolFor("lambda0")) << id;
      EXPECT_EQ(out["all_solutions"].size(), c["expected"]["all_solutions"].size()) << id;
      const CurveModel fit = std::get<CurveModel>(io::loadModelFile(dir / "fit.json"));
      EXPECT_EQ(fit.family.lambda, out["lambda0"].get<double>()) << id;
      // The modified curve passes through the target at t0.
      const glm::dvec3 p = Curve::create(fit).evaluate(span, out["t0"].get<double>()).point;
      EXPECT_NEAR(p.x, in["target"][0].get<double>(), 1e-7) << id;
      EXPECT_NEAR(p.y, in["target"][1].get<double>(), 1e-7) << id;
      EXPECT_TRUE(std::filesystem::exists(dir / "fit.svg"));
    }
  }
  EXPECT_GT(cases, 0);
}

TEST(CliExtend, CurvePassesThroughTargets) {
  ScratchDir dir("extend_curve");
  const CliResult r = runCli("extend " + quote(examplesDir() + "/clamped_bspline.json") +
                                 " --to 10,4 --to 12,2 -o " + quote((dir / "ext.json").string()) + " --svg " +
                                 quote((dir / "ext.svg").string()),
                             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  const CurveModel ext = std::get<CurveModel>(io::loadModelFile(dir / "ext.json"));
  EXPECT_EQ(ext.points.size(), 8u);
  const Curve c = Curve::create(ext);
  const auto [u0, u1] = c.parameterRange();
  const glm::dvec3 end = c.evaluateAt(u1).point;
  EXPECT_NEAR(end.x, 12, 1e-9);
  EXPECT_NEAR(end.y, 2, 1e-9);
  EXPECT_TRUE(std::filesystem::exists(dir / "ext.svg"));
}

// -q is a flag of every subcommand, so that a script may pass it to each alike; where a command
// prints a summary or a listing beside its output files, -q silences it.
TEST(CliQuiet, EverySubcommandTakesItAndItSilencesSummaries) {
  ScratchDir dir("quiet");
  for (const char* command : {"sample", "eval", "basis", "gb-fit", "extend", "import", "info", "demo", "merge", "render",
                              "view"}) {
    const CliResult help = runCli(std::string(command) + " --help", dir.path());
    EXPECT_EQ(help.rc, 0) << command << ": " << help.err;
    EXPECT_NE(help.out.find("-q,--quiet"), std::string::npos) << command << " has no -q:\n" << help.out;
  }
  const CliResult extend = runCli("extend -q " + quote(examplesDir() + "/clamped_bspline.json") +
                                      " --to 10,4 --to 12,2 -o " + quote((dir / "ext.json").string()),
                                  dir.path());
  ASSERT_EQ(extend.rc, 0) << extend.err;
  EXPECT_EQ(extend.out, "");
  EXPECT_TRUE(std::filesystem::exists(dir / "ext.json"));
  const CliResult demo = runCli("demo -q --dir " + quote((dir / "demo").string()), dir.path());
  ASSERT_EQ(demo.rc, 0) << demo.err;
  EXPECT_EQ(demo.out, "");
  EXPECT_EQ(demo.err, "");
  EXPECT_TRUE(std::filesystem::exists(dir / "demo" / "butterfly_aeb.json"));
}

TEST(CliExtend, SurfaceWithTargetCurve) {
  ScratchDir dir("extend_surface");
  const CliResult r = runCli("extend " + quote(examplesDir() + "/bspline_surface.json") + " --to-curve " +
                                 quote(examplesDir() + "/bspline_surface_target.json") + " -o " +
                                 quote((dir / "ext.json").string()),
                             dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  const SurfaceModel ext = std::get<SurfaceModel>(io::loadModelFile(dir / "ext.json"));
  EXPECT_EQ(ext.rows, 5);
  const Surface s = Surface::create(ext);
  const auto [u0, u1] = s.parameterRangeU();
  const glm::dvec3 p = s.evaluateAt(u1, 0.0).point;  // the surface at u_m equals the target curve
  EXPECT_NEAR(p.x, 4.5, 1e-9);
  EXPECT_NEAR(p.z, 0.0, 1e-9);
}

TEST(CliInfo, ListsDevicesOrSaysNone) {
  ScratchDir dir("info");
  const CliResult r = runCli("info", dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.out.find("Vulkan devices:"), std::string::npos);
  EXPECT_NE(r.out.find("selected:"), std::string::npos);
}

TEST(CliDemo, WritesModelsObjAndSvg) {
  ScratchDir dir("demo");
  const CliResult r = runCli("demo", dir.path(), dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  const auto demo = dir / "shapespline-demo";
  for (const char* f : {"butterfly_aeb.json", "butterfly_aeb.obj", "butterfly_aeb.svg", "open_aeb_alpha_0.25.obj",
                        "open_aeb_alpha_1.svg", "surface_aeb_lambda_-2.obj", "surface_aeb_lambda_0.obj",
                        "surface_aeb_lambda_1.json"}) {
    EXPECT_TRUE(std::filesystem::exists(demo / f)) << f;
    EXPECT_NE(r.out.find(f), std::string::npos) << f;
  }
  // The demo's butterfly is the example model.
  EXPECT_EQ(io::toJson(io::loadModelFile(demo / "butterfly_aeb.json")),
            io::toJson(io::loadModelFile(examplesDir() + "/butterfly_aeb.json")));
}

}  // namespace
}  // namespace shapespline::test
