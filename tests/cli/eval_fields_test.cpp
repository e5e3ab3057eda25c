// `eval --fields`: only the fields asked for, each with exactly the text the full `eval` prints for
// it (the lean list kernel gives the same bits on the CPU), for surfaces and curves, local and
// global samples; an unknown field exits 2 naming --fields with nothing printed.
#include "cli_runner.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace shapespline::test {
namespace {

using nlohmann::json;

// The printed samples (equal doubles print as equal shortest texts).
json printedSamples(const std::string& out) {
  return json::parse(out, nullptr, true, false).at("samples");
}

void expectSubsetOfFull(const std::string& model, const std::string& at, const std::string& fields,
                        const std::vector<std::string>& printed, const std::vector<std::string>& absent) {
  SCOPED_TRACE(model + " --fields " + fields);
  ScratchDir dir("eval_fields");
  writeText(dir / "at.json", at);
  const std::string base = "eval " + quote(exampleModel(model)) + " --at " + quote((dir / "at.json").string()) +
                           " --device cpu -q";
  const CliResult full = runCli(base, dir.path());
  ASSERT_EQ(full.rc, 0) << full.err;
  const CliResult lean = runCli(base + " --fields " + fields, dir.path());
  ASSERT_EQ(lean.rc, 0) << lean.err;
  const json f = printedSamples(full.out), l = printedSamples(lean.out);
  ASSERT_EQ(f.size(), l.size());
  for (size_t i = 0; i < f.size(); ++i) {
    for (const std::string& key : printed) {
      ASSERT_TRUE(l[i].contains(key)) << "sample " << i << " lacks " << key << ": " << lean.out;
      EXPECT_EQ(l[i].at(key).dump(), f[i].at(key).dump()) << "sample " << i << ", " << key;
    }
    for (const std::string& key : absent) EXPECT_FALSE(l[i].contains(key)) << "sample " << i << " has " << key;
  }
}

TEST(EvalFields, SurfaceFieldsAreTheFullOutputsOwn) {
  const std::string at = R"({"samples":[{"patch":[2,2],"uv":[0.25,0.5]},{"patch":[2,2],"uv":[1,0]},)"
                         R"({"patch":[4,4],"uv":[0,0.75]},{"patch":[4,4],"uv":[0.5,0.75]}]})";
  expectSubsetOfFull("nurbs_torus.json", at, "point,du,dv", {"patch", "uv", "UV", "point", "du", "dv"},
                     {"duu", "duv", "dvv", "normal", "render_normal"});
  expectSubsetOfFull("nurbs_torus.json", at, "point", {"patch", "uv", "UV", "point"}, {"du", "dv", "normal"});
  expectSubsetOfFull("nurbs_torus.json", at, "dv,normal", {"point", "dv", "normal"}, {"du", "duu"});
  const std::string aeb = R"({"samples":[{"patch":[1,2],"uv":[0.3,0.7]},{"patch":[0,0],"uv":[0,0]}]})";
  expectSubsetOfFull("surface_aeb.json", aeb, "du", {"point", "du"}, {"dv", "duu", "normal"});
}

TEST(EvalFields, CurveFieldsAreTheFullOutputsOwn) {
  const std::string at = R"({"samples":[{"u":0},{"u":0.3},{"u":0.5},{"u":1}]})";
  expectSubsetOfFull("clamped_bspline.json", at, "d1", {"u", "point", "d1"}, {"d2"});
  expectSubsetOfFull("clamped_bspline.json", at, "point", {"u", "point"}, {"d1", "d2"});
}

TEST(EvalFields, AnUnknownFieldIsRefused) {
  ScratchDir dir("eval_fields_bad");
  writeText(dir / "at.json", R"({"samples":[{"patch":[2,2],"uv":[0.25,0.5]}]})");
  const CliResult r = runCli("eval " + quote(exampleModel("nurbs_torus.json")) + " --at " +
                                 quote((dir / "at.json").string()) + " --device cpu --fields point,d1",
                             dir.path());
  EXPECT_EQ(r.rc, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find("--fields"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'d1' is not one"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace shapespline::test
