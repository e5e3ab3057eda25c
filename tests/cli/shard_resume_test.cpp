// Issue 16, requirement 3 at the command line: every shard writes OUT.shard.json (job, shard,
// items, points/vertices, bytes and SHA-256 of each file, as sha256sum prints them, and the job
// metadata) with its data; rerunning a shard whose files verify does nothing (exit 0, a notice,
// the files untouched), a shard whose file or record does not verify is sampled again; `merge`
// takes a shard pattern and verifies the record of every shard that has one. In every format
// that shards (.f32/.f64, .npy, .ply, .obj, .csv).
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

std::string surface() { return quote(examplesDir() + "/surface_aeb.json"); }

CliResult sample(const ScratchDir& dir, const std::string& out, const std::string& opts) {
  return runCli("sample " + surface() + " -o " + quote(out) + " --grid 3 --device cpu " + opts, dir.path(), dir.path());
}

// The files of a sampled output: the data, its raw sidecar (.f32/.f64/.npy) and its record.
std::vector<std::string> filesOf(const std::string& name) {
  std::vector<std::string> v{name};
  if (name.ends_with(".f32") || name.ends_with(".f64") || name.ends_with(".npy")) v.push_back(name + ".json");
  return v;
}

struct Stamp {
  ino_t ino = 0;
  long long mtimeNs = 0;
  std::string bytes;
  friend bool operator==(const Stamp&, const Stamp&) = default;
};

Stamp stampOf(const fs::path& p) {
  struct stat st {};
  ::stat(p.c_str(), &st);
  return {st.st_ino, static_cast<long long>(st.st_mtim.tv_sec) * 1'000'000'000LL + st.st_mtim.tv_nsec, readText(p)};
}

// sha256sum's digits of a file (a tool we did not write).
std::string sha256sum(const ScratchDir& dir, const fs::path& p) {
  const fs::path out = dir / "_sum.txt", err = dir / "_sumerr.txt";
  const CliResult r =
      runCaptured("sha256sum " + quote(p.string()) + " >" + quote(out.string()) + " 2>" + quote(err.string()), out, err);
  return r.out.substr(0, 64);
}

const char* const kFormats[] = {"f32", "f64", "npy", "ply", "obj", "csv"};

TEST(CliShardRecord, EveryShardRecordsItsFilesAndJob) {
  ScratchDir dir("shard_record");
  for (const char* ext : kFormats) {
    SCOPED_TRACE(ext);
    const std::string name = std::string("p2.") + ext;
    const CliResult r = sample(dir, name, "--shard 2/3 -q");
    ASSERT_EQ(r.rc, 0) << r.err;
    ASSERT_TRUE(fs::exists(dir / (name + ".shard.json")));
    const json rec = json::parse(readText(dir / (name + ".shard.json")));
    EXPECT_EQ(rec["format"], "shapespline-shard");
    EXPECT_EQ(rec["format_version"], 1);
    EXPECT_EQ(rec["output_format"], ext);
    EXPECT_EQ(rec["kind"], "surface");
    EXPECT_EQ(rec["shard"], json({{"index", 2}, {"count", 3}}));
    // 16 patches in 3 shards: items 5..10.
    EXPECT_EQ(rec["items"], json({{"first", 5}, {"count", 5}, {"total", 16}}));
    EXPECT_EQ(rec["points"], 5 * 9);
    if (std::string(ext) == "ply" || std::string(ext) == "obj") {
      EXPECT_GT(rec["vertices"].get<int>(), 0);  // owned + foreign vertices of the welded shard
    } else {
      EXPECT_EQ(rec["vertices"], 5 * 9);
    }
    const std::vector<std::string> files = filesOf(name);
    ASSERT_EQ(rec["files"].size(), files.size());
    for (size_t i = 0; i < files.size(); ++i) {
      const json& f = rec["files"][i];
      EXPECT_EQ(f["name"], files[i]);
      EXPECT_EQ(f["role"], i == 0 ? "data" : "sidecar");
      EXPECT_EQ(f["bytes"].get<uint64_t>(), fs::file_size(dir / files[i]));
      EXPECT_EQ(f["sha256"], sha256sum(dir, dir / files[i]));
    }
    // The job fingerprint is the sidecar's / the header's; the metadata is the job's.
    if (files.size() == 2) {
      const json side = json::parse(readText(dir / files[1]));
      EXPECT_EQ(rec["job"], side["job"]);
      EXPECT_EQ(rec["metadata"], side["metadata"]);
    } else if (std::string(ext) != "csv") {
      EXPECT_TRUE(contains(readText(dir / name), "shapespline job " + rec["job"].get<std::string>())) << name;
    }
    EXPECT_EQ(rec["metadata"]["model_sha256"], sha256sum(dir, examplesDir() + "/surface_aeb.json"));
  }
  // An unsharded job writes no record.
  ASSERT_EQ(sample(dir, "whole.f32", "-q").rc, 0);
  EXPECT_FALSE(fs::exists(dir / "whole.f32.shard.json"));
}

TEST(CliShardRecord, RerunOfAVerifiedShardDoesNothing) {
  ScratchDir dir("shard_resume");
  for (const char* ext : kFormats) {
    SCOPED_TRACE(ext);
    const std::string name = std::string("p1.") + ext;
    ASSERT_EQ(sample(dir, name, "--shard 1/2 -q").rc, 0);
    std::vector<std::string> files = filesOf(name);
    files.push_back(name + ".shard.json");
    std::vector<Stamp> before;
    for (const auto& f : files) before.push_back(stampOf(dir / f));
    const auto listing = entries(dir.path());
    const CliResult r = sample(dir, name, "--shard 1/2");
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "shapespline: notice: " + name + ": shard 1/2 is complete: its files verify against '" +
                                    name + ".shard.json'"))
        << r.err;
    EXPECT_TRUE(contains(r.err, "nothing to do")) << r.err;
    EXPECT_FALSE(contains(r.err, "wrote")) << r.err;
    for (size_t i = 0; i < files.size(); ++i) EXPECT_EQ(stampOf(dir / files[i]), before[i]) << files[i] << " was touched";
    EXPECT_EQ(entries(dir.path()), listing) << "no file added or left behind";
    // Quiet: the same, silently. Other threads or chunk sizes are the same job.
    const CliResult q = sample(dir, name, "--shard 1/2 -q --threads 1 --chunk-points 7");
    EXPECT_EQ(q.rc, 0);
    EXPECT_EQ(q.err, "");
    for (size_t i = 0; i < files.size(); ++i) EXPECT_EQ(stampOf(dir / files[i]), before[i]) << files[i];
  }
}

TEST(CliShardRecord, AShardThatDoesNotVerifyIsSampledAgain) {
  ScratchDir dir("shard_redo");
  for (const char* ext : kFormats) {
    SCOPED_TRACE(ext);
    const std::string name = std::string("p2.") + ext;
    ASSERT_EQ(sample(dir, name, "--shard 2/2 -q").rc, 0);
    std::vector<std::string> files = filesOf(name);
    files.push_back(name + ".shard.json");
    std::vector<std::string> good;
    for (const auto& f : files) good.push_back(readText(dir / f));
    auto expectRedone = [&](const std::string& why) {
      const CliResult r = sample(dir, name, "--shard 2/2");
      EXPECT_EQ(r.rc, 0) << r.err;
      EXPECT_TRUE(contains(r.err, "shapespline: notice: " + name + ": the shard record '" + name +
                                      ".shard.json' does not verify ("))
          << r.err;
      EXPECT_TRUE(contains(r.err, why)) << "expected '" << why << "' in: " << r.err;
      EXPECT_TRUE(contains(r.err, "sampling the shard again")) << r.err;
      EXPECT_TRUE(contains(r.err, "shapespline: wrote " + name)) << r.err;
      for (size_t i = 0; i < files.size(); ++i) EXPECT_EQ(readText(dir / files[i]), good[i]) << files[i];
    };
    // One byte of the data changed, the size kept: only the SHA-256 tells.
    std::string bad = good[0];
    bad[bad.size() / 2] ^= 0x20;
    writeText(dir / name, bad);
    expectRedone("'" + name + "' has another SHA-256 than the record's");
    // The data cut short.
    writeText(dir / name, good[0].substr(0, good[0].size() - 3));
    expectRedone("'" + name + "' is " + std::to_string(good[0].size() - 3) + " bytes, the record says " +
                 std::to_string(good[0].size()));
    // The data gone; the sidecar changed.
    fs::remove(dir / name);
    expectRedone("'" + name + "' is missing");
    if (files.size() == 3) {
      writeText(dir / files[1], good[1] + " ");
      expectRedone("'" + files[1] + "' is ");
    }
    // A record that is not one (hostile or broken), or of another job, is replaced.
    for (const std::string& rec : {std::string("not json"), std::string("{}"), std::string(100000, '['),
                                   std::string("{\"format\": \"shapespline-shard\", \"format_version\": 1, \"x\": 1}")}) {
      writeText(dir / files.back(), rec);
      expectRedone("the record ");
    }
    json other = json::parse(good.back());
    other["job"] = "0123456789abcdef";
    writeText(dir / files.back(), other.dump());
    expectRedone("it is of another job (0123456789abcdef");
    other = json::parse(good.back());
    other["metadata"]["tool_commit"] = "feedfacefeed";
    writeText(dir / files.back(), other.dump());
    expectRedone("its job metadata \"tool_commit\" differs");
    // A record in the shard's place that is a folder: sampled again too (the record is replaced).
    fs::remove(dir / files.back());
    fs::create_directories(dir / files.back());
    const CliResult r = sample(dir, name, "--shard 2/2");
    EXPECT_EQ(r.rc, 2) << "a folder in the record's place cannot be replaced: " << r.err;
    EXPECT_TRUE(contains(r.err, "shapespline: error: -o: ")) << r.err;
    fs::remove(dir / files.back());
  }
}

// ---- merge by pattern -------------------------------------------------------------------------------

CliResult merge(const ScratchDir& dir, const std::string& out, const std::string& shards) {
  return runCli("merge -o " + quote(out) + " " + shards, dir.path(), dir.path());
}

TEST(CliShardRecord, MergeExpandsAShardPattern) {
  ScratchDir dir("shard_merge_pattern");
  for (const char* ext : kFormats) {
    SCOPED_TRACE(ext);
    const std::string e = ext;
    ASSERT_EQ(sample(dir, "whole." + e, "-q").rc, 0);
    // With {count}: N from the files present; without: from shard 1 (record, sidecar or header).
    for (const std::string& pattern : {"part-{shard:03d}-of-{count:03d}." + e, "q{shard}." + e}) {
      SCOPED_TRACE(pattern);
      for (int k = 1; k <= 3; ++k) ASSERT_EQ(sample(dir, pattern, "-q --shard " + std::to_string(k) + "/3").rc, 0);
      const CliResult r = merge(dir, "m." + e, quote(pattern));
      ASSERT_EQ(r.rc, 0) << r.err;
      EXPECT_EQ(readText(dir / ("m." + e)), readText(dir / ("whole." + e))) << "merged file differs from unsharded";
      // Without records (the user removed them) the pattern still expands: from shard 1's header /
      // sidecar, from {count}, or (CSV without {count}) from the shards present.
      for (int k = 1; k <= 3; ++k) {
        const std::string shard = pattern.find("{count") != std::string::npos
                                      ? "part-00" + std::to_string(k) + "-of-003." + e
                                      : "q" + std::to_string(k) + "." + e;
        fs::remove(dir / (shard + ".shard.json"));
      }
      fs::remove(dir / ("m." + e));
      ASSERT_EQ(merge(dir, "m." + e, quote(pattern)).rc, 0);
      EXPECT_EQ(readText(dir / ("m." + e)), readText(dir / ("whole." + e)));
      fs::remove(dir / ("m." + e));
      if (fs::exists(dir / ("m." + e + ".json"))) fs::remove(dir / ("m." + e + ".json"));
    }
  }
}

TEST(CliShardRecord, MergeRefusesBadPatternsAndShardsThatDoNotVerify) {
  ScratchDir dir("shard_merge_bad");
  for (int k = 1; k <= 3; ++k) ASSERT_EQ(sample(dir, "s-{shard}-{count}.f32", "-q --shard " + std::to_string(k) + "/3").rc, 0);
  auto refused = [&](const CliResult& r, const std::string& field, const std::string& part) {
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "shapespline: error: " + field + ": ")) << r.err;
    EXPECT_TRUE(contains(r.err, part)) << "expected '" << part << "' in: " << r.err;
    EXPECT_FALSE(fs::exists(dir / "m.f32"));
    EXPECT_FALSE(fs::exists(dir / "m.f32.json"));
  };
  // A malformed pattern, one without {shard}, one that matches nothing.
  refused(merge(dir, "m.f32", quote("s-{shard:5d}-{count}.f32")), "SHARD", "malformed placeholder");
  refused(merge(dir, "m.f32", quote("s-1-{count}.f32")), "SHARD", "needs {shard}");
  refused(merge(dir, "m.f32", quote("t-{shard}-{count}.f32")), "SHARD", "no file matches the shard pattern");
  // A stale shard of another count beside them.
  ASSERT_EQ(sample(dir, "s-{shard}-{count}.f32", "-q --shard 1/2").rc, 0);
  refused(merge(dir, "m.f32", quote("s-{shard}-{count}.f32")), "SHARD", "several shard counts");
  fs::remove(dir / "s-1-2.f32");
  // A missing shard in the middle.
  fs::rename(dir / "s-2-3.f32", dir / "keep.f32");
  refused(merge(dir, "m.f32", quote("s-{shard}-{count}.f32")), "SHARD[2]", "is missing: the pattern expands to shards 1..3");
  fs::rename(dir / "keep.f32", dir / "s-2-3.f32");
  // A shard changed after it was written (the size kept): its record tells, by pattern or by name.
  const std::string good = readText(dir / "s-2-3.f32");
  std::string bad = good;
  bad[7] ^= 1;
  writeText(dir / "s-2-3.f32", bad);
  refused(merge(dir, "m.f32", quote("s-{shard}-{count}.f32")), "SHARD[2]",
          "does not verify against its shard record");
  refused(merge(dir, "m.f32", "s-1-3.f32 s-2-3.f32 s-3-3.f32"), "SHARD[2]", "'s-2-3.f32' has another SHA-256");
  writeText(dir / "s-2-3.f32", good);
  // A broken record is refused, naming it.
  const std::string rec = readText(dir / "s-3-3.f32.shard.json");
  writeText(dir / "s-3-3.f32.shard.json", "{\"format\": 1}");
  refused(merge(dir, "m.f32", quote("s-{shard}-{count}.f32")), "SHARD[3]", "its shard record");
  writeText(dir / "s-3-3.f32.shard.json", rec);
  ASSERT_EQ(merge(dir, "m.f32", quote("s-{shard}-{count}.f32")).rc, 0);
}

TEST(CliShardRecord, CsvMergeSeesAMissingLastShardThroughTheRecords) {
  ScratchDir dir("shard_merge_csv");
  for (int k = 1; k <= 3; ++k) ASSERT_EQ(sample(dir, "c" + std::to_string(k) + ".csv", "-q --shard " + std::to_string(k) + "/3").rc, 0);
  const CliResult r = merge(dir, "m.csv", "c1.csv c2.csv");
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "shapespline: error: SHARD[1]: is shard 1/3 of a job of 3 shards (its shard record), but 2 were given"))
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "m.csv"));
}

}  // namespace
}  // namespace shapespline::test
