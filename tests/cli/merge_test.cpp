// Issue 12 at the command line: `merge` joins only the shards of one job -- same model, arguments,
// precision and format, shards 1..N of N in order, complete, sizes as their headers say -- and
// refuses anything else with exit 2 naming the shard (SHARD[k], 1-based), the path and the reason,
// leaving no file behind; crafted counts and indices never overflow; a shard's sidecar describes
// its own items only; merged files are byte-identical to the unsharded job in every format; merge
// streams (bounded memory).
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// `sample MODEL -o DIR/NAME OPTS --device cpu -q`; asserts success.
void sampleOnCpuTo(const ScratchDir& dir, const std::string& modelPath, const std::string& name, const std::string& opts) {
  const CliResult r = runCli("sample " + quote(modelPath) + " -o " + quote((dir / name).string()) + " " + opts +
                                 " --device cpu -q",
                             dir.path());
  ASSERT_EQ(r.rc, 0) << name << ": " << r.err;
}

CliResult merge(const ScratchDir& dir, const std::string& out, const std::vector<std::string>& inputs) {
  std::string args = "merge -o " + quote((dir / out).string());
  for (const auto& f : inputs) args += " " + quote(f.empty() || f[0] == '/' ? f : (dir / f).string());
  return runCli(args, dir.path());
}

// The folder holds exactly `expected` (sorted names): nothing partial or temporary was left.
void expectEntries(const ScratchDir& dir, std::vector<std::string> expected) {
  std::vector<std::string> got = dir.entries();
  std::sort(got.begin(), got.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(got, expected);
}

// A refused merge: exit 2, "shapespline: error: SHARD[k]: ... (got ...path...)" naming `reason`.
void expectRefused(const CliResult& r, const std::string& shard, const std::string& reason) {
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "shapespline: error: " + shard + ": ")) << r.err;
  EXPECT_TRUE(contains(r.err, reason)) << "expected '" << reason << "' in: " << r.err;
  EXPECT_FALSE(contains(r.err, "json.exception")) << r.err;
  EXPECT_FALSE(contains(r.err, "stoll")) << r.err;
}

std::vector<std::string> shardNames(const std::string& stem, const std::string& ext, int n) {
  std::vector<std::string> v;
  for (int k = 1; k <= n; ++k) v.push_back(stem + std::to_string(k) + "." + ext);
  return v;
}

// Samples the whole job and its N shards; returns the shard file names.
std::vector<std::string> wholeAndShards(const ScratchDir& dir, const std::string& modelPath, const std::string& ext,
                                        const std::string& opts, int n) {
  sampleOnCpuTo(dir, modelPath, "whole." + ext, opts);
  const auto names = shardNames("part", ext, n);
  for (int k = 1; k <= n; ++k) {
    sampleOnCpuTo(dir, modelPath, names[static_cast<size_t>(k - 1)],
             opts + " --shard " + std::to_string(k) + "/" + std::to_string(n));
  }
  return names;
}

// ---- Byte identity in every format --------------------------------------------------------------

struct Job {
  std::string model, ext, opts;
  int shards;
};

TEST(CliMerge, EveryFormatMergesToTheUnshardedFileByteForByte) {
  const std::vector<Job> jobs = {
      {"surface_aeb.json", "ply", "--grid 3", 4},       {"surface_aeb.json", "obj", "--grid 3x4", 3},
      {"surface_aeb.json", "csv", "--grid 3", 5},       {"surface_aeb.json", "f64", "--grid 3 --derivatives", 3},
      {"butterfly_aeb.json", "ply", "--samples 5", 3},  {"butterfly_aeb.json", "obj", "--samples 5", 4},
      {"butterfly_aeb.json", "csv", "--samples 5", 2},  {"butterfly_aeb.json", "f32", "--samples 5", 3},
      {"butterfly_aeb.json", "f64", "--samples 4", 23},  // more shards than its 20 spans: some are empty
      {"surface_aeb.json", "ply", "--grid 2 --precision float --normals", 7},
      {"butterfly_aeb.json", "obj", "--samples 3", 24},  // 20 spans: four empty shards in each
      {"butterfly_aeb.json", "ply", "--samples 3", 24},  {"surface_aeb.json", "obj", "--grid 2", 20},
  };
  for (const Job& j : jobs) {
    SCOPED_TRACE(j.model + " ." + j.ext + " " + j.opts + " x" + std::to_string(j.shards));
    ScratchDir dir("merge_identity");
    const auto parts = wholeAndShards(dir, exampleModel(j.model), j.ext, j.opts, j.shards);
    const CliResult r = merge(dir, "merged." + j.ext, parts);
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(readText(dir / ("merged." + j.ext)), readText(dir / ("whole." + j.ext)));
    if (j.ext == "f32" || j.ext == "f64") {
      // The merged sidecar is the unsharded job's, but for the data file's name.
      std::string whole = readText(dir / ("whole." + j.ext + ".json"));
      const std::string from = "\"whole." + j.ext + "\"";
      ASSERT_NE(whole.find(from), std::string::npos);
      whole.replace(whole.find(from), from.size(), "\"merged." + j.ext + "\"");
      EXPECT_EQ(readText(dir / ("merged." + j.ext + ".json")), whole);
    }
  }
}

// ---- A shard's sidecar describes its own items only ---------------------------------------------

TEST(CliMerge, ShardSidecarListsOnlyItsOwnItems) {
  ScratchDir dir("merge_sidecar");
  sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "whole.f64", "--samples 3");
  const json whole = json::parse(readText(dir / "whole.f64.json"));
  const size_t total = whole["items"]["total"].get<size_t>();
  ASSERT_GE(total, 4u);
  EXPECT_EQ(whole["items"]["spans_u"].size(), total);
  // 1000 shards of ~20 spans: most are empty and must list no span at all.
  sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "empty.f64", "--samples 3 --shard 1/1000");
  const json empty = json::parse(readText(dir / "empty.f64.json"));
  EXPECT_EQ(empty["items"]["count"], 0);
  EXPECT_EQ(empty["items"]["spans_u"].size(), 0u) << empty["items"].dump();
  sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "half.f64", "--samples 3 --shard 2/2");
  const json half = json::parse(readText(dir / "half.f64.json"));
  const size_t first = half["items"]["first"].get<size_t>(), count = half["items"]["count"].get<size_t>();
  ASSERT_EQ(half["items"]["spans_u"].size(), count);
  for (size_t k = 0; k < count; ++k) EXPECT_EQ(half["items"]["spans_u"][k], whole["items"]["spans_u"][first + k]);
  // Surfaces: the rows (u) the shard touches, and the columns of its row when it stays in one.
  sampleOnCpuTo(dir, exampleModel("surface_aeb.json"), "s.f64", "--grid 2 --shard 2/16");
  const json s = json::parse(readText(dir / "s.f64.json"));
  EXPECT_EQ(s["items"]["count"], 1);
  EXPECT_EQ(s["items"]["spans_u"].size(), 1u);
  EXPECT_EQ(s["items"]["spans_v"].size(), 1u);
  // Every shard and the whole job carry the same job fingerprint.
  EXPECT_EQ(half["job"], whole["job"]);
  EXPECT_EQ(empty["job"], whole["job"]);
  EXPECT_EQ(whole["job"].get<std::string>().size(), 16u);
}

// ---- Crafted counts and indices -----------------------------------------------------------------

TEST(CliMerge, PlyCountsThatOverflowAreRefused) {
  ScratchDir dir("merge_ply_overflow");
  // 2^61 spans of 2 samples: 2^62 vertices of 12 bytes are 3 * 2^64 = 0 bytes in size_t arithmetic,
  // 2^61 edges of 8 bytes 2^64 = 0 bytes: an empty body "matches" the header.
  writeText(dir / "a.ply",
            "ply\nformat binary_little_endian 1.0\ncomment shapespline sample of x\n"
            "comment shapespline job 0123456789abcdef curve shard 1/1 items 0..2305843009213693952 of "
            "2305843009213693952 grid 2x1\nelement vertex 4611686018427387904\nproperty float x\nproperty float y\n"
            "property float z\nelement edge 2305843009213693952\nproperty uint vertex1\nproperty uint vertex2\n"
            "end_header\n");
  // 2^62 vertices of 4 bytes likewise, without a job line.
  writeText(dir / "b.ply",
            "ply\nformat binary_little_endian 1.0\nelement vertex 4611686018427387904\nproperty float x\n"
            "element edge 0\nproperty uint vertex1\nproperty uint vertex2\nend_header\n");
  for (const char* f : {"a.ply", "b.ply"}) {
    SCOPED_TRACE(f);
    const CliResult r = merge(dir, "m.ply", {f});
    expectRefused(r, "SHARD[1]", f);
    expectEntries(dir, {"a.ply", "b.ply"});
  }
  // A count beyond 2^64 does not wrap either.
  writeText(dir / "c.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 99999999999999999999999\n"
                           "property float x\nend_header\n");
  expectRefused(merge(dir, "m.ply", {"c.ply"}), "SHARD[1]", "c.ply");
  expectEntries(dir, {"a.ply", "b.ply", "c.ply"});
}

TEST(CliMerge, ObjIndicesNearInt64MaxAndGarbageAreRefused) {
  ScratchDir dir("merge_obj_overflow");
  // Per-item shards: their polylines' indices are parsed and renumbered.
  sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "p1.obj", "--samples 3 --shard 1/2 --mesh-layout per-item");
  sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "p2.obj", "--samples 3 --shard 2/2 --mesh-layout per-item");
  const std::string good = readText(dir / "p2.obj");
  const size_t l = good.find("\nl ");
  ASSERT_NE(l, std::string::npos);
  const size_t eol = good.find('\n', l + 1);
  for (const std::string& bad : {std::string("l 9223372036854775807 1"), std::string("l -9223372036854775808 -1"),
                                 std::string("l 99999999999999999999999 1"), std::string("l abc -1"),
                                 std::string("l 1/-/2 -1"), std::string("l 0 -1")}) {
    SCOPED_TRACE(bad);
    writeText(dir / "p2.obj", good.substr(0, l + 1) + bad + good.substr(eol));
    const CliResult r = merge(dir, "m.obj", {"p1.obj", "p2.obj"});
    expectRefused(r, "SHARD[2]", "p2.obj");
    expectEntries(dir, {"p1.obj", "p2.obj", "p1.obj.shard.json", "p2.obj.shard.json"});  // + the shard records
  }
}

// ---- Shards that do not belong together ---------------------------------------------------------

TEST(CliMerge, ShardsOfDifferentJobsAreRefused) {
  ScratchDir dir("merge_mixed");
  for (const char* ext : {"ply", "obj", "f64"}) {
    SCOPED_TRACE(ext);
    const std::string e = ext;
    const std::string opts = "--samples 4";
    sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "a1." + e, opts + " --shard 1/2");
    sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "a2." + e, opts + " --shard 2/2");
    sampleOnCpuTo(dir, exampleModel("open_aeb.json"), "b2." + e, opts + " --shard 2/2");        // another model
    sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "c2." + e, "--samples 5 --shard 2/2");  // other arguments
    sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "d2." + e, opts + " --derivatives --shard 2/2");
    sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "e1." + e, opts + " --shard 1/3");
    sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "e2." + e, opts + " --shard 2/3");
    sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "f2." + e, opts + " --precision float --shard 2/2");
    expectRefused(merge(dir, "m." + e, {"a1." + e, "b2." + e}), "SHARD[2]", "another job");
    expectRefused(merge(dir, "m." + e, {"a1." + e, "c2." + e}), "SHARD[2]", "another job");
    expectRefused(merge(dir, "m." + e, {"a1." + e, "d2." + e}), "SHARD[2]", "another job");
    expectRefused(merge(dir, "m." + e, {"a1." + e, "f2." + e}), "SHARD[2]", "another job");
    expectRefused(merge(dir, "m." + e, {"a2." + e, "a1." + e}), "SHARD[1]", "shard 2/2");   // out of order
    expectRefused(merge(dir, "m." + e, {"a1." + e, "a1." + e}), "SHARD[2]", "shard 1/2");   // the same twice
    expectRefused(merge(dir, "m." + e, {"a1." + e}), "SHARD[1]", "2 shards");              // one missing
    expectRefused(merge(dir, "m." + e, {"e1." + e, "e2." + e}), "SHARD[1]", "3 shards");   // the last missing
    expectRefused(merge(dir, "m." + e, {"a1." + e, "e2." + e}), "SHARD[2]", "another job");
    EXPECT_FALSE(fs::exists(dir / ("m." + e)));
  }
}

TEST(CliMerge, TruncatedExtendedAndNonRegularShardsAreRefused) {
  ScratchDir dir("merge_truncated");
  for (const char* ext : {"ply", "obj", "f64", "csv"}) {
    SCOPED_TRACE(ext);
    const std::string e = ext;
    sampleOnCpuTo(dir, exampleModel("surface_aeb.json"), "p1." + e, "--grid 3 --shard 1/2");
    sampleOnCpuTo(dir, exampleModel("surface_aeb.json"), "p2." + e, "--grid 3 --shard 2/2");
    const std::string good = readText(dir / ("p2." + e));
    writeText(dir / ("t2." + e), good.substr(0, good.size() - 5));
    if (e == "f64") {  // the data cut or extended beside an intact sidecar
      fs::copy_file(dir / "p2.f64.json", dir / "t2.f64.json", fs::copy_options::overwrite_existing);
      fs::copy_file(dir / "p2.f64.json", dir / "x2.f64.json", fs::copy_options::overwrite_existing);
    }
    expectRefused(merge(dir, "m." + e, {"p1." + e, "t2." + e}), "SHARD[2]", "t2." + e);
    writeText(dir / ("x2." + e), good + (e == "obj" || e == "csv" ? "v 1 2 3\n" : "junk"));
    expectRefused(merge(dir, "m." + e, {"p1." + e, "x2." + e}), "SHARD[2]", "x2." + e);
    fs::create_directories(dir / ("dir." + e));
    expectRefused(merge(dir, "m." + e, {"p1." + e, "dir." + e}), "SHARD[2]", "not a regular file");
    expectRefused(merge(dir, "m." + e, {"p1." + e, "missing." + e}), "SHARD[2]", "cannot open");
    EXPECT_FALSE(fs::exists(dir / ("m." + e)));
    fs::remove(dir / ("t2." + e));
    fs::remove(dir / ("x2." + e));
  }
}

TEST(CliMerge, BrokenSidecarsAreRefusedWithExit2) {
  ScratchDir dir("merge_sidecar_broken");
  sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "p1.f64", "--samples 3 --shard 1/2");
  sampleOnCpuTo(dir, exampleModel("butterfly_aeb.json"), "p2.f64", "--samples 3 --shard 2/2");
  const std::string good = readText(dir / "p2.f64.json");
  const json g = json::parse(good);
  json wrongCount = g;
  wrongCount["counts"]["bytes"] = 1;
  json wrongType = g;
  wrongType["items"]["first"] = "zero";
  json huge = g;
  huge["items"]["count"] = 18446744073709551615ull;
  for (const std::string& bad : {std::string("{}"), std::string("[]"), std::string("not json"),
                                 std::string(100000, '['), wrongCount.dump(), wrongType.dump(), huge.dump()}) {
    SCOPED_TRACE(bad.substr(0, 60));
    writeText(dir / "p2.f64.json", bad);
    const CliResult r = merge(dir, "m.f64", {"p1.f64", "p2.f64"});
    expectRefused(r, "SHARD[2]", "p2.f64");
    EXPECT_LT(r.err.size(), 600u) << "the message must not echo the sidecar";
    EXPECT_FALSE(fs::exists(dir / "m.f64"));
    EXPECT_FALSE(fs::exists(dir / "m.f64.json"));
  }
  fs::remove(dir / "p2.f64.json");
  expectRefused(merge(dir, "m.f64", {"p1.f64", "p2.f64"}), "SHARD[2]", "p2.f64.json");
}

TEST(CliMerge, CsvShardsOutOfOrderOrOverlappingAreRefused) {
  ScratchDir dir("merge_csv");
  sampleOnCpuTo(dir, exampleModel("surface_aeb.json"), "p1.csv", "--grid 3 --shard 1/2");
  sampleOnCpuTo(dir, exampleModel("surface_aeb.json"), "p2.csv", "--grid 3 --shard 2/2");
  sampleOnCpuTo(dir, exampleModel("surface_aeb.json"), "q2.csv", "--grid 3 --derivatives --shard 2/2");
  sampleOnCpuTo(dir, exampleModel("surface_aeb.json"), "r2.csv", "--grid 4 --shard 2/2");
  expectRefused(merge(dir, "m.csv", {"p2.csv", "p1.csv"}), "SHARD[2]", "order");
  expectRefused(merge(dir, "m.csv", {"p1.csv", "p1.csv"}), "SHARD[2]", "order");
  expectRefused(merge(dir, "m.csv", {"p1.csv", "q2.csv"}), "SHARD[2]", "header");
  expectRefused(merge(dir, "m.csv", {"p1.csv", "r2.csv"}), "SHARD[2]", "rows per patch");
  EXPECT_FALSE(fs::exists(dir / "m.csv"));
}

// ---- The model path in headers cannot inject lines ----------------------------------------------

TEST(CliMerge, ModelPathIsEscapedInPlyAndObjHeaders) {
  ScratchDir dir("merge_escape");
  const fs::path sub = dir / "x\nv 1 2 3\nend_header\ny";
  fs::create_directories(sub);
  fs::copy_file(exampleModel("butterfly_aeb.json"), sub / "m.json");
  const std::string path = (sub / "m.json").string();
  sampleOnCpuTo(dir, path, "c.obj", "--samples 3");
  sampleOnCpuTo(dir, path, "c.ply", "--samples 3");
  const std::string obj = readText(dir / "c.obj");
  EXPECT_FALSE(contains(obj, "\nv 1 2 3\n")) << obj.substr(0, 200);
  EXPECT_TRUE(contains(obj, "x\\nv 1 2 3\\nend_header\\ny")) << obj.substr(0, 200);
  const std::string ply = readText(dir / "c.ply");
  EXPECT_EQ(ply.find("\nend_header\n"), ply.rfind("\nend_header\n"));
  EXPECT_FALSE(contains(ply, "\nv 1 2 3\n"));
  // Shards with that path still merge into the unsharded file.
  sampleOnCpuTo(dir, path, "p1.ply", "--samples 3 --shard 1/2");
  sampleOnCpuTo(dir, path, "p2.ply", "--samples 3 --shard 2/2");
  ASSERT_EQ(merge(dir, "m.ply", {"p1.ply", "p2.ply"}).rc, 0);
  EXPECT_EQ(readText(dir / "m.ply"), ply);
}

// ---- Bounded memory -----------------------------------------------------------------------------

// Peak RSS (KiB) of `shapespline merge -o OUT SHARDS...` in `dir`, measured by GNU time.
long mergeRssKiB(const ScratchDir& dir, const std::string& out, const std::vector<std::string>& shards) {
  std::string cmd = "/usr/bin/time -f %M -o " + quote((dir / "rss.txt").string()) + " " + quote(SHAPESPLINE_CLI) +
                    " merge -o " + quote((dir / out).string());
  for (const auto& s : shards) cmd += " " + quote((dir / s).string());
  cmd += " 2>" + quote((dir / "err.txt").string());
  EXPECT_EQ(std::system(cmd.c_str()), 0) << readText(dir / "err.txt");
  return std::stol(readText(dir / "rss.txt"));
}

// Merging 2 x 69 MB of raw shards takes no more memory than merging two tiny ones, plus the
// fixed buffers (a merge that read whole shards needed 140 MB more); relative to that baseline
// the bound holds under the sanitizers too.
TEST(CliMerge, MergeStreamsInBoundedMemory) {
  if (!fs::exists("/usr/bin/time")) GTEST_SKIP() << "needs /usr/bin/time to measure the peak RSS";
  ScratchDir dir("merge_memory");
  for (int k = 1; k <= 2; ++k) {
    const std::string kn = std::to_string(k) + "/2";
    sampleOnCpuTo(dir, exampleModel("surface_aeb.json"), "p" + std::to_string(k) + ".f64", "--grid 600 --shard " + kn);
    sampleOnCpuTo(dir, exampleModel("surface_aeb.json"), "t" + std::to_string(k) + ".f64", "--grid 2 --shard " + kn);
  }
  ASSERT_GT(fs::file_size(dir / "p1.f64"), 60u << 20);
  const long baseKiB = mergeRssKiB(dir, "t.f64", {"t1.f64", "t2.f64"});
  const long rssKiB = mergeRssKiB(dir, "m.f64", {"p1.f64", "p2.f64"});
  EXPECT_EQ(fs::file_size(dir / "m.f64"), fs::file_size(dir / "p1.f64") + fs::file_size(dir / "p2.f64"));
  EXPECT_LT(rssKiB, baseKiB + 16 * 1024) << "merge must stream its shards, not read them whole";
  std::printf("merge of %ju MB: peak RSS %ld KiB (tiny shards: %ld KiB)\n",
              static_cast<uintmax_t>(fs::file_size(dir / "m.f64") >> 20), rssKiB, baseKiB);
}

}  // namespace
}  // namespace shapespline::test
