// Issue 12, input limits at the command line: deep nesting, huge values, special files, oversized
// files, many keys, long arrays and many samples in every JSON input (model, `eval --at`,
// `extend --to-curve`) fail with exit 2 and a short message naming the field and the limit; no
// input crashes, blocks or exhausts memory. CLI11 argument errors use the same message format.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <chrono>
#include <filesystem>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// `shapespline <args>` in `scratch`, killed after `seconds` (rc 124 then), with the address space
// limited to `memoryKiB` (0: unlimited) so that an unbounded read fails instead of exhausting memory.
CliResult runBounded(const std::string& args, const fs::path& scratch, int seconds = 20, long memoryKiB = 0) {
  const auto out = scratch / "_stdout.txt", err = scratch / "_stderr.txt";
  std::string cmd =
      "cd " + quote(scratch.string()) + " && timeout -s KILL " + std::to_string(seconds) + " bash -c " +
      quote((memoryKiB > 0 ? "ulimit -v " + std::to_string(memoryKiB) + "; " : std::string()) + "exec \"$0\" \"$@\"") +
      " " + quote(SHAPESPLINE_CLI) + " " + args + " >" + quote(out.string()) + " 2>" + quote(err.string());
  return runCaptured(cmd, out, err);
}

// One error line (plus at most a usage hint): nothing of the input is echoed at length.
void expectShortError(const CliResult& r, const std::string& field, const std::string& rule) {
  EXPECT_EQ(r.rc, 2) << r.err.substr(0, 400);
  EXPECT_TRUE(contains(r.err, "shapespline: error: " + field)) << r.err.substr(0, 400);
  EXPECT_TRUE(contains(r.err, rule)) << r.err.substr(0, 400);
  EXPECT_LT(r.err.size(), 400u) << r.err.substr(0, 400);
}

std::string nested(size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

// ---- Depth: 100k levels overflowed the stack (a recursive dump() in the error path) ------------

TEST(InputLimits, DeeplyNestedModelIsRefused) {
  ScratchDir dir("limits_deep_model");
  writeText(dir / "m.json", "{\"kind\": \"curve\", \"construction\": \"bspline\", \"order\": 3, \"points\": [" +
                                nested(100'000) + "]}");
  const CliResult r = runBounded("sample m.json -o out.ply --device cpu", dir.path());
  expectShortError(r, "points[0]", "JSON nesting is limited to 64 levels");
  EXPECT_FALSE(fs::exists(dir / "out.ply"));
}

TEST(InputLimits, DeeplyNestedValueOfAnUnknownKeyIsRefused) {
  ScratchDir dir("limits_deep_key");
  writeText(dir / "m.json", "{\"kind\": " + nested(100'000) + "}");
  expectShortError(runBounded("sample m.json -o out.ply --device cpu", dir.path()), "kind",
                   "JSON nesting is limited to 64 levels");
}

TEST(InputLimits, DeeplyNestedAtFileIsRefused) {
  ScratchDir dir("limits_deep_at");
  writeText(dir / "at.json", "{\"samples\": [" + nested(100'000) + "]}");
  const CliResult r = runBounded("eval " + quote(exampleModel("open_aeb.json")) + " --at at.json --device cpu", dir.path());
  expectShortError(r, "--at.samples[0]", "JSON nesting is limited to 64 levels");
  EXPECT_TRUE(r.out.empty());
}

TEST(InputLimits, DeeplyNestedTargetCurveIsRefused) {
  ScratchDir dir("limits_deep_curve");
  writeText(dir / "c.json", "[" + nested(100'000) + "]");
  const CliResult r =
      runBounded("extend " + quote(exampleModel("bspline_surface.json")) + " --to-curve c.json -o e.json", dir.path());
  expectShortError(r, "--to-curve[0][0]", "JSON nesting is limited to 64 levels");
  EXPECT_FALSE(fs::exists(dir / "e.json"));
}

// Nesting within the limit but wrong: the message shows a bounded part of the value.
TEST(InputLimits, NestedValuesInErrorsAreShortened) {
  ScratchDir dir("limits_nested_value");
  writeText(dir / "at.json", "{\"samples\": [" + nested(60) + "]}");
  expectShortError(runBounded("eval " + quote(exampleModel("open_aeb.json")) + " --at at.json --device cpu", dir.path()),
                   "--at.samples[0]", "must be an object (got [[[[");
  writeText(dir / "c.json", "[" + nested(60) + "]");
  expectShortError(
      runBounded("extend " + quote(exampleModel("bspline_surface.json")) + " --to-curve c.json -o e.json", dir.path()),
      "--to-curve[0].points[0]", "must be [x, y, z] (got [[[[");
}

// ---- Values: error messages never serialize unbounded input ----------------------------------

TEST(InputLimits, HugeValuesAreNotEchoed) {
  ScratchDir dir("limits_huge_value");
  std::string big = "[";
  for (int i = 0; i < 200'000; ++i) big += (i ? ",1" : "1");
  big += "]";
  writeText(dir / "at.json", "{\"samples\": [" + big + "]}");
  expectShortError(runBounded("eval " + quote(exampleModel("open_aeb.json")) + " --at at.json --device cpu", dir.path()),
                   "--at.samples[0]", "must be an object (got [1,1,1");
  writeText(dir / "at2.json", "{\"samples\": [{\"span\": 0, \"t\": " + big + "}]}");
  expectShortError(runBounded("eval " + quote(exampleModel("open_aeb.json")) + " --at at2.json --device cpu", dir.path()),
                   "--at.samples[0].t", "must be a number");
  writeText(dir / "c.json", "[[1, 2, \"" + std::string(300'000, 'x') + "\"]]");
  expectShortError(
      runBounded("extend " + quote(exampleModel("bspline_surface.json")) + " --to-curve c.json -o e.json", dir.path()),
      "--to-curve[0].points[0]", "must hold finite numbers");
  writeText(dir / "m.json",
            "{\"kind\": \"curve\", \"construction\": \"bspline\", \"order\": 3, \"points\": " + big + "}");
  expectShortError(runBounded("sample m.json -o out.ply --device cpu", dir.path()), "points[0]", "a point is");
}

TEST(InputLimits, HugeCommandLineValuesAreNotEchoed) {
  ScratchDir dir("limits_huge_arg");
  const std::string junk(100'000, '7');
  expectShortError(
      runBounded("extend " + quote(exampleModel("clamped_bspline.json")) + " --to 1,2,x" + junk + " -o e.json", dir.path()),
      "--to[0]", "expected comma-separated numbers");
  expectShortError(
      runBounded("sample " + quote(exampleModel("open_aeb.json")) + " -o out.ply --threads x" + junk, dir.path()),
      "--threads", "could not convert");
  // Values the subcommands check themselves are cut in the one error printer (main.cpp).
  expectShortError(runBounded("sample " + quote(exampleModel("surface_aeb.json")) + " -o out.ply --grid 1" + junk, dir.path()),
                   "--grid", "expected a positive integer");
  expectShortError(runBounded("sample " + quote(exampleModel("open_aeb.json")) + " -o out.ply --device x" + junk, dir.path()),
                   "--device", "");
}

// ---- Files: special files and size --------------------------------------------------------------

TEST(InputLimits, DevZeroModelIsRefusedWithoutReading) {
  ScratchDir dir("limits_dev_zero");
  // 4 GiB of address space: before the fix the read ran into it (bad_alloc) instead of refusing.
#if defined(__SANITIZE_ADDRESS__)
  const long memoryKiB = 0;  // ASan reserves terabytes of shadow address space: no ulimit -v
#else
  const long memoryKiB = 4L << 20;
#endif
  const CliResult r = runBounded("sample /dev/zero -o out.ply --device cpu", dir.path(), 20, memoryKiB);
  expectShortError(r, "MODEL", "is not a regular file (it is a character device)");
}

TEST(InputLimits, FifoInputsAreRefusedWithoutBlocking) {
  ScratchDir dir("limits_fifo");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  expectShortError(runBounded("sample fifo -o out.ply --device cpu", dir.path(), 10), "MODEL",
                   "is not a regular file (it is a FIFO)");
  // A .json name is first looked into for a part manifest's format: that look must not block either.
  ASSERT_EQ(::mkfifo((dir / "fifo.json").c_str(), 0600), 0);
  expectShortError(runBounded("sample fifo.json -o out.ply --device cpu", dir.path(), 10), "MODEL",
                   "is not a regular file (it is a FIFO)");
  expectShortError(runBounded("eval " + quote(exampleModel("open_aeb.json")) + " --at fifo --device cpu", dir.path(), 10),
                   "--at", "is not a regular file (it is a FIFO)");
  expectShortError(
      runBounded("extend " + quote(exampleModel("bspline_surface.json")) + " --to-curve fifo -o e.json", dir.path(), 10),
      "--to-curve[0]", "is not a regular file (it is a FIFO)");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

TEST(InputLimits, DirectoryModelIsRefused) {
  ScratchDir dir("limits_dir");
  fs::create_directories(dir / "sub");
  // `sample` reads a folder's .json models (several models, one process); an empty one is refused,
  // and so is a folder where one model file is expected.
  expectShortError(runBounded("sample sub -o '{stem}.ply' --device cpu", dir.path()), "MODEL",
                   "the folder holds no .json model");
  fs::create_directories(dir / "sub" / "m.json");
  expectShortError(runBounded("render sub/m.json -o out.png", dir.path()), "MODEL",
                   "is not a regular file (it is a directory)");
}

TEST(InputLimits, OversizedFilesAreRefusedBeforeReading) {
  ScratchDir dir("limits_big");
  { std::ofstream o(dir / "big.json"); }
  fs::resize_file(dir / "big.json", (32u << 20) + 1);  // sparse: costs no disk
  expectShortError(runBounded("sample big.json -o out.ply --device cpu", dir.path()), "MODEL",
                   "input files are limited to 32 MiB (33554432 bytes); a model's big point arrays go in .npy files beside it "
                   "(\"points\": {\"npy\": \"points.npy\"}, docs/format.md) (got 33554433 bytes)");
  expectShortError(runBounded("eval " + quote(exampleModel("open_aeb.json")) + " --at big.json --device cpu", dir.path()),
                   "--at", "input files are limited to 32 MiB");
  expectShortError(
      runBounded("extend " + quote(exampleModel("bspline_surface.json")) + " --to-curve big.json -o e.json", dir.path()),
      "--to-curve[0]", "input files are limited to 32 MiB");
}

TEST(InputLimits, MissingFilesStillExitTwo) {
  ScratchDir dir("limits_missing");
  expectShortError(runBounded("sample none.json -o out.ply --device cpu", dir.path()), "MODEL", "cannot read");
  expectShortError(runBounded("eval " + quote(exampleModel("open_aeb.json")) + " --at none.json --device cpu", dir.path()),
                   "--at", "cannot open the file");
}

// ---- Counts: keys, array lengths, samples -------------------------------------------------------

// Seconds for `shapespline sample` to refuse the model `makeDoc(n)` (best of 3), after checking
// the message: the growth from n to 8n tells a linear parser (about 8x, less with the process
// start-up) from a quadratic one (64x). A ratio in one run, so slow machines and sanitizers pass.
template <class MakeDoc>
double secondsToRefuse(const ScratchDir& dir, size_t n, MakeDoc makeDoc, const std::string& field,
                       const std::string& rule) {
  writeText(dir / "m.json", makeDoc(n));
  double best = 1e9;
  for (int rep = 0; rep < 3; ++rep) {
    const auto start = std::chrono::steady_clock::now();
    const CliResult r = runBounded("sample m.json -o out.ply --device cpu", dir.path(), 120);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    expectShortError(r, field, rule);
  }
  return best;
}

TEST(InputLimits, ManyKeysAreRefusedInLinearTime) {
  ScratchDir dir("limits_keys");
  // Before the fix the duplicate-key check was quadratic: 27 s for 100k keys.
  const auto doc = [](size_t n) {
    std::string d = "{\"kind\": \"curve\"";
    for (size_t i = 0; i < n; ++i) d += ", \"k" + std::to_string(i) + "\": 0";
    return d + "}";
  };
  const std::string rule = "JSON objects are limited to 1024 keys (got more than 1024 keys)";
  const double small = secondsToRefuse(dir, 12'500, doc, "k1023", rule);
  const double large = secondsToRefuse(dir, 100'000, doc, "k1023", rule);
  EXPECT_LT(large, 24 * small) << small << " s -> " << large << " s for 8x the keys";
}

// nlohmann's parser callback (the duplicate-key check used one) rescans the enclosing array after
// every object: 100k objects in a model took 14 s.
TEST(InputLimits, ManyObjectsAreParsedInLinearTime) {
  ScratchDir dir("limits_objects");
  const auto doc = [](size_t n) {
    std::string d = "{\"kind\": \"curve\", \"construction\": \"bspline\", \"order\": 3, \"points\": [{}";
    for (size_t i = 0; i < n; ++i) d += ",{}";
    return d + "]}";
  };
  const double small = secondsToRefuse(dir, 12'500, doc, "points[0]", "a point is");
  const double large = secondsToRefuse(dir, 100'000, doc, "points[0]", "a point is");
  EXPECT_LT(large, 24 * small) << small << " s -> " << large << " s for 8x the objects";
}

TEST(InputLimits, DuplicateKeysAmongManyAreFound) {
  ScratchDir dir("limits_dup");
  std::string doc = "{\"kind\": \"curve\", \"construction\": \"bspline\", \"points\": [{";
  for (int i = 0; i < 1000; ++i) doc += (i ? ", \"k" : "\"k") + std::to_string(i) + "\": 0";
  writeText(dir / "m.json", doc + ", \"k500\": 1}]}");
  expectShortError(runBounded("sample m.json -o out.ply --device cpu", dir.path()), "points[0].k500",
                   "duplicate key in a JSON object");
}

TEST(InputLimits, LongArraysAreRefused) {
  ScratchDir dir("limits_array");
  std::string doc = "{\"kind\": \"curve\", \"construction\": \"bspline\", \"order\": 3, \"points\": [0";
  doc.reserve(doc.size() + 2 * (4u << 20) + 16);
  for (size_t i = 0; i < (4u << 20); ++i) doc += ",0";
  writeText(dir / "m.json", doc + "]}");
  expectShortError(runBounded("sample m.json -o out.ply --device cpu", dir.path()), "points[4194304]",
                   "JSON arrays are limited to 4194304 elements");
}

TEST(InputLimits, TooManySamplesAreRefused) {
  ScratchDir dir("limits_samples");
  std::string doc = "{\"samples\": [{}";
  for (int i = 0; i < 1'000'000; ++i) doc += ",{}";
  writeText(dir / "at.json", doc + "]}");
  const CliResult r = runBounded("eval " + quote(exampleModel("open_aeb.json")) + " --at at.json --device cpu", dir.path());
  expectShortError(r, "--at", "a sample list holds at most 1000000 samples (got 1000001 samples)");
}

// ---- CLI11 argument errors: the same "shapespline: error: <option>: <reason>" format, exit 2 ------

TEST(ArgumentErrors, ConversionErrorsNameTheOption) {
  ScratchDir dir("args_conversion");
  const std::string m = quote(exampleModel("open_aeb.json"));
  for (const auto& [args, option] : std::vector<std::pair<std::string, std::string>>{
           {"sample " + m + " -o out.ply --threads abc", "--threads"},
           {"sample " + m + " -o out.ply --chunk-points 1e99", "--chunk-points"}}) {
    const CliResult r = runBounded(args, dir.path());
    EXPECT_EQ(r.rc, 2) << args;
    EXPECT_EQ(r.err.rfind("shapespline: error: " + option + ": could not convert", 0), 0u) << r.err;
    EXPECT_TRUE(contains(r.err, "--help")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out.ply"));
  }
}

TEST(ArgumentErrors, OtherParseErrorsUseTheErrorPrefix) {
  ScratchDir dir("args_other");
  const std::string m = quote(exampleModel("open_aeb.json"));
  for (const auto& [args, start] : std::vector<std::pair<std::string, std::string>>{
           {"sample " + m + " -o out.ply --threads", "shapespline: error: --threads: "},
           {"sample -o out.ply", "shapespline: error: MODEL: "},
           {"sample " + m + " -o out.ply --bogus", "shapespline: error: arguments: "},
           {"frobnicate", "shapespline: error: arguments: "},
           {"", "shapespline: error: arguments: "}}) {
    const CliResult r = runBounded(args, dir.path());
    EXPECT_EQ(r.rc, 2) << args;
    EXPECT_EQ(r.err.rfind(start, 0), 0u) << args << " -> " << r.err;
    EXPECT_TRUE(contains(r.err, "--help")) << r.err;
  }
}

TEST(ArgumentErrors, HelpIsUnchanged) {
  ScratchDir dir("args_help");
  const CliResult r = runBounded("sample --help", dir.path());
  EXPECT_EQ(r.rc, 0);
  EXPECT_TRUE(contains(r.out, "Usage:")) << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;
}

}  // namespace
}  // namespace shapespline::test
