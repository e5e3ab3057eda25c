// Issue 29 at the command line: no output ever replaces a file the command reads (compared as
// files: other spellings, symlinks and hard links included); large and tiny nets have one outcome
// on every device; a query outside the model is the user's error (exit 2); `demo` commits its
// folder as one set; an option that does not apply to the input is refused, never ignored.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <unistd.h>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// `shapespline ARGS` run in `dir` (relative paths resolve there).
CliResult runIn(const ScratchDir& dir, const std::string& args) { return runCli(args, dir.path(), dir.path()); }

// The command was refused before any work: exit 2, a message naming `option` and `input`, nothing
// on stdout, the input byte for byte as it was and no file beside it but `keep`.
void expectRefused(const CliResult& r, const ScratchDir& dir, const std::string& option, const std::string& input,
                   const fs::path& inputPath, const std::string& inputBytes, size_t filesBefore,
                   const std::string& what) {
  EXPECT_EQ(r.rc, 2) << what << ": " << r.err;
  EXPECT_TRUE(contains(r.err, option + ": ")) << what << ": " << r.err;
  EXPECT_TRUE(contains(r.err, "is the same file as " + input)) << what << ": " << r.err;
  EXPECT_TRUE(contains(r.err, "which this command reads")) << what << ": " << r.err;
  EXPECT_TRUE(r.out.empty()) << what << ": " << r.out;
  EXPECT_EQ(readText(inputPath), inputBytes) << what << ": the input was changed";
  EXPECT_EQ(dir.entries().size(), filesBefore) << what << ": a file was left behind";
}

// ---- An output never replaces an input ------------------------------------------------------------

TEST(CliOutputIsNotAnInput, SampleRefusesItsModelAsDataSidecarBufferOrRecord) {
  ScratchDir dir("io_sample");
  const std::string model = readText(exampleModel("surface_aeb.json"));
  struct Case {
    std::string modelName, args;
  };
  // The sidecar of a raw or .npy file, the buffer of a .gltf and a shard's record are outputs too.
  const std::vector<Case> cases = {{"m.f32.json", "-o m.f32"},
                                   {"m.npy.json", "-o m.npy"},
                                   {"m.bin", "-o m.gltf"},
                                   {"m.obj", "-o m.obj"},
                                   {"m.obj", "-o ./sub/../m.obj"},
                                   {"m.f32.shard.json", "-o m.f32 --shard 1/2"}};
  fs::create_directories(dir / "sub");
  for (const Case& c : cases) {
    writeText(dir / c.modelName, model);
    const size_t before = dir.entries().size();
    const CliResult r = runIn(dir, "sample " + c.modelName + " " + c.args + " --grid 3 --device cpu");
    expectRefused(r, dir, "-o", "MODEL", dir / c.modelName, model, before, c.args);
    fs::remove(dir / c.modelName);
  }
}

TEST(CliOutputIsNotAnInput, ASymlinkOrAHardLinkToTheModelIsTheModel) {
  ScratchDir dir("io_links");
  const std::string model = readText(exampleModel("surface_aeb.json"));
  writeText(dir / "m.json", model);
  fs::create_symlink(dir / "m.json", dir / "soft.ply");
  fs::create_hard_link(dir / "m.json", dir / "hard.ply");
  for (const char* out : {"soft.ply", "hard.ply"}) {
    const size_t before = dir.entries().size();
    const CliResult r = runIn(dir, std::string("sample m.json -o ") + out + " --grid 3 --device cpu");
    expectRefused(r, dir, "-o", "MODEL", dir / "m.json", model, before, out);
    EXPECT_TRUE(fs::is_symlink(dir / "soft.ply"));
  }
  // Another file with the same bytes is not the model: written as usual.
  writeText(dir / "copy.ply", model);
  EXPECT_EQ(runIn(dir, "sample m.json -o copy.ply --grid 3 --device cpu -q").rc, 0);
}

TEST(CliOutputIsNotAnInput, ExtendGbFitAndMergeRefuseTheirInputs) {
  ScratchDir dir("io_others");
  const std::string curve = readText(exampleModel("clamped_bspline.json"));
  writeText(dir / "c.json", curve);
  size_t before = dir.entries().size();
  expectRefused(runIn(dir, "extend c.json --to 10,2 -o c.json"), dir, "-o", "MODEL", dir / "c.json", curve, before,
                "extend -o");
  expectRefused(runIn(dir, "extend c.json --to 10,2 -o e.json --svg ./c.json"), dir, "--svg", "MODEL", dir / "c.json",
                curve, before, "extend --svg");

  const std::string surface = readText(exampleModel("bspline_surface.json"));
  const std::string target = readText(exampleModel("bspline_surface_target.json"));
  writeText(dir / "s.json", surface);
  writeText(dir / "t.json", target);
  before = dir.entries().size();
  expectRefused(runIn(dir, "extend s.json --to-curve t.json -o t.json"), dir, "-o", "--to-curve[0]", dir / "t.json",
                target, before, "extend --to-curve");

  const std::string gb = readText(exampleModel("gb_curve.json"));
  writeText(dir / "g.json", gb);
  before = dir.entries().size();
  expectRefused(runIn(dir, "gb-fit g.json --span 1 --through 1,1 -o g.json"), dir, "-o", "MODEL", dir / "g.json", gb,
                before, "gb-fit");

  // merge: the output may not be a shard, a shard's sidecar or a shard's record.
  for (int k = 1; k <= 2; ++k) {
    ASSERT_EQ(runIn(dir, "sample s.json -o p" + std::to_string(k) + ".f32 --grid 3 --device cpu -q --shard " +
                             std::to_string(k) + "/2")
                  .rc,
              0);
  }
  const std::string shard = readText(dir / "p2.f32");
  before = dir.entries().size();
  expectRefused(runIn(dir, "merge p1.f32 p2.f32 -o p2.f32"), dir, "-o", "SHARD[2]", dir / "p2.f32", shard, before,
                "merge onto a shard");
  fs::create_symlink(dir / "p1.f32.json", dir / "q.f32.json");
  const std::string sidecar = readText(dir / "p1.f32.json");
  before = dir.entries().size();
  expectRefused(runIn(dir, "merge p1.f32 p2.f32 -o q.f32"), dir, "-o", "SHARD[1] sidecar", dir / "p1.f32.json",
                sidecar, before, "merge onto a shard's sidecar");
  EXPECT_EQ(runIn(dir, "merge p1.f32 p2.f32 -o whole.f32").rc, 0);
}

TEST(CliOutputIsNotAnInput, RenderRefusesItsModel) {
  REQUIRE_VULKAN();
  ScratchDir dir("io_render");
  const std::string model = readText(exampleModel("surface_aeb.json"));
  writeText(dir / "mm.json", model);
  const size_t before = dir.entries().size();
  expectRefused(runIn(dir, "render mm.json -o mm.json --size 64x64"), dir, "-o", "MODEL", dir / "mm.json", model,
                before, "render");
}

TEST(CliOutputIsNotAnInput, ViewRefusesAScreenshotOverItsModelOrScript) {
  ScratchDir dir("io_view");
  const std::string model = readText(exampleModel("surface_aeb.json"));
  writeText(dir / "m.png", model);
  writeText(dir / "s.png", "frames 1\nscreenshot s.png\nquit\n");
  writeText(dir / "t.txt", "frames 1\nscreenshot m.png\nquit\n");
  const CliResult probe = runIn(dir, "view m.png --script t.txt");
  if (contains(probe.err, "this build has no viewer")) GTEST_SKIP() << "no viewer in this build";
  for (const auto& [script, input] : {std::pair{"t.txt", "MODEL"}, std::pair{"s.png", "--script"}}) {
    const CliResult r = runIn(dir, std::string("view m.png --script ") + script + " --screenshot-dir .");
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_TRUE(contains(r.err, std::string("is the same file as ") + input)) << r.err;
  }
  EXPECT_EQ(readText(dir / "m.png"), model);
}

// ---- One outcome on every device ------------------------------------------------------------------

// A surface net of `rows` x `rows` wavy points scaled by `scale` (JSON numbers, 17 digits).
std::string surfaceModel(double scale, int rows = 5) {
  std::string pts = "[";
  char buf[128];
  for (int i = 0; i < rows; ++i) {
    pts += i ? ", [" : "[";
    for (int j = 0; j < rows; ++j) {
      const double z = 0.5 * std::sin(1.3 * i + 0.7 * j);
      std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g, %.17g]", j ? ", " : "", i * scale, j * scale, z * scale);
      pts += buf;
    }
    pts += "]";
  }
  return R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, "lambda": -1, "alpha": 0.5, "closed": [false, false], "points": )" +
         pts + "]}";
}

std::string curveModel(double scale) {
  std::string pts = "[";
  char buf[128];
  for (int i = 0; i < 7; ++i) {
    std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g, %.17g]", i ? ", " : "", i * scale, std::sin(1.1 * i) * scale,
                  std::cos(0.9 * i) * scale);
    pts += buf;
  }
  return R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, "lambda": -1, "alpha": 0.5, "closed": false, "points": )" +
         pts + "]}";
}

// Largest |a - b| relative to the largest |b| of the same field (records of `perRecord` doubles,
// fields of 3), or inf when the sizes differ.
double worstRelative(const std::string& a, const std::string& b, size_t perRecord) {
  if (a.size() != b.size() || a.size() % 8) return INFINITY;
  const size_t n = a.size() / 8;
  auto at = [](const std::string& s, size_t i) {
    double v;
    std::memcpy(&v, s.data() + i * 8, 8);
    return v;
  };
  std::vector<double> scale(perRecord / 3, 0.0);
  for (size_t i = 0; i < n; ++i) scale[i % perRecord / 3] = std::max(scale[i % perRecord / 3], std::abs(at(b, i)));
  double worst = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double s = scale[i % perRecord / 3];
    if (s > 0) worst = std::max(worst, std::abs(at(a, i) - at(b, i)) / s);
  }
  return worst;
}

struct ExtremeCase {
  std::string tag, json, grid;
  size_t perRecord;
};

std::vector<ExtremeCase> extremeCases() {
  const std::string surface = "--grid 4 --derivatives --normals", curve = "--samples 6 --derivatives";
  return {{"surface_4e307", surfaceModel(4e307 / 4), surface, 21},  // the issue's surface: about 4e307
          {"curve_4e307", curveModel(4e307 / 6), curve, 9},
          {"surface_subnormal", surfaceModel(1e-310), surface, 21},
          {"curve_subnormal", curveModel(1e-310), curve, 9},
          {"surface_1e300", surfaceModel(1e300), surface, 21}};
}

TEST(CliOneOutcomeOnEveryDevice, Fp64NearItsLimitsSucceedsOnTheCpuAsOnTheGpu) {
  ScratchDir dir("extreme_cpu");
  for (const ExtremeCase& c : extremeCases()) {
    writeText(dir / (c.tag + ".json"), c.json);
    const CliResult cpu = runIn(dir, "sample " + c.tag + ".json -o " + c.tag + ".cpu.f64 --device cpu -q " + c.grid);
    ASSERT_EQ(cpu.rc, 0) << c.tag << ": " << cpu.err;
    expectFiniteOutput(dir / (c.tag + ".cpu.f64"), c.tag);
  }
}

TEST(CliOneOutcomeOnEveryDevice, VulkanFp64AndFp32AgreeWithTheCpu) {
  REQUIRE_VULKAN();
  ScratchDir dir("extreme_vk");
  for (const ExtremeCase& c : extremeCases()) {
    writeText(dir / (c.tag + ".json"), c.json);
    const CliResult cpu = runIn(dir, "sample " + c.tag + ".json -o cpu.f64 --device cpu -q " + c.grid);
    ASSERT_EQ(cpu.rc, 0) << c.tag << ": " << cpu.err;
    const CliResult vk =
        runIn(dir, "sample " + c.tag + ".json -o vk.f64 --device vulkan --require-device -q " + c.grid);
    ASSERT_EQ(vk.rc, 0) << c.tag << ": " << vk.err;
    // Both evaluate 2^k * net and scale back: equal to fp64 rounding (normals are scale-free).
    EXPECT_LE(worstRelative(readText(dir / "vk.f64"), readText(dir / "cpu.f64"), c.perRecord), 1e-10) << c.tag;
    // fp32 output cannot hold these nets: the same refusal whatever the device.
    const CliResult cpu32 = runIn(dir, "sample " + c.tag + ".json -o c.f32 --device cpu --precision float " + c.grid);
    const CliResult vk32 = runIn(dir, "sample " + c.tag + ".json -o v.f32 --device vulkan --precision float " + c.grid);
    EXPECT_EQ(cpu32.rc, vk32.rc) << c.tag << ": " << cpu32.err << " | " << vk32.err;
    if (cpu32.rc != 0) {
      EXPECT_EQ(cpu32.err, vk32.err) << c.tag;
    }
    EXPECT_FALSE(contains(vk32.err, "internal error")) << c.tag << ": " << vk32.err;
  }
}

TEST(CliOneOutcomeOnEveryDevice, ValuesBeyondFp64AreRefusedAlikeNeverAsInternalErrors) {
  ScratchDir dir("extreme_over");
  // Coordinates of alternating sign at 1.7e308: the derivatives themselves exceed fp64.
  std::string pts = "[";
  for (int i = 0; i < 5; ++i) {
    pts += i ? ", [" : "[";
    for (int j = 0; j < 5; ++j) {
      const char* s = (i + j) % 2 ? "-1.7e308" : "1.7e308";
      pts += std::string(j ? ", " : "") + "[" + s + ", " + s + ", " + s + "]";
    }
    pts += "]";
  }
  writeText(dir / "over.json",
            R"({"kind": "surface", "construction": "extended_bspline", "degree": 5, "lambda": 0, "closed": [false, false], "points": )" +
                pts + "]}");
  std::vector<std::string> devices = {"--device cpu"};
  if (vulkanDevice()) devices.push_back("--device vulkan --require-device");
  for (const std::string& device : devices) {
    const CliResult r = runIn(dir, "sample over.json -o o.f64 --grid 4 --derivatives --normals " + device);
    EXPECT_EQ(r.rc, 3) << device << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "exceeds the fp64 range of the output")) << device << ": " << r.err;
    EXPECT_FALSE(contains(r.err, "internal error")) << device << ": " << r.err;
    EXPECT_FALSE(fs::exists(dir / "o.f64")) << device;
  }
}

TEST(CliOneOutcomeOnEveryDevice, EvalOfAHugeNetMatchesSample) {
  ScratchDir dir("extreme_eval");
  writeText(dir / "s.json", surfaceModel(4e307 / 4));
  writeText(dir / "at.json", R"({"samples": [{"patch": [0, 0], "uv": [0.25, 0.5]}, {"patch": [1, 1], "uv": [1, 0]}]})");
  std::vector<std::string> devices = {"--device cpu"};
  if (vulkanDevice()) devices.push_back("--device vulkan --require-device");
  for (const std::string& device : devices) {
    const CliResult r = runIn(dir, "eval s.json --at at.json -q " + device);
    ASSERT_EQ(r.rc, 0) << device << ": " << r.err;
    expectFiniteText(r.out, device);
    const json doc = json::parse(r.out);
    ASSERT_EQ(doc["samples"].size(), 2u);
    EXPECT_FALSE(doc["samples"][0]["normal"].is_null()) << device;
  }
}

// ---- A query outside the model is the user's error ------------------------------------------------

TEST(CliQueriesOutsideTheModel, GlobalParametersOutsideTheRangeAreExit2NamingTheEntry) {
  ScratchDir dir("query_range");
  std::vector<std::string> devices = {"--device cpu"};
  if (vulkanDevice()) devices.push_back("--device vulkan --require-device");
  for (const char* u : {"1e9", "1e300", "-0.5", "1.0000001"}) {
    writeText(dir / "at.json", std::string(R"({"samples": [{"u": 0.5}, {"u": )") + u + "}]}");
    for (const std::string& device : devices) {
      const CliResult r = runIn(dir, "eval " + quote(exampleModel("clamped_bspline.json")) + " --at at.json " + device);
      EXPECT_EQ(r.rc, 2) << u << " " << device << ": " << r.err;
      EXPECT_TRUE(contains(r.err, "--at.samples[1].u: must be in the model's parameter range [0, 1]")) << r.err;
      EXPECT_TRUE(r.out.empty()) << r.out;
    }
  }
}

TEST(CliQueriesOutsideTheModel, APatchOnAnEmptyKnotIntervalIsExit2OnEveryDevice) {
  ScratchDir dir("query_empty");
  // Knots 0,0,0,0,1,1,2,2,2,2 in u: interval 4 ([1, 1]) is empty.
  std::string pts = "[";
  for (int i = 0; i < 6; ++i) {
    pts += i ? ", [" : "[";
    for (int j = 0; j < 4; ++j) pts += std::string(j ? ", " : "") + "[" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string((i * j) % 3) + "]";
    pts += "]";
  }
  writeText(dir / "s.json", R"({"kind": "surface", "construction": "bspline", "order": 4, "closed": [false, false],
    "knots": [[0, 0, 0, 0, 1, 1, 2, 2, 2, 2], [0, 0, 0, 0, 1, 1, 1, 1]], "points": )" + pts + "]}");
  writeText(dir / "at.json", R"({"samples": [{"patch": [4, 3], "uv": [0.5, 0.5]}]})");
  std::vector<std::string> devices = {"--device cpu"};
  if (vulkanDevice()) devices.push_back("--device vulkan --require-device");
  for (const std::string& device : devices) {
    const CliResult r = runIn(dir, "eval s.json --at at.json " + device);
    EXPECT_EQ(r.rc, 2) << device << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "--at.samples[0].patch[0]: is an empty knot interval")) << device << ": " << r.err;
    EXPECT_TRUE(r.out.empty());
  }
}

// ---- demo commits its folder as one set ----------------------------------------------------------

TEST(CliDemo, AFullDiskLeavesTheFolderAsItWas) {
  ScratchDir dir("demo_full");
  // ulimit -f 16 (KiB): the first OBJ larger than that fails with EFBIG (SIGXFSZ is ignored).
  const std::string limited = "bash -c 'ulimit -f 16; exec \"$0\" \"$@\"' " + quote(SHAPESPLINE_CLI);
  auto demo = [&](const std::string& folder) {
    const auto out = dir / "_o", err = dir / "_e";
    return runCaptured("cd " + quote(dir.path().string()) + " && " + limited + " demo --dir " + folder + " >" +
                           quote(out.string()) + " 2>" + quote(err.string()),
                       out, err);
  };
  fs::create_directories(dir / "existing");
  writeText(dir / "existing" / "butterfly_aeb.json", "mine");
  for (const char* folder : {"existing", "fresh"}) {
    const CliResult r = demo(folder);
    EXPECT_EQ(r.rc, 3) << folder << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "File too large") || contains(r.err, "No space")) << r.err;
  }
  EXPECT_EQ(entries(dir / "existing"), std::vector<std::string>{"butterfly_aeb.json"});
  EXPECT_EQ(readText(dir / "existing" / "butterfly_aeb.json"), "mine");
  EXPECT_FALSE(fs::exists(dir / "fresh")) << "a folder the failed run created is removed";
  // Without the limit every file appears, the model files first sampled from their own bytes (and
  // the contact sheet, a set of its own, where a Vulkan device draws it).
  const CliResult ok = runIn(dir, "demo --dir fresh");
  ASSERT_EQ(ok.rc, 0) << ok.err;
  EXPECT_EQ(entries(dir / "fresh").size(), vulkanDevice() ? 19u : 18u);
  EXPECT_TRUE(contains(readText(dir / "fresh" / "surface_aeb_lambda_0.obj"), "fresh/surface_aeb_lambda_0.json"));
}

// ---- An option that does not apply is refused -----------------------------------------------------

struct Inapplicable {
  std::string args, option, rule;
  bool vulkan = false;
};

TEST(CliInapplicableOptions, AreExit2NamingTheOptionAndTheReason) {
  ScratchDir dir("inapplicable");
  const std::string surface = quote(exampleModel("bspline_surface.json")), target = quote(exampleModel("bspline_surface_target.json"));
  const std::string curve = quote(exampleModel("open_aeb.json")), bspline = quote(exampleModel("clamped_bspline.json"));
  const std::string aebSurface = quote(exampleModel("surface_aeb.json"));
  const std::vector<Inapplicable> cases = {
      {"extend " + surface + " --to-curve " + target + " -o e.json --svg s.svg", "--svg", "does not apply to surfaces"},
      {"basis --family bspline --order 4 --lambda 2", "--lambda", "does not apply to --family bspline"},
      {"basis --family gb --degree 5 --lambda 0.5", "--degree", "does not apply to --family gb"},
      {"basis --family xuwang --degree 4 --order 3", "--order", "does not apply to --family xuwang"},
      {"basis --family ubp --order 4 --mu 0.1", "--mu", "does not apply to --family ubp"},
      {"basis --family singular_blend --lambda 1", "--lambda", "does not apply to --family singular_blend"},
      {"sample " + curve + " -o c.f32 --mesh-layout welded", "--mesh-layout", "does not apply to f32 output"},
      {"sample " + curve + " -o c.csv --device cpu --require-device", "--require-device", "applies to --device auto or vulkan"},
      {"eval " + curve + " --at at.json --device cpu --require-device", "--require-device", "applies to --device auto or vulkan"},
      {"render " + curve + " -o c.png --rate 8", "--rate", "does not apply to curves", true},
      {"render " + curve + " -o c.png --wireframe", "--wireframe", "does not apply to curves", true},
      {"render " + bspline + " -o c.png --lambda 1", "--lambda", "which has no lambda", true},
      {"render " + bspline + " -o c.png --sweep lambda=0,1", "--sweep", "which has no lambda", true},
      {"render " + surface + " -o c.png --sweep alpha=0.5,1 --overlay", "--overlay", "overlays draw curves"},
      {"render " + curve + " -o c.png --overlay", "--overlay", "needs --sweep"},
      {"render " + curve + " -o c.png --overlay --sweep lambda=-6,-5,-4,-3,-2,-1,0", "--overlay", "at most 6 values"},
      {"render " + curve + " -o c.png --sweep lambda=0,1 --distance", "--distance", "distance maps colour surfaces"},
      {"render " + aebSurface + " -o c.png --sweep lambda=0,0.5,1 --distance", "--distance", "needs --sweep with two values"},
      {"render " + aebSurface + " -o c.png --sweep lambda=0,1 --distance --control-net", "--control-net",
       "does not apply to a distance map"},
      {"render " + curve + " -o c.png --title \"\xce\xbb = 1\"", "--title", "printable ASCII"},
  };
  writeText(dir / "at.json", R"({"samples": [{"span": 1, "t": 0.5}]})");
  for (const Inapplicable& c : cases) {
    if (c.vulkan && !vulkanDevice()) continue;
    const CliResult r = runIn(dir, c.args);
    EXPECT_EQ(r.rc, 2) << c.args << ": " << r.err;
    EXPECT_TRUE(contains(r.err, c.option + ": ")) << c.args << ": " << r.err;
    EXPECT_TRUE(contains(r.err, c.rule)) << c.args << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << c.args;
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"at.json"}) << c.args << ": an output was written";
  }
}

TEST(CliInapplicableOptions, ViewScreenshotDirNeedsAScriptThatTakesScreenshots) {
  ScratchDir dir("inapplicable_view");
  writeText(dir / "quit.txt", "quit\n");
  const CliResult r = runIn(dir, "view " + quote(exampleModel("surface_aeb.json")) + " --script quit.txt --screenshot-dir shots");
  if (contains(r.err, "this build has no viewer")) GTEST_SKIP() << "no viewer in this build";
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "--screenshot-dir: does not apply without a --script that takes screenshots")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "shots"));
}

}  // namespace
}  // namespace shapespline::test
