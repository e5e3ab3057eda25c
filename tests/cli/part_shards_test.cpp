// Parts and trimmed faces on the cluster (docs/cluster.md "Trimmed faces and parts"): `sample
// part.json --shard K/N` and `sample FACE --trim --shard K/N` cut the job's items where the samples
// inside the trim loops balance, `merge` joins the shards into the unsharded job's bytes (data and
// sidecar) on the CPU and on Vulkan, under Slurm's variables, and after a killed shard is run
// again; shard records let a finished shard be skipped. CSV shards are refused (no identity).
#include "cli_runner.h"
#include "handmade_part.h"

#include <gtest/gtest.h>

#include <csignal>
#include <sys/wait.h>
#include <unistd.h>

#include <numeric>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

class PartShards : public ::testing::Test {
 protected:
  void SetUp() override {
    writeHandmadePart(dir_ / "part", {{3, 2}, {1, 1}, {2, 2}, {1, 3}});
    fs::create_directories(dir_ / "whole");
    fs::create_directories(dir_ / "merged");
  }
  std::string part() const { return quote((dir_ / "part" / "part.json").string()); }
  std::string face() const { return quote((dir_ / "part" / "face_0.json").string()) + " --trim"; }
  CliResult run(const std::string& args) { return runCli(args, dir_.path()); }
  // `sample MODEL ARGS -o NAME`, which must succeed.
  void sample(const std::string& model, const std::string& args, const std::string& name) {
    const CliResult r = run("sample " + model + " " + args + " -q -o " + quote((dir_ / name).string()));
    ASSERT_EQ(r.rc, 0) << r.err;
  }
  void merge(const std::vector<std::string>& shards, const std::string& name) {
    std::string args = "merge -o " + quote((dir_ / name).string());
    for (const auto& s : shards) args += " " + quote((dir_ / s).string());
    const CliResult r = run(args);
    ASSERT_EQ(r.rc, 0) << r.err;
  }
  // The bytes of NAME and, for raw and .npy, of its sidecar NAME.json (which names the data file:
  // compare files of the same name, in other folders).
  std::string bytesOf(const std::string& name) const {
    std::string b = readText(dir_ / name);
    if (!name.ends_with(".ply")) b += "|" + readText(dir_ / (name + ".json"));
    return b;
  }
  ScratchDir dir_{"part_shards"};
};

TEST_F(PartShards, FourShardsMergeIntoTheWholeJobsBytes) {
  for (const std::string device : {"--device cpu", "--device vulkan --require-device"}) {
    for (const std::string ext : {"npy", "f32", "ply"}) {
      for (const std::string& model : {part(), face()}) {
        SCOPED_TRACE(device + " ." + ext + " " + model);
        const std::string opts = "--grid 6 --normals " + device;
        sample(model, opts, "whole/out." + ext);
        std::vector<std::string> shards;
        for (int k = 1; k <= 4; ++k) {
          shards.push_back("s" + std::to_string(k) + "." + ext);
          sample(model, opts + " --shard " + std::to_string(k) + "/4", shards.back());
        }
        merge(shards, "merged/out." + ext);
        EXPECT_GT(readText(dir_ / ("whole/out." + ext)).size(), 1000u);
        EXPECT_TRUE(bytesOf("merged/out." + ext) == bytesOf("whole/out." + ext)) << "the merge is not the whole job's bytes";
        // Every shard holds records: the cut balances them.
        for (const auto& s : shards) EXPECT_GT(readText(dir_ / s).size(), 400u) << s;
      }
    }
  }
}

// The shards cut by samples inside the loops, not by faces: a face of 81 patches beside 9 faces of
// one patch holds 90% of the samples, and no shard of 4 holds more than 30% of them.
TEST_F(PartShards, OneBigFaceDoesNotMakeOneShardTheWholeJob) {
  std::vector<std::pair<int, int>> faces(10, {1, 1});
  faces[3] = {9, 9};
  writeHandmadePart(dir_ / "part", faces);
  std::vector<uint64_t> records;
  for (int k = 1; k <= 4; ++k) {
    const std::string name = "s" + std::to_string(k) + ".f64";
    sample(part(), "--grid 8 --device cpu --shard " + std::to_string(k) + "/4", name);
    records.push_back(json::parse(readText(dir_ / (name + ".json")))["shard"]["records"].get<uint64_t>());
  }
  const uint64_t total = std::accumulate(records.begin(), records.end(), uint64_t{0});
  sample(part(), "--grid 8 --device cpu", "whole/out.f64");
  EXPECT_EQ(total, json::parse(readText(dir_ / "whole/out.f64.json"))["records"].get<uint64_t>());
  for (uint64_t r : records) EXPECT_LE(static_cast<double>(r), 0.30 * static_cast<double>(total)) << r << " of " << total;
}

// --shard auto under a Slurm array's variables names each task's shard; the pattern's files merge.
TEST_F(PartShards, SlurmArrayTasksMergeIntoTheWholeJob) {
  sample(part(), "--grid 5 --device cpu", "whole/out.npy");
  for (int task = 0; task < 3; ++task) {
    const std::string cmd = "cd " + quote(dir_.path().string()) + " && env -u JOB_COMPLETION_INDEX -u SHAPESPLINE_SHARD_COUNT " +
                            "-u SLURM_ARRAY_TASK_COUNT -u SLURM_ARRAY_TASK_STEP " +
                            "SLURM_ARRAY_TASK_ID=" + std::to_string(task) + " SLURM_ARRAY_TASK_MIN=0 SLURM_ARRAY_TASK_MAX=2 " +
                            quote(SHAPESPLINE_CLI) + " sample " + part() +
                            " --grid 5 --device cpu -q --shard auto -o 'p-{shard}-of-{count}.npy' >out.txt 2>err.txt";
    const CliResult r = runCaptured(cmd, dir_ / "out.txt", dir_ / "err.txt");
    ASSERT_EQ(r.rc, 0) << r.err;
  }
  ASSERT_TRUE(fs::exists(dir_ / "p-2-of-3.npy.shard.json"));
  const CliResult m =
      run("merge " + quote((dir_ / "p-{shard}-of-{count}.npy").string()) + " -o " + quote((dir_ / "merged/out.npy").string()));
  ASSERT_EQ(m.rc, 0) << m.err;
  EXPECT_TRUE(bytesOf("merged/out.npy") == bytesOf("whole/out.npy"));
}

// A finished shard whose record verifies is left as it is; a shard killed while it ran left nothing
// and runs again; the merge is still the whole job.
TEST_F(PartShards, AKilledShardRunsAgainAndFinishedOnesAreKept) {
  const std::string opts = "--grid 128 --device cpu";
  sample(part(), opts, "whole/out.f64");
  for (int k : {1, 3}) sample(part(), opts + " --shard " + std::to_string(k) + "/3", "s" + std::to_string(k) + ".f64");
  // Shard 2, killed as soon as it has started.
  const std::string cmd = "exec " + quote(SHAPESPLINE_CLI) + " sample " + part() + " " + opts + " --shard 2/3 -q -o " +
                          quote((dir_ / "s2.f64").string());
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::usleep(20'000);
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (WIFSIGNALED(status)) {
    EXPECT_FALSE(fs::exists(dir_ / "s2.f64")) << "a killed shard left its file";
  }
  // Run again: shard 1 verifies and is kept, shard 2 is sampled.
  const auto before = fs::last_write_time(dir_ / "s1.f64");
  const CliResult again = run("sample " + part() + " " + opts + " --shard 1/3 -o " + quote((dir_ / "s1.f64").string()));
  ASSERT_EQ(again.rc, 0) << again.err;
  EXPECT_NE(again.err.find("shard 1/3 is complete"), std::string::npos) << again.err;
  EXPECT_EQ(fs::last_write_time(dir_ / "s1.f64"), before);
  sample(part(), opts + " --shard 2/3", "s2.f64");
  merge({"s1.f64", "s2.f64", "s3.f64"}, "merged/out.f64");
  EXPECT_TRUE(bytesOf("merged/out.f64") == bytesOf("whole/out.f64"));
}

TEST_F(PartShards, MergeRefusesShardsThatDoNotMakeTheJob) {
  for (int k = 1; k <= 3; ++k) sample(part(), "--grid 5 --device cpu --shard " + std::to_string(k) + "/3", "s" + std::to_string(k) + ".f32");
  sample(face(), "--grid 5 --device cpu --shard 2/3", "face2.f32");
  struct Case {
    std::vector<std::string> shards;
    std::string rule;
  };
  const Case cases[] = {
      {{"s1.f32", "s2.f32"}, "expected 1/2"},
      {{"s2.f32", "s1.f32", "s3.f32"}, "expected 1/3"},
      {{"s1.f32", "face2.f32", "s3.f32"}, "another job"},
  };
  for (const Case& c : cases) {
    std::string args = "merge -o " + quote((dir_ / "m.f32").string());
    for (const auto& s : c.shards) args += " " + quote((dir_ / s).string());
    const CliResult r = run(args);
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find(c.rule), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "m.f32"));
  }
}

// A trimmed sidecar whose keys hold other types (merge_fuzzer found `"dtype": [...]` thrown as an
// unexpected exception) is refused like any broken sidecar, exit 2, nothing written.
TEST_F(PartShards, SidecarKeysOfAnotherTypeAreRefused) {
  for (int k = 1; k <= 2; ++k) sample(part(), "--grid 5 --device cpu --shard " + std::to_string(k) + "/2", "t" + std::to_string(k) + ".npy");
  const std::string good = readText(dir_ / "t1.npy.json");
  for (const char* key : {"dtype", "format", "records"}) {
    json bad = json::parse(good);
    bad[key] = json::array({1, 2});
    writeText(dir_ / "t1.npy.json", bad.dump());
    fs::remove(dir_ / "t1.npy.shard.json");  // else the record's SHA-256 refuses the edit first
    const CliResult r = run("merge -o " + quote((dir_ / "m.npy").string()) + " " + quote((dir_ / "t1.npy").string()) + " " +
                            quote((dir_ / "t2.npy").string()));
    EXPECT_EQ(r.rc, 2) << key << "\n" << r.err;
    EXPECT_NE(r.err.find("SHARD[1]"), std::string::npos) << key << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "m.npy")) << key;
  }
}

TEST_F(PartShards, CsvShardsAreRefused) {
  for (const std::string& model : {part(), face()}) {
    const CliResult r = run("sample " + model + " --grid 4 --device cpu --shard 1/2 -o " + quote((dir_ / "s.csv").string()));
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("shapespline: error: --shard: shards of trimmed faces and parts are written as .npy"),
              std::string::npos)
        << r.err;
    for (const std::string& name : dir_.entries()) EXPECT_TRUE(name == "part" || name == "whole" || name == "merged") << name;
  }
}

}  // namespace
}  // namespace shapespline::test
