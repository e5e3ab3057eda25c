// Issue 16, requirement 2 at the command line: `sample --shard auto` takes K/N from a Slurm job
// array (SLURM_ARRAY_TASK_ID with _MIN/_MAX or _COUNT, _STEP 1) or a Kubernetes Indexed Job
// (JOB_COMPLETION_INDEX with --shard-count or SHAPESPLINE_SHARD_COUNT), and refuses every
// inconsistent or malformed value with exit 2 naming the variable, its value and the rule, writing
// nothing; `-o` takes a shard pattern ({shard}, {count}, {shard:05d}); a malformed one names -o.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

const char* const kShardVars[] = {"SLURM_ARRAY_TASK_ID",    "SLURM_ARRAY_TASK_MIN",  "SLURM_ARRAY_TASK_MAX",
                                  "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_STEP", "JOB_COMPLETION_INDEX",
                                  "SHAPESPLINE_SHARD_COUNT"};

using Env = std::map<std::string, std::string>;

// `shapespline <args>` in `dir` with every scheduler variable unset but those of `env`.
CliResult runWithEnv(const ScratchDir& dir, const Env& env, const std::string& args) {
  std::string cmd = "cd " + quote(dir.path().string()) + " && env";
  for (const char* v : kShardVars) cmd += std::string(" -u ") + v;
  for (const auto& [k, v] : env) cmd += " " + k + "=" + quote(v);
  const auto out = dir / "_stdout.txt", err = dir / "_stderr.txt";
  cmd += " " + quote(SHAPESPLINE_CLI) + " " + args + " >" + quote(out.string()) + " 2>" + quote(err.string());
  return runCaptured(cmd, out, err);
}

std::string butterfly() { return quote(examplesDir() + "/butterfly_aeb.json"); }

// `sample --shard auto -o out-{shard:02d}-of-{count:02d}.f64`: returns the sidecar's shard K/N.
std::string autoShard(const ScratchDir& dir, const Env& env, const std::string& extra = "") {
  const CliResult r = runWithEnv(dir, env,
                                 "sample " + butterfly() +
                                     " -o 'out-{shard:02d}-of-{count:02d}.f64' --samples 3 --shard auto --device cpu -q " +
                                     extra);
  EXPECT_EQ(r.rc, 0) << r.err;
  for (const auto& name : entries(dir.path())) {
    if (name.size() > 9 && name.ends_with(".f64.json") && !name.ends_with(".shard.json")) {
      const json side = json::parse(readText(dir / name));
      const std::string kn = std::to_string(side["shard"]["index"].get<int>()) + "/" +
                             std::to_string(side["shard"]["count"].get<int>());
      char expected[64];
      std::snprintf(expected, sizeof expected, "out-%02d-of-%02d.f64.json", side["shard"]["index"].get<int>(),
                    side["shard"]["count"].get<int>());
      EXPECT_EQ(name, expected) << "the pattern expands to the shard's K and N";
      for (const auto& n : entries(dir.path())) fs::remove(dir / n);
      return kn;
    }
  }
  return "(no output)";
}

// A refused `--shard auto`: exit 2, "shapespline: error: FIELD: ..." naming `parts`, nothing written.
void expectRefused(const ScratchDir& dir, const Env& env, const std::string& field,
                   const std::vector<std::string>& parts, const std::string& extra = "") {
  const CliResult r = runWithEnv(dir, env,
                                 "sample " + butterfly() + " -o 'out-{shard}.f64' --samples 3 --shard auto --device cpu " +
                                     extra);
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "shapespline: error: " + field + ": ")) << r.err;
  for (const auto& p : parts) EXPECT_TRUE(contains(r.err, p)) << "expected '" << p << "' in: " << r.err;
  EXPECT_TRUE(entries(dir.path()).empty()) << "a refused job writes nothing";
}

TEST(CliShardAuto, SlurmArrayGivesKOfN) {
  ScratchDir dir("shard_auto_slurm");
  // sbatch --array=5-8: task 7 is shard 3 of 4.
  EXPECT_EQ(autoShard(dir, {{"SLURM_ARRAY_TASK_ID", "7"}, {"SLURM_ARRAY_TASK_MIN", "5"}, {"SLURM_ARRAY_TASK_MAX", "8"}}),
            "3/4");
  // Everything Slurm sets for --array=1-4 (step 1, count 4).
  EXPECT_EQ(autoShard(dir, {{"SLURM_ARRAY_TASK_ID", "1"},
                            {"SLURM_ARRAY_TASK_MIN", "1"},
                            {"SLURM_ARRAY_TASK_MAX", "4"},
                            {"SLURM_ARRAY_TASK_COUNT", "4"},
                            {"SLURM_ARRAY_TASK_STEP", "1"}}),
            "1/4");
  // 0-based arrays: --array=0-2, the last task.
  EXPECT_EQ(autoShard(dir, {{"SLURM_ARRAY_TASK_ID", "2"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_MAX", "2"}}),
            "3/3");
  // MAX from MIN and COUNT, MIN from MAX and COUNT.
  EXPECT_EQ(autoShard(dir, {{"SLURM_ARRAY_TASK_ID", "2"}, {"SLURM_ARRAY_TASK_MIN", "1"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}),
            "2/4");
  EXPECT_EQ(autoShard(dir, {{"SLURM_ARRAY_TASK_ID", "10"}, {"SLURM_ARRAY_TASK_MAX", "11"}, {"SLURM_ARRAY_TASK_COUNT", "2"}}),
            "1/2");
  // A single-task array is the whole job as shard 1/1.
  EXPECT_EQ(autoShard(dir, {{"SLURM_ARRAY_TASK_ID", "3"}, {"SLURM_ARRAY_TASK_MIN", "3"}, {"SLURM_ARRAY_TASK_MAX", "3"}}),
            "1/1");
  // A count that agrees with the array is accepted.
  EXPECT_EQ(autoShard(dir,
                      {{"SLURM_ARRAY_TASK_ID", "2"},
                       {"SLURM_ARRAY_TASK_MIN", "1"},
                       {"SLURM_ARRAY_TASK_MAX", "2"},
                       {"SHAPESPLINE_SHARD_COUNT", "2"}},
                      "--shard-count 2"),
            "2/2");
}

TEST(CliShardAuto, KubernetesIndexedJobGivesKOfN) {
  ScratchDir dir("shard_auto_k8s");
  EXPECT_EQ(autoShard(dir, {{"JOB_COMPLETION_INDEX", "0"}}, "--shard-count 4"), "1/4");
  EXPECT_EQ(autoShard(dir, {{"JOB_COMPLETION_INDEX", "3"}, {"SHAPESPLINE_SHARD_COUNT", "4"}}), "4/4");
  EXPECT_EQ(autoShard(dir, {{"JOB_COMPLETION_INDEX", "1"}, {"SHAPESPLINE_SHARD_COUNT", "3"}}, "--shard-count 3"), "2/3");
}

TEST(CliShardAuto, BadSlurmValuesAreRefusedNamingTheVariable) {
  ScratchDir dir("shard_auto_slurm_bad");
  const Env ok{{"SLURM_ARRAY_TASK_ID", "2"}, {"SLURM_ARRAY_TASK_MIN", "1"}, {"SLURM_ARRAY_TASK_MAX", "4"}};
  auto with = [&](const std::string& k, const std::string& v) {
    Env e = ok;
    e[k] = v;
    return e;
  };
  auto without = [&](const std::string& k) {
    Env e = ok;
    e.erase(k);
    return e;
  };
  // Malformed numbers, in every variable.
  for (const char* var : {"SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_MIN", "SLURM_ARRAY_TASK_MAX",
                          "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_STEP"}) {
    SCOPED_TRACE(var);
    for (const std::string bad : {"x", "-1", "+2", " 2", "2.0", "12345678901"}) {
      SCOPED_TRACE(bad);
      expectRefused(dir, with(var, bad), var, {"must be a non-negative decimal integer", "(got " + bad + ")"});
    }
    expectRefused(dir, with(var, ""), var, {"must be a non-negative decimal integer", "(got (empty))"});
  }
  // A step, a list with gaps, a task outside the array, MIN above MAX.
  expectRefused(dir, with("SLURM_ARRAY_TASK_STEP", "2"), "SLURM_ARRAY_TASK_STEP", {"must be 1", "(got 2)"});
  expectRefused(dir, with("SLURM_ARRAY_TASK_COUNT", "3"), "SLURM_ARRAY_TASK_COUNT",
                {"must equal SLURM_ARRAY_TASK_MAX - SLURM_ARRAY_TASK_MIN + 1 = 4", "(got 3)"});
  expectRefused(dir, with("SLURM_ARRAY_TASK_COUNT", "0"), "SLURM_ARRAY_TASK_COUNT", {"at least 1", "(got 0)"});
  expectRefused(dir, with("SLURM_ARRAY_TASK_ID", "9"), "SLURM_ARRAY_TASK_ID", {"[1, 4]", "(got 9)"});
  expectRefused(dir, with("SLURM_ARRAY_TASK_ID", "0"), "SLURM_ARRAY_TASK_ID", {"[1, 4]", "(got 0)"});
  expectRefused(dir, with("SLURM_ARRAY_TASK_MIN", "5"), "SLURM_ARRAY_TASK_MIN",
                {"must not exceed SLURM_ARRAY_TASK_MAX (4)", "(got 5)"});
  // Missing pieces.
  expectRefused(dir, without("SLURM_ARRAY_TASK_ID"), "SLURM_ARRAY_TASK_ID", {"is needed", "(got (not set))"});
  expectRefused(dir, without("SLURM_ARRAY_TASK_MIN"), "SLURM_ARRAY_TASK_MIN", {"is needed", "(got (not set))"});
  expectRefused(dir, without("SLURM_ARRAY_TASK_MAX"), "SLURM_ARRAY_TASK_MAX", {"is needed", "(got (not set))"});
  expectRefused(dir, {{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_MAX", "4"}, {"SLURM_ARRAY_TASK_COUNT", "9"}},
                "SLURM_ARRAY_TASK_COUNT", {"exceeds SLURM_ARRAY_TASK_MAX + 1 = 5", "(got 9)"});
  // More than 10^9 shards.
  expectRefused(dir, {{"SLURM_ARRAY_TASK_ID", "0"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_MAX", "2000000000"}},
                "SLURM_ARRAY_TASK_MAX", {"at most 1000000000", "(got 2000000000)"});
  // A shard count beside the array must agree with it.
  expectRefused(dir, ok, "--shard-count", {"differs from the Slurm job array's task count 4", "(got 3)"},
                "--shard-count 3");
  expectRefused(dir, with("SHAPESPLINE_SHARD_COUNT", "5"), "SHAPESPLINE_SHARD_COUNT",
                {"differs from the Slurm job array's task count 4", "(got 5)"});
}

TEST(CliShardAuto, BadKubernetesValuesAreRefusedNamingTheVariable) {
  ScratchDir dir("shard_auto_k8s_bad");
  expectRefused(dir, {{"JOB_COMPLETION_INDEX", "0"}}, "--shard-count",
                {"needs the job's completions", "SHAPESPLINE_SHARD_COUNT", "(got (not given))"});
  expectRefused(dir, {{"JOB_COMPLETION_INDEX", "4"}}, "JOB_COMPLETION_INDEX", {"below the shard count 4", "(got 4)"},
                "--shard-count 4");
  expectRefused(dir, {{"JOB_COMPLETION_INDEX", "abc"}}, "JOB_COMPLETION_INDEX",
                {"non-negative decimal integer", "(got abc)"}, "--shard-count 4");
  expectRefused(dir, {{"JOB_COMPLETION_INDEX", "0"}}, "--shard-count", {"[1, 1000000000]", "(got 0)"},
                "--shard-count 0");
  expectRefused(dir, {{"JOB_COMPLETION_INDEX", "0"}}, "--shard-count", {"non-negative decimal integer", "(got -4)"},
                "--shard-count -4");
  expectRefused(dir, {{"JOB_COMPLETION_INDEX", "0"}, {"SHAPESPLINE_SHARD_COUNT", "x"}}, "SHAPESPLINE_SHARD_COUNT",
                {"non-negative decimal integer", "(got x)"});
  expectRefused(dir, {{"JOB_COMPLETION_INDEX", "0"}, {"SHAPESPLINE_SHARD_COUNT", "2000000000"}},
                "SHAPESPLINE_SHARD_COUNT", {"[1, 1000000000]", "(got 2000000000)"});
  expectRefused(dir, {{"JOB_COMPLETION_INDEX", "0"}, {"SHAPESPLINE_SHARD_COUNT", "3"}}, "SHAPESPLINE_SHARD_COUNT",
                {"differs from --shard-count 4", "(got 3)"}, "--shard-count 4");
}

TEST(CliShardAuto, NoSchedulerOrBothAreRefused) {
  ScratchDir dir("shard_auto_none");
  expectRefused(dir, {}, "--shard", {"no scheduler task index", "SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX", "(got auto)"});
  // A shard count alone is no task index.
  expectRefused(dir, {{"SHAPESPLINE_SHARD_COUNT", "4"}}, "--shard", {"no scheduler task index"});
  expectRefused(dir, {{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_MIN", "1"}, {"SLURM_ARRAY_TASK_MAX", "2"},
                      {"JOB_COMPLETION_INDEX", "0"}},
                "--shard", {"both a Slurm job array", "(got auto)"}, "--shard-count 2");
  // --shard-count belongs to --shard auto.
  const CliResult r = runWithEnv(dir, {}, "sample " + butterfly() + " -o x.f64 --shard 1/2 --shard-count 2 --device cpu");
  EXPECT_EQ(r.rc, 2);
  EXPECT_TRUE(contains(r.err, "shapespline: error: --shard-count: is for --shard auto")) << r.err;
  EXPECT_TRUE(entries(dir.path()).empty());
}

// ---- Shard patterns in -o ---------------------------------------------------------------------------

TEST(CliShardPattern, PlaceholdersExpand) {
  ScratchDir dir("shard_pattern");
  struct Case {
    std::string pattern, shard, expected;
  };
  for (const Case& c : {Case{"p-{shard}-{count}.ply", "2/3", "p-2-3.ply"},
                        Case{"p-{shard:05d}-of-{count:05d}.obj", "2/3", "p-00002-of-00003.obj"},
                        Case{"p_{shard:02d}_{shard:02d}.f32", "3/12", "p_03_03.f32"},
                        Case{"p{shard:02d}.f32", "123/200", "p123.f32"},  // wider than the width: in full
                        Case{"lit{x}-{shard}.npy", "1/2", "lit{x}-1.npy"},  // other braces are text
                        Case{"whole-{shard}-of-{count}.f64", "", "whole-1-of-1.f64"}}) {  // unsharded: 1/1
    SCOPED_TRACE(c.pattern);
    const CliResult r = runCli("sample " + butterfly() + " -o " + quote(c.pattern) + " --samples 3 --device cpu -q" +
                                   (c.shard.empty() ? "" : " --shard " + c.shard),
                               dir.path(), dir.path());
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / c.expected)) << "expected " << c.expected;
    // A shard's record follows the expanded name; the unsharded job has none.
    EXPECT_EQ(fs::exists(dir / (c.expected + ".shard.json")), !c.shard.empty());
    for (const auto& n : entries(dir.path())) fs::remove(dir / n);
  }
  // A placeholder in a folder of -o is refused; one in the file name works under any folder.
  fs::create_directories(dir / "sub");
  ASSERT_EQ(runCli("sample " + butterfly() + " -o 'sub/a-{shard}.ply' --samples 3 --shard 1/2 --device cpu -q",
                   dir.path(), dir.path())
                .rc,
            0);
  EXPECT_TRUE(fs::exists(dir / "sub" / "a-1.ply"));
}

TEST(CliShardPattern, MalformedPatternsAreRefusedNamingO) {
  ScratchDir dir("shard_pattern_bad");
  for (const std::string bad : {"p{shard:5d}.f32", "p{shard:00d}.f32", "p{shard:011d}.f32", "p{shard:0d}.f32",
                                "p{shard:05x}.f32", "p{shard.f32", "p{countx}.f32", "p{shard}{count}.f32",
                                "p{shard}7.f32", "d{shard}/x.f32", "p{shard:-5d}.f32"}) {
    SCOPED_TRACE(bad);
    const CliResult r = runCli("sample " + butterfly() + " -o " + quote(bad) + " --samples 3 --shard 1/2 --device cpu",
                               dir.path(), dir.path());
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "shapespline: error: -o: ")) << r.err;
    EXPECT_TRUE(contains(r.err, "(got " + bad + ")")) << r.err;
    EXPECT_TRUE(entries(dir.path()).empty());
  }
  const CliResult r = runCli("sample " + butterfly() + " -o 'p{shard:5d}.f32' --shard 1/2 --device cpu", dir.path(), dir.path());
  EXPECT_TRUE(contains(r.err, "malformed placeholder '{shard:5d}' at character 2")) << r.err;
  EXPECT_TRUE(contains(r.err, "{shard:0Wd}")) << r.err;
}

// ---- examples/k8s: the Indexed Job's pods, then the merge Job, as Kubernetes would run them ----------

std::string firstMatch(const std::string& text, const std::string& re) {
  std::smatch m;
  return std::regex_search(text, m, std::regex(re)) ? m[1].str() : "";
}

TEST(CliShardAuto, KubernetesManifestsShardAndMerge) {
  ScratchDir dir("shard_k8s_manifest");
  const std::string k8s = std::string(SHAPESPLINE_SOURCE_DIR) + "/examples/k8s/";
  const std::string job = readText(k8s + "sample-indexed-job.yaml"), merge = readText(k8s + "merge-job.yaml");
  EXPECT_TRUE(contains(job, "completionMode: Indexed"));
  const std::string completions = firstMatch(job, R"re(\n  completions: (\d+))re");
  const std::string count = firstMatch(job, R"re(name: SHAPESPLINE_SHARD_COUNT\s+value: "(\d+)")re");
  ASSERT_FALSE(completions.empty());
  EXPECT_EQ(count, completions) << "SHAPESPLINE_SHARD_COUNT must equal completions";
  const std::string out = firstMatch(job, R"re(- -o\s+- (/out/\S+))re");
  const std::string pattern = firstMatch(merge, R"re("(/out/[^"]+)")re");
  ASSERT_FALSE(out.empty());
  EXPECT_EQ(pattern, out) << "the merge Job reads the pattern the pods write";
  // /out is the scratch folder, /models the examples; a small grid instead of the manifest's.
  fs::create_directories(dir / "out");
  auto local = [&](const std::string& p) { return (dir.path() / p.substr(1)).string(); };
  const std::string model = quote(examplesDir() + "/surface_aeb.json");
  const int n = std::stoi(completions);
  for (int index = 0; index < n; ++index) {
    const CliResult r = runWithEnv(dir, {{"JOB_COMPLETION_INDEX", std::to_string(index)}, {"SHAPESPLINE_SHARD_COUNT", count}},
                                   "sample " + model + " --grid 3 --device cpu --shard auto -q -o " + quote(local(out)));
    ASSERT_EQ(r.rc, 0) << "index " << index << ": " << r.err;
  }
  ASSERT_EQ(runWithEnv(dir, {}, "sample " + model + " --grid 3 --device cpu -q -o whole.f32").rc, 0);
  const CliResult m = runWithEnv(dir, {}, "merge -o merged.f32 " + quote(local(pattern)));
  ASSERT_EQ(m.rc, 0) << m.err;
  EXPECT_EQ(readText(dir / "merged.f32"), readText(dir / "whole.f32"));
}

}  // namespace
}  // namespace shapespline::test
