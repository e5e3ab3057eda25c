// Issue 12, requirement 5: memory is bounded for any job. A patch (span) larger than a chunk is
// cut into rows of samples, so `sample` on one patch at --grid 4096 (or 65536) holds two chunks of
// planes and not the whole patch, on the CPU and on the Vulkan path. The peak RSS of the child
// process (wait4's ru_maxrss) is checked against the bound docs/performance.md states. (That the
// bytes do not depend on where the rows are cut: tests/cli/memory_bound_test.cpp.)
#include "cli/cli_runner.h"
#include "cli/output_checks.h"
#include "cli/one_patch_models.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// The bounds docs/performance.md states (whole process, peak RSS): the CPU path holds 2 chunks of
// fp64 planes (default 2^18 points: 6 MiB per field and chunk) plus the writer's buffer; the Vulkan path
// adds the driver (lavapipe and its LLVM: ~70-120 MB before any job) to 2 slots of planes
// (4 MiB per field and slot). Before rows were split, one patch at 4096 x 4096 took 796 MB on the
// CPU and failed on lavapipe (its 201 MB fp32 plane exceeds maxStorageBufferRange, 128 MiB).
constexpr long kCpuBoundKiB = 128 * 1024;
constexpr long kVulkanBoundKiB = 200 * 1024;

struct Measured {
  int rc = -1;
  long maxRssKiB = 0;
  std::string err;
};

// Runs `shapespline args...` in `dir` as a direct child (no shell in between, so ru_maxrss is the
// tool's own peak), optionally with a file size limit (bytes; the tool then fails with exit 3).
Measured runMeasured(const std::vector<std::string>& args, const fs::path& dir, rlim_t fileLimit = RLIM_INFINITY) {
  const fs::path errPath = dir / "_stderr.txt";
  std::vector<std::string> argv = {SHAPESPLINE_CLI};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> cargv;
  for (auto& a : argv) cargv.push_back(a.data());
  cargv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (chdir(dir.c_str()) != 0) _exit(126);
    const int null = open("/dev/null", O_WRONLY);
    const int err = open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (null < 0 || err < 0) _exit(126);
    dup2(null, 1);
    dup2(err, 2);
    if (fileLimit != RLIM_INFINITY) {
      const rlimit lim{fileLimit, fileLimit};
      setrlimit(RLIMIT_FSIZE, &lim);
      signal(SIGXFSZ, SIG_IGN);  // the write then fails with EFBIG instead of killing the tool
    }
    execv(cargv[0], cargv.data());
    _exit(127);
  }
  Measured m;
  int status = 0;
  rusage usage{};
  if (pid > 0 && wait4(pid, &status, 0, &usage) == pid) {
    m.rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    m.maxRssKiB = usage.ru_maxrss;
  }
  m.err = readText(errPath);
  fs::remove(errPath);
  return m;
}

// One patch at --grid 4096 (16.8 M points, 201 MB of fp32 records) to a raw file.
void expectOnePatchBounded(const std::string& device, long boundKiB, const std::string& tag) {
  ScratchDir dir("mem_" + tag);
  writeText(dir / "patch.json", kOnePatch);
  std::vector<std::string> args = {"sample", "patch.json", "-o", "p.f32", "--grid", "4096", "-q"};
  for (const auto& a : {std::string("--device"), device}) args.push_back(a);
  if (device == "vulkan") args.push_back("--require-device");
  const Measured m = runMeasured(args, dir.path());
  ASSERT_EQ(m.rc, 0) << m.err;
  EXPECT_EQ(fs::file_size(dir / "p.f32"), size_t{4096} * 4096 * 3 * 4);
  EXPECT_LE(m.maxRssKiB, boundKiB) << tag << ": one patch at --grid 4096 took " << m.maxRssKiB / 1024 << " MiB";
  std::printf("[ measured ] %s: one patch at --grid 4096, peak RSS %ld MiB (bound %ld MiB)\n", tag.c_str(),
              m.maxRssKiB / 1024, boundKiB / 1024);
}

TEST(MemoryBoundRss, CpuOnePatchAtGrid4096) { expectOnePatchBounded("cpu", kCpuBoundKiB, "cpu"); }

TEST(MemoryBoundRss, VulkanOnePatchAtGrid4096) {
  REQUIRE_VULKAN();
  expectOnePatchBounded("vulkan", kVulkanBoundKiB, "vulkan");
}

// --grid 65536 (4.3e9 points, 51 GB of records) is accepted and streams in bounded memory: it runs
// until a 64 MiB file size limit stops it (exit 3, nothing left behind). Before, the first chunk
// alone asked for 103 GB ("out of memory" on the CPU, "exceeds maxStorageBufferRange" on Vulkan).
void expectGrid65536Bounded(const std::string& device, long boundKiB, const std::string& tag) {
  ScratchDir dir("mem65536_" + tag);
  writeText(dir / "patch.json", kOnePatch);
  std::vector<std::string> args = {"sample", "patch.json", "-o", "p.f32", "--grid", "65536", "-q", "--device", device};
  if (device == "vulkan") args.push_back("--require-device");
  const Measured m = runMeasured(args, dir.path(), rlim_t{64} << 20);
  EXPECT_EQ(m.rc, 3) << m.err;
  // It stopped at the file limit (a write error), not for lack of memory.
  EXPECT_NE(m.err.find("File too large"), std::string::npos) << m.err;
  EXPECT_EQ(m.err.find("memory"), std::string::npos) << m.err;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"patch.json"}) << "a partial or temporary file was left";
  EXPECT_LE(m.maxRssKiB, boundKiB) << tag << ": --grid 65536 took " << m.maxRssKiB / 1024 << " MiB";
  std::printf("[ measured ] %s: one patch at --grid 65536 until a 64 MiB file limit, peak RSS %ld MiB\n", tag.c_str(),
              m.maxRssKiB / 1024);
}

TEST(MemoryBoundRss, CpuGrid65536StreamsUntilTheFileLimit) { expectGrid65536Bounded("cpu", kCpuBoundKiB, "cpu"); }

TEST(MemoryBoundRss, VulkanGrid65536StreamsUntilTheFileLimit) {
  REQUIRE_VULKAN();
  expectGrid65536Bounded("vulkan", kVulkanBoundKiB, "vulkan");
}

// A curve span at the largest --samples: bounded as well (cut into sample ranges, whose bytes
// tests/cli/memory_bound_test.cpp checks).
TEST(MemoryBoundRss, CpuOneSpanAtMaxSamples) {
  ScratchDir dir("mem_span");
  writeText(dir / "curve.json", kOneSpan);
  const Measured m = runMeasured({"sample", "curve.json", "-o", "c.f32", "--samples", "65536", "--derivatives",
                                  "--chunk-points", "1000", "-q", "--device", "cpu"},
                                 dir.path());
  ASSERT_EQ(m.rc, 0) << m.err;
  EXPECT_EQ(fs::file_size(dir / "c.f32"), size_t{65536} * 9 * 4);
  EXPECT_LE(m.maxRssKiB, kCpuBoundKiB);
}

// A .npy file (fp64, C order) of `shape` opened for its values, its header written; null on failure.
std::FILE* openNpy(const fs::path& path, const std::string& shape) {
  std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': " + shape + ", }";
  while ((10 + dict.size() + 1) % 64 != 0) dict += ' ';
  dict += '\n';
  const std::string head = std::string("\x93NUMPY\x01\x00", 8) + char(dict.size() & 0xff) + char(dict.size() >> 8) + dict;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f) std::fwrite(head.data(), 1, head.size(), f);
  return f;
}

// Issue 31: a big net in a .npy file is never held where it need not be. A shard with no items
// streams the file through its rules and the job fingerprint (io/streamed_net.h); a job to a raw
// file samples it in bands as it streams (io/streamed_bands.h), a one-item shard as the whole job.
// The shards peak under a third of the net's bytes, the whole job (bands of up to 16 MiB of net,
// held as read and as a band surface, and the sampler's buffers) under 64 MiB, where a shard of
// one item to PLY (whose header carries the metadata, so it builds the surface first) holds more
// than the whole net.
TEST(MemoryBoundRss, ABigNetIsNotHeldWhereItStreams) {
  ScratchDir dir("mem_big_net");
  constexpr int kN = 2000;  // 96 MB of fp64 points
  {
    std::FILE* f = openNpy(dir / "net.npy", "(" + std::to_string(kN) + ", " + std::to_string(kN) + ", 3)");
    ASSERT_NE(f, nullptr);
    std::vector<double> row(3 * kN);
    for (int i = 0; i < kN; ++i) {
      for (int j = 0; j < kN; ++j) {
        double* p = &row[3 * size_t(j)];
        p[0] = i, p[1] = j, p[2] = std::sin(0.01 * i) * std::cos(0.02 * j);
      }
      std::fwrite(row.data(), sizeof(double), row.size(), f);
    }
    ASSERT_EQ(std::fclose(f), 0);
  }
  writeText(dir / "m.json",
            R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, "alpha": 0.5, "points": {"npy": "net.npy"}})");
  const long netKiB = long(fs::file_size(dir / "net.npy") / 1024);
  auto run = [&](const std::string& out, const std::string& shard) {
    std::vector<std::string> args = {"sample", "m.json", "--grid", "2", "--device", "cpu", "-q", "-o", out};
    if (!shard.empty()) args.insert(args.end(), {"--shard", shard});
    return runMeasured(args, dir.path());
  };
  // 1999² patches in 4,000,000 shards: shard 1 has none, the last one has one.
  const Measured empty = run("empty.f32", "1/4000000"), one = run("one.f32", "4000000/4000000"),
                 whole = run("whole.f32", ""), built = run("one.ply", "4000000/4000000");
  for (const Measured* m : {&empty, &one, &whole, &built}) ASSERT_EQ(m->rc, 0) << m->err;
  EXPECT_EQ(fs::file_size(dir / "empty.f32"), 0u);
  EXPECT_EQ(fs::file_size(dir / "one.f32"), 4u * 3 * 4);
  EXPECT_EQ(fs::file_size(dir / "whole.f32"), uint64_t{1999} * 1999 * 4 * 3 * 4);
  for (const auto& [m, what] : {std::pair{&empty, "an empty shard"}, std::pair{&one, "a one-item shard"}})
    EXPECT_LE(m->maxRssKiB, netKiB / 3) << what << " held " << m->maxRssKiB / 1024 << " MiB of a " << netKiB / 1024
                                        << " MiB net";
  EXPECT_LE(whole.maxRssKiB, 64 * 1024) << "the whole job held " << whole.maxRssKiB / 1024 << " MiB of a "
                                        << netKiB / 1024 << " MiB net";
  EXPECT_GT(built.maxRssKiB, netKiB) << "the shard that builds the surface should hold the net";
  std::printf("[ measured ] a %ld MiB net: an empty shard peaks at %ld MiB, a one-item shard at %ld MiB, the whole "
              "job in bands at %ld MiB; a one-item PLY shard (built) at %ld MiB\n",
              netKiB / 1024, empty.maxRssKiB / 1024, one.maxRssKiB / 1024, whole.maxRssKiB / 1024,
              built.maxRssKiB / 1024);
}

// Issue 53: a big α-EB curve in a .npy file streams the same way, in bands of spans
// (io/streamed_bands.h streamCurveSpans). Read whole, a curve cost about 15 times its file (the
// points, the extended polygon, nodes, V, α, the layout's lists). An empty shard and a one-span
// shard peak under 64 MiB, and the whole job to .f32 under 1.5 times the file plus 100 MiB (it
// holds bands of up to 16 MiB of net and the sampler's buffers; the bound scales with the file).
TEST(MemoryBoundRss, ABigCurveIsNotHeldWhereItStreams) {
  ScratchDir dir("mem_big_curve");
  constexpr size_t kN = 1'500'000;  // 24 MB of 2-D fp64 points
  {
    std::FILE* f = openNpy(dir / "curve.npy", "(" + std::to_string(kN) + ", 2)");
    ASSERT_NE(f, nullptr);
    std::vector<double> xy(2 * 4096);
    for (size_t first = 0; first < kN; first += 4096) {
      const size_t n = std::min<size_t>(4096, kN - first);
      for (size_t k = 0; k < n; ++k) {
        const double t = 1e-3 * static_cast<double>(first + k);
        xy[2 * k] = std::cos(t) * (1.0 + 1e-3 * t), xy[2 * k + 1] = std::sin(1.3 * t) * t;
      }
      std::fwrite(xy.data(), sizeof(double), 2 * n, f);
    }
    ASSERT_EQ(std::fclose(f), 0);
  }
  writeText(dir / "m.json", R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, "alpha": 0.5, )"
                            R"("points": {"npy": "curve.npy"}})");
  const long fileKiB = long(fs::file_size(dir / "curve.npy") / 1024);
  auto run = [&](const std::string& out, const std::string& shard) {
    std::vector<std::string> args = {"sample", "m.json", "--samples", "4", "--device", "cpu", "-q", "-o", out};
    if (!shard.empty()) args.insert(args.end(), {"--shard", shard});
    return runMeasured(args, dir.path());
  };
  // kN - 1 spans in kN - 1 shards: the last has one; in 10^9 shards the first has none.
  const std::string last = std::to_string(kN - 1);
  const Measured empty = run("empty.f32", "1/1000000000"), one = run("one.f32", last + "/" + last),
                 whole = run("whole.f32", "");
  for (const Measured* m : {&empty, &one, &whole}) ASSERT_EQ(m->rc, 0) << m->err;
  EXPECT_EQ(fs::file_size(dir / "empty.f32"), 0u);
  EXPECT_EQ(fs::file_size(dir / "one.f32"), 4u * 3 * 4);  // 2-D points carry z = 0
  EXPECT_EQ(fs::file_size(dir / "whole.f32"), uint64_t{kN - 1} * 4 * 3 * 4);
  for (const auto& [m, what] : {std::pair{&empty, "an empty shard"}, std::pair{&one, "a one-span shard"}})
    EXPECT_LE(m->maxRssKiB, 64 * 1024) << what << " held " << m->maxRssKiB / 1024 << " MiB of a " << fileKiB / 1024
                                       << " MiB curve";
  EXPECT_LE(whole.maxRssKiB, fileKiB * 3 / 2 + 100 * 1024)
      << "the whole job held " << whole.maxRssKiB / 1024 << " MiB of a " << fileKiB / 1024 << " MiB curve";
  std::printf("[ measured ] a %ld MiB curve: an empty shard peaks at %ld MiB, a one-span shard at %ld MiB, the whole "
              "job to .f32 at %ld MiB\n",
              fileKiB / 1024, empty.maxRssKiB / 1024, one.maxRssKiB / 1024, whole.maxRssKiB / 1024);
}

}  // namespace
}  // namespace shapespline::test
