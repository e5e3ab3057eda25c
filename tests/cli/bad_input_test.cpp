// The bad-input catalog: every bad model of tests/support/bad_models.h through `sample` and
// `eval`, plus the command-line cases (unwritable output, absurd sample counts, bad --shard,
// unknown extension, missing model). Each must exit with 2, name the field, and leave no file.
#include "cli_runner.h"
#include "support/bad_models.h"

#include <gtest/gtest.h>

namespace shapespline::test {
namespace {

class BadModelCli : public ::testing::TestWithParam<BadModel> {};

TEST_P(BadModelCli, SampleExitsTwoNamingTheFieldAndWritesNothing) {
  const BadModel& bad = GetParam();
  ScratchDir dir("bad_" + bad.name);
  writeText(dir / "model.json", bad.json_text);
  const CliResult r = runCli("sample " + quote((dir / "model.json").string()) + " -o " +
                                 quote((dir / "out.obj").string()) + " --device cpu",
                             dir.path());
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_NE(r.err.find("shapespline: error: " + bad.field), std::string::npos)
      << "field '" << bad.field << "' not named in: " << r.err;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"model.json"});
}

TEST_P(BadModelCli, EvalExitsTwo) {
  const BadModel& bad = GetParam();
  ScratchDir dir("bad_eval_" + bad.name);
  writeText(dir / "model.json", bad.json_text);
  writeText(dir / "at.json", R"({"samples": [{"span": 0, "t": 0.5}]})");
  const CliResult r = runCli("eval " + quote((dir / "model.json").string()) + " --at " + quote((dir / "at.json").string()) +
                                 " --device cpu",
                             dir.path());
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_NE(r.err.find(bad.field), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

INSTANTIATE_TEST_SUITE_P(Catalog, BadModelCli, ::testing::ValuesIn(badModelCatalog()),
                         [](const auto& info) { return info.param.name; });

TEST(BadModelCatalog, HasAtLeastThirtyEntries) { EXPECT_GE(badModelCatalog().size(), 30u); }

struct BadArgs {
  std::string name;
  std::string args;   // {M} = a valid curve model, {S} = a valid surface model, {D} = scratch folder
  std::string field;  // must appear in the error message
  int rc = 2;
};

std::string expand(std::string s, const ScratchDir& dir) {
  auto rep = [&](const std::string& key, const std::string& value) {
    for (size_t p; (p = s.find(key)) != std::string::npos;) s.replace(p, key.size(), value);
  };
  rep("{M}", quote(examplesDir() + "/open_aeb.json"));
  rep("{G}", quote(examplesDir() + "/gb_curve.json"));
  rep("{B}", quote(examplesDir() + "/clamped_bspline.json"));
  rep("{S}", quote(examplesDir() + "/surface_aeb.json"));
  rep("{D}", dir.path().string());
  return s;
}

class BadArgsCli : public ::testing::TestWithParam<BadArgs> {};

TEST_P(BadArgsCli, ExitsWithCodeNamingTheFieldAndWritesNothing) {
  const BadArgs& c = GetParam();
  ScratchDir dir("args_" + c.name);
  writeText(dir / "at.json", R"({"samples": [{"span": 99, "t": 0.5}]})");
  writeText(dir / "bad_at.json", R"({"samples": [{"span": 0, "t": 0.5)");
  const auto before = dir.entries();
  const CliResult r = runCli(expand(c.args, dir), dir.path());
  EXPECT_EQ(r.rc, c.rc) << r.err;
  EXPECT_NE(r.err.find(c.field), std::string::npos) << "'" << c.field << "' not in: " << r.err;
  EXPECT_EQ(dir.entries().size(), before.size()) << "a file was left behind";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadArgsCli,
    ::testing::Values(
        BadArgs{"unwritable_folder", "sample {M} -o /nonexistent_dir_xyz/out.obj --device cpu", "-o"},
        BadArgs{"output_is_directory", "sample {M} -o {D} --device cpu", "-o"},
        BadArgs{"unknown_extension", "sample {M} -o {D}/out.xyz --device cpu", "-o"},
        BadArgs{"missing_model", "sample {D}/nope.json -o {D}/out.obj --device cpu", "MODEL"},
        BadArgs{"samples_too_many", "sample {M} -o {D}/out.obj --samples 100000 --device cpu", "--samples"},
        BadArgs{"samples_one", "sample {M} -o {D}/out.obj --samples 1 --device cpu", "--samples"},
        BadArgs{"samples_negative", "sample {M} -o {D}/out.obj --samples -5 --device cpu", "--samples"},
        BadArgs{"grid_too_big", "sample {S} -o {D}/out.obj --grid 65537x2 --device cpu", "--grid"},
        BadArgs{"grid_zero", "sample {S} -o {D}/out.obj --grid 0 --device cpu", "--grid"},
        BadArgs{"grid_garbage", "sample {S} -o {D}/out.obj --grid 4xz --device cpu", "--grid"},
        BadArgs{"grid_on_curve", "sample {M} -o {D}/out.obj --grid 4x4 --device cpu", "--grid"},
        BadArgs{"ply_too_many_vertices", "sample {S} -o {D}/out.ply --grid 20000x20000 --device cpu", "--grid"},
        BadArgs{"svg_surface", "sample {S} -o {D}/out.svg --device cpu", "-o"},
        // STL is written for part meshes only.
        BadArgs{"stl_surface", "sample {S} -o {D}/out.stl --device cpu", "-o: '"},
        BadArgs{"stl_curve", "sample {M} -o {D}/out.stl --device cpu", "STL is written for part meshes only"},
        BadArgs{"stl_shard", "sample {S} -o {D}/out.stl --shard 1/2 --device cpu", "STL is written for part meshes only"},
        BadArgs{"stl_merge", "merge -o {D}/out.stl {D}/a.stl {D}/b.stl", "STL is written for part meshes only"},
        BadArgs{"normals_on_curve", "sample {M} -o {D}/out.csv --normals --device cpu", "--normals"},
        BadArgs{"shard_zero", "sample {M} -o {D}/out.obj --shard 0/3 --device cpu", "--shard"},
        BadArgs{"shard_beyond", "sample {M} -o {D}/out.obj --shard 4/3 --device cpu", "--shard"},
        BadArgs{"shard_garbage", "sample {M} -o {D}/out.obj --shard x --device cpu", "--shard"},
        BadArgs{"bad_device", "sample {M} -o {D}/out.obj --device tpu", "--device"},
        BadArgs{"bad_precision", "sample {M} -o {D}/out.obj --precision half", "--precision"},
        BadArgs{"eval_span_out_of_range", "eval {M} --at {D}/at.json --device cpu", "samples[0].span"},
        BadArgs{"eval_malformed_at", "eval {M} --at {D}/bad_at.json --device cpu", "--at"},
        BadArgs{"eval_missing_at", "eval {M} --at {D}/none.json --device cpu", "--at"},
        BadArgs{"basis_unknown_family", "basis --family foo", "--family"},
        BadArgs{"basis_lambda_out_of_range", "basis --family xuwang --degree 4 --lambda 5", "--lambda"},
        BadArgs{"basis_missing_order", "basis --family ubp", "--order"},
        BadArgs{"gbfit_not_gb", "gb-fit {M} --span 1 --through 1,2", "MODEL"},
        BadArgs{"extend_not_bspline", "extend {M} --to 9,9 -o {D}/ext.json", "MODEL"},
        BadArgs{"extend_bad_point", "extend {B} --to 9,x -o {D}/ext.json", "--to"},
        BadArgs{"extend_u_count", "extend {B} --to 9,4 --to 10,2 --u 1.5 -o {D}/ext.json", "--u"},
        BadArgs{"gbfit_unreachable", "gb-fit {G} --span 2 --through 100,100 -o {D}/fit.json", "--through"},
        BadArgs{"unknown_option", "sample {M} -o {D}/out.obj --frobnicate", "frobnicate"}),
    [](const auto& info) { return info.param.name; });

TEST(CliExitCodes, HelpDocumentsExitCodes) {
  ScratchDir dir("help");
  const CliResult r = runCli("--help", dir.path());
  EXPECT_EQ(r.rc, 0);
  EXPECT_NE(r.out.find("Exit codes: 0 success; 1 some of several models failed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 bad input"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("3 device or runtime error"), std::string::npos);
  EXPECT_EQ(runCli("", dir.path()).rc, 2);  // a subcommand is required
}

}  // namespace
}  // namespace shapespline::test
