// Issue 31 (many models, one process): `sample A.json B.json ... -o 'out/{stem}.EXT'` and
// `sample FOLDER -o ...` write, for every model, exactly the files (data and sidecar bytes) that
// `sample MODEL -o OUT` writes alone, on the CPU and on Vulkan (one session: one device, pipelines
// compiled once); a bad model is reported by name and the others are still written (exit 1), or
// --fail-fast stops at it with its own exit code; several models need {stem} and no --shard.
#include "cli_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// Three small models of different constructions (and so different pipelines), one of them a curve.
void writeModels(const fs::path& dir) {
  fs::create_directories(dir);
  writeText(dir / "a.json", R"({"kind": "surface", "construction": "extended_bspline", "degree": 4,
    "points": [[[0,0,0],[0,1,0.5],[0,2,0],[0,3,1]], [[1,0,0.2],[1,1,0],[1,2,0.4],[1,3,0]],
               [[2,0,0],[2,1,1],[2,2,0],[2,3,0.3]], [[3,0,0.5],[3,1,0],[3,2,0.2],[3,3,0]]]})");
  writeText(dir / "b.json", R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, "alpha": 0.5,
    "points": [[[0,0,0],[0,1,0.5],[0,2,0]], [[1,0,0.2],[1,1,0],[1,2,0.4]], [[2,0,0],[2,1,1],[2,2,0]]]})");
  writeText(dir / "c.json", R"({"kind": "curve", "construction": "bspline", "order": 3,
    "points": [[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0]], "weights": [1, 0.7071067811865476, 1, 0.7071067811865476, 1],
    "knots": [0, 0, 0, 0.5, 0.5, 1, 1, 1]})");
}

class BatchSample : public ::testing::Test {
 protected:
  void SetUp() override {
    writeModels(dir_ / "models");
    fs::create_directories(dir_ / "batch");
    fs::create_directories(dir_ / "single");
  }
  CliResult run(const std::string& args) { return runCli(args + " -q", dir_.path()); }
  std::string model(const std::string& name) const { return quote((dir_ / "models" / name).string()); }
  ScratchDir dir_{"batch_sample"};
};

TEST_F(BatchSample, EveryModelGetsTheFilesItGetsAlone) {
  for (const char* device : {"cpu", "vulkan"}) {
    SCOPED_TRACE(device);
    const std::string opts = std::string(" --samples 7 --device ") + device + " --precision float";
    const CliResult b = run("sample " + model("a.json") + " " + model("b.json") + " " + model("c.json") + " -o " +
                            quote((dir_ / "batch" / "{stem}.npy").string()) + opts);
    ASSERT_EQ(b.rc, 0) << b.err;
    for (const char* stem : {"a", "b", "c"}) {
      const CliResult s = run("sample " + model(std::string(stem) + ".json") + " -o " +
                              quote((dir_ / "single" / (std::string(stem) + ".npy")).string()) + opts);
      ASSERT_EQ(s.rc, 0) << s.err;
      for (const char* ext : {".npy", ".npy.json"}) {
        const std::string batch = readText(dir_ / "batch" / (std::string(stem) + ext));
        const std::string single = readText(dir_ / "single" / (std::string(stem) + ext));
        EXPECT_FALSE(batch.empty()) << stem << ext;
        EXPECT_TRUE(batch == single) << stem << ext << " differs from the file sampled alone";
      }
    }
  }
  // A folder is its .json files in name order.
  const CliResult f = run("sample " + quote((dir_ / "models").string()) + " -o " +
                          quote((dir_ / "batch" / "{stem}.ply").string()) + " --samples 5 --device cpu");
  ASSERT_EQ(f.rc, 0) << f.err;
  for (const char* stem : {"a", "b", "c"}) EXPECT_TRUE(fs::exists(dir_ / "batch" / (std::string(stem) + ".ply"))) << stem;
}

TEST_F(BatchSample, ABadModelIsReportedAndTheOthersAreWritten) {
  writeText(dir_ / "models" / "bad.json", R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, "alpha": 1.5,
    "points": [[[0,0,0],[0,1,0]], [[1,0,0],[1,1,0]]]})");
  const std::string out = quote((dir_ / "batch" / "{stem}.f32").string());
  const CliResult r = run("sample " + model("a.json") + " " + model("bad.json") + " " + model("b.json") + " -o " + out +
                          " --device cpu");
  EXPECT_EQ(r.rc, 1) << r.err;
  EXPECT_NE(r.err.find("bad.json: alpha"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1 of 3 models failed"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "batch" / "a.f32"));
  EXPECT_TRUE(fs::exists(dir_ / "batch" / "b.f32"));
  EXPECT_FALSE(fs::exists(dir_ / "batch" / "bad.f32"));
  EXPECT_FALSE(fs::exists(dir_ / "batch" / "bad.f32.json"));

  fs::remove_all(dir_ / "batch");
  fs::create_directories(dir_ / "batch");
  const CliResult ff = run("sample " + model("a.json") + " " + model("bad.json") + " " + model("b.json") + " -o " + out +
                           " --device cpu --fail-fast");
  EXPECT_EQ(ff.rc, 2) << ff.err;  // the bad model's own code
  EXPECT_NE(ff.err.find("alpha"), std::string::npos) << ff.err;
  EXPECT_TRUE(fs::exists(dir_ / "batch" / "a.f32"));
  EXPECT_FALSE(fs::exists(dir_ / "batch" / "b.f32")) << "--fail-fast went on after the failure";
}

// Each model's outputs are committed while the next one samples; its line (what it wrote, or why
// it failed) still comes in model order, and a commit that fails is that model's failure.
TEST_F(BatchSample, LinesComeInModelOrderAndAFailedCommitIsThatModelsFailure) {
  writeText(dir_ / "models" / "bad.json", R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, "alpha": 1.5,
    "points": [[[0,0,0],[0,1,0]], [[1,0,0],[1,1,0]]]})");
  const std::string models = model("a.json") + " " + model("bad.json") + " " + model("b.json") + " " + model("c.json");
  const std::string out = " -o " + quote((dir_ / "batch" / "{stem}.npy").string()) + " --samples 5 --device cpu";
  const CliResult r = runCli("sample " + models + out, dir_.path());
  EXPECT_EQ(r.rc, 1) << r.err;
  const size_t a = r.err.find("a.npy"), bad = r.err.find("bad.json: alpha"), b = r.err.find("b.npy"),
               c = r.err.find("c.npy");
  ASSERT_TRUE(a != std::string::npos && bad != std::string::npos && b != std::string::npos && c != std::string::npos)
      << r.err;
  EXPECT_TRUE(a < bad && bad < b && b < c) << r.err;

  // The second rename of every model's set (its sidecar) fails: every model fails, in order, each
  // with nothing written.
  fs::remove_all(dir_ / "batch");
  fs::create_directories(dir_ / "batch");
  const CliResult f = runShell("SHAPESPLINE_IO_FAULT=rename:2 " + quote(SHAPESPLINE_CLI) + " sample " +
                                   model("a.json") + " " + model("b.json") + " " + model("c.json") + out,
                               dir_.path());
  EXPECT_EQ(f.rc, 1) << f.err;
  EXPECT_NE(f.err.find("3 of 3 models failed"), std::string::npos) << f.err;
  const size_t fa = f.err.find("a.json: "), fb = f.err.find("b.json: "), fc = f.err.find("c.json: ");
  ASSERT_TRUE(fa != std::string::npos && fb != std::string::npos && fc != std::string::npos) << f.err;
  EXPECT_TRUE(fa < fb && fb < fc) << f.err;
  EXPECT_NE(f.err.find("rename"), std::string::npos) << f.err;
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir_ / "batch")) left.push_back(e.path().filename().string());
  EXPECT_TRUE(left.empty()) << left.size() << " files left, first " << left.front();
}

TEST_F(BatchSample, SeveralModelsNeedStemAndNoShard) {
  const CliResult noStem = run("sample " + model("a.json") + " " + model("b.json") + " -o " +
                               quote((dir_ / "batch" / "x.f32").string()) + " --device cpu");
  EXPECT_EQ(noStem.rc, 2);
  EXPECT_NE(noStem.err.find("{stem}"), std::string::npos) << noStem.err;
  const CliResult shard = run("sample " + model("a.json") + " " + model("b.json") + " -o " +
                              quote((dir_ / "batch" / "{stem}.f32").string()) + " --shard 1/2 --device cpu");
  EXPECT_EQ(shard.rc, 2);
  EXPECT_NE(shard.err.find("--shard"), std::string::npos) << shard.err;
  fs::create_directories(dir_ / "other");
  fs::copy_file(dir_ / "models" / "a.json", dir_ / "other" / "a.json");
  const CliResult same = run("sample " + model("a.json") + " " + quote((dir_ / "other" / "a.json").string()) + " -o " +
                             quote((dir_ / "batch" / "{stem}.f32").string()) + " --device cpu");
  EXPECT_EQ(same.rc, 2);
  EXPECT_NE(same.err.find("same file stem"), std::string::npos) << same.err;
  auto entries = std::vector<fs::path>(fs::directory_iterator(dir_ / "batch"), fs::directory_iterator());
  EXPECT_TRUE(entries.empty()) << "a refused batch wrote " << entries.size() << " files";
}

}  // namespace
}  // namespace shapespline::test
