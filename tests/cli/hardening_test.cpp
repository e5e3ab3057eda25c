// Issue 7 at the command line: under faults and extreme values `sample` and `eval` keep working or
// fail cleanly (documented exit code, a message naming the failure, no output and no temporary
// file left), never write a NaN or Inf, warn where precision is lost, and write the same bytes for
// the same input across runs, thread counts and chunk sizes.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <regex>
#include <sys/stat.h>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// `shapespline <args>` with extra environment (`env`: "NAME=value ...") and an optional file size
// limit in KiB (ulimit -f, applied by bash to the exec'd binary; SIGXFSZ keeps its default action,
// so the binary must ignore it itself).
CliResult run(const std::string& args, const fs::path& scratch, const std::string& env = "", int fileLimitKiB = 0) {
  const auto out = scratch / "_stdout.txt", err = scratch / "_stderr.txt";
  std::string cmd = "cd " + quote(scratch.string()) + " && env " + env + " ";
  if (fileLimitKiB > 0) cmd += "bash -c 'ulimit -f " + std::to_string(fileLimitKiB) + "; exec \"$0\" \"$@\"' ";
  cmd += quote(SHAPESPLINE_CLI) + " " + args + " >" + quote(out.string()) + " 2>" + quote(err.string());
  return runCaptured(cmd, out, err);
}

// `sample MODEL -o folder/name opts`, creating the folder.
CliResult sample(const std::string& modelPath, const fs::path& folder, const std::string& name, const std::string& opts,
                 const std::string& env = "", int fileLimitKiB = 0) {
  fs::create_directories(folder);
  return run("sample " + quote(modelPath) + " -o " + quote((folder / name).string()) + " " + opts, folder, env,
             fileLimitKiB);
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += x + " ";
  return s;
}

// ---- Parsing outputs back: every number must be finite -------------------------------------------

// ---- Determinism --------------------------------------------------------------------------------

struct FormatCase {
  std::string model, file, opts;
};

// Byte-identical output (and sidecar) for two runs, 1 vs 2 threads, tiny vs large chunks.
const std::vector<std::string> kCpuVariants = {"--threads 1 --chunk-points 1", "--threads 1 --chunk-points 1",
                                               "--threads 2 --chunk-points 1", "--threads 2 --chunk-points 4194304", ""};
const std::vector<std::string> kGpuVariants = {"--chunk-points 1", "--chunk-points 1", ""};

void expectSameBytes(const FormatCase& c, const std::string& device, const std::string& tag,
                     const std::vector<std::string>& variants = kCpuVariants) {
  ScratchDir dir("det_" + tag);
  std::string first, firstSidecar;
  for (size_t i = 0; i < variants.size(); ++i) {
    const fs::path folder = dir / ("run" + std::to_string(i));
    const CliResult r = sample(c.model, folder, c.file, device + " " + c.opts + " " + variants[i] + " -q");
    ASSERT_EQ(r.rc, 0) << tag << " [" << variants[i] << "]: " << r.err;
    const std::string bytes = readText(folder / c.file);
    const bool raw = contains(c.file, ".f32") || contains(c.file, ".f64");
    const std::string sidecar = raw ? readText(folder / (c.file + ".json")) : "";
    ASSERT_FALSE(bytes.empty()) << tag;
    if (i == 0) {
      first = bytes, firstSidecar = sidecar;
      continue;
    }
    EXPECT_TRUE(bytes == first) << tag << ": output differs between [" << variants[0] << "] and [" << variants[i]
                                << "] (" << first.size() << " vs " << bytes.size() << " bytes)";
    EXPECT_TRUE(sidecar == firstSidecar) << tag << ": sidecar differs for [" << variants[i] << "]";
  }
}

TEST(CliHardeningDeterminism, CpuEveryFormatAcrossRunsThreadsAndChunks) {
  const std::string curve = exampleModel("open_aeb.json"), closed = exampleModel("butterfly_aeb.json");
  const std::string surface = exampleModel("surface_aeb.json");
  const std::vector<std::pair<std::string, FormatCase>> cases = {
      {"curve_obj", {curve, "c.obj", "--samples 7"}},
      {"curve_ply", {curve, "c.ply", "--samples 7 --derivatives"}},
      {"curve_csv", {closed, "c.csv", "--samples 7 --derivatives"}},
      {"curve_f32", {curve, "c.f32", "--samples 7 --derivatives"}},
      {"curve_f64", {closed, "c.f64", "--samples 7 --derivatives"}},
      {"curve_svg", {closed, "c.svg", "--samples 7"}},
      {"curve_ply_float", {curve, "c.ply", "--samples 7 --precision float"}},
      {"surface_obj", {surface, "s.obj", "--grid 4x3"}},
      {"surface_ply", {surface, "s.ply", "--grid 4x3 --derivatives"}},
      {"surface_csv", {surface, "s.csv", "--grid 3 --derivatives --normals"}},
      {"surface_f32", {surface, "s.f32", "--grid 3 --derivatives --normals"}},
      {"surface_f64", {surface, "s.f64", "--grid 4x3 --derivatives --normals"}},
  };
  for (const auto& [tag, c] : cases) expectSameBytes(c, "--device cpu", "cpu_" + tag);
}

TEST(CliHardeningDeterminism, VulkanAcrossRunsAndChunks) {
  REQUIRE_VULKAN();
  const std::string curve = exampleModel("open_aeb.json"), surface = exampleModel("surface_aeb.json");
  for (const char* precision : {"double", "float"}) {
    const std::string ext = std::string(precision) == "double" ? ".f64" : ".f32";
    const std::string dev = std::string("--device vulkan --require-device --precision ") + precision;
    expectSameBytes({curve, "c" + ext, "--samples 9 --derivatives"}, dev, std::string("vk_curve_") + precision,
                    kGpuVariants);
    expectSameBytes({surface, "s" + ext, "--grid 5x4 --derivatives --normals"}, dev,
                    std::string("vk_surface_") + precision, kGpuVariants);
  }
}

TEST(CliHardeningDeterminism, ChunkAndThreadOptionsAreValidated) {
  ScratchDir dir("det_opts");
  for (const char* bad : {"--threads -1", "--threads 5000", "--chunk-points -3", "--chunk-points 99999999999"}) {
    const CliResult r = sample(exampleModel("open_aeb.json"), dir / "o", "c.obj", std::string("--device cpu ") + bad);
    EXPECT_EQ(r.rc, 2) << bad << ": " << r.err;
    EXPECT_TRUE(contains(r.err, std::string(bad).substr(0, std::string(bad).find(' ')))) << r.err;
    EXPECT_TRUE(entries(dir / "o").empty()) << joined(entries(dir / "o"));
  }
}

// ---- Failure injection --------------------------------------------------------------------------

// The run failed with `code`, said `words` on stderr, and left nothing in `folder`.
void expectCleanFailure(const CliResult& r, int code, const std::vector<std::string>& words, const fs::path& folder,
                        const std::string& what) {
  EXPECT_EQ(r.rc, code) << what << ": " << r.err;
  EXPECT_TRUE(contains(r.err, "shapespline: error: ")) << what << ": " << r.err;
  for (const auto& w : words) EXPECT_TRUE(contains(r.err, w)) << what << ": expected '" << w << "' in: " << r.err;
  EXPECT_TRUE(entries(folder).empty()) << what << ": left " << joined(entries(folder));
}

TEST(CliHardeningFaults, AllocationFailureAndDeviceLossAreExit3WithNoOutput) {
  REQUIRE_VULKAN();
  ScratchDir dir("fault_vk");
  int k = 0;
  for (const std::string env : {"SHAPESPLINE_FAULT=alloc", "SHAPESPLINE_FAULT=alloc:4"}) {
    for (const char* file : {"c.obj", "c.f64"}) {
      const fs::path out = dir / ("out" + std::to_string(k++));
      const CliResult r = sample(exampleModel("open_aeb.json"), out, file, "--device vulkan --samples 9", env);
      expectCleanFailure(r, 3, {"error: vulkan: ", "VK_ERROR_OUT_OF_DEVICE_MEMORY", "injected", "--chunk-points",
                                "no output written"},
                         out, env + " " + file);
    }
    const fs::path out = dir / ("out" + std::to_string(k++));
    const CliResult r = sample(exampleModel("surface_aeb.json"), out, "s.ply", "--device vulkan --precision float --grid 4", env);
    expectCleanFailure(r, 3, {"error: vulkan: ", "VK_ERROR_OUT_OF_DEVICE_MEMORY"}, out, env + " surface");
  }
  // Device loss (vk/fault.h): list evaluation (`eval`, vk::OneShot) and grid streaming (`sample`,
  // the evaluator's chunk ring) both fail cleanly.
  writeText(dir / "at.json", R"({"samples": [{"span": 0, "t": 0.5}]})");
  const CliResult r = run("eval " + quote(exampleModel("open_aeb.json")) + " --at at.json --device vulkan", dir.path(),
                          "SHAPESPLINE_FAULT=device_lost");
  EXPECT_EQ(r.rc, 3) << r.err;
  EXPECT_TRUE(contains(r.err, "error: vulkan: ") && contains(r.err, "VK_ERROR_DEVICE_LOST")) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  for (const char* file : {"c.obj", "c.f64"}) {
    const fs::path out = dir / ("lost" + std::to_string(k++));
    const CliResult q = sample(exampleModel("open_aeb.json"), out, file, "--device vulkan --samples 9",
                               "SHAPESPLINE_FAULT=device_lost");
    expectCleanFailure(q, 3, {"error: vulkan: ", "VK_ERROR_DEVICE_LOST"}, out, std::string("device_lost ") + file);
  }
}

TEST(CliHardeningFaults, NoDeviceFallsBackToTheCpuUnlessTheDeviceIsRequired) {
  ScratchDir dir("fault_nodev");
  for (const char* file : {"s.obj", "s.f64"}) {
    const CliResult cpu = sample(exampleModel("surface_aeb.json"), dir / "cpu", file, "--device cpu --grid 4 -q");
    ASSERT_EQ(cpu.rc, 0) << cpu.err;
    const CliResult r =
        sample(exampleModel("surface_aeb.json"), dir / "fb", file, "--device vulkan --grid 4", "SHAPESPLINE_FAULT=no_device");
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "notice: no Vulkan device")) << r.err;
    EXPECT_TRUE(contains(r.err, "falling back to the CPU")) << r.err;
    EXPECT_TRUE(readText(dir / "fb" / file) == readText(dir / "cpu" / file)) << file << ": fallback output differs";

    const fs::path out = dir / (std::string("req_") + file);
    const CliResult q = sample(exampleModel("surface_aeb.json"), out, file, "--device vulkan --require-device --grid 4",
                               "SHAPESPLINE_FAULT=no_device");
    expectCleanFailure(q, 3, {"--require-device", "no Vulkan device", "injected"}, out, "require-device");
  }
  writeText(dir / "at.json", R"({"samples": [{"span": 0, "t": 0.5}]})");
  const CliResult e = run("eval " + quote(exampleModel("open_aeb.json")) + " --at at.json --device vulkan --require-device",
                          dir.path(), "SHAPESPLINE_FAULT=no_device");
  EXPECT_EQ(e.rc, 3) << e.err;
  EXPECT_TRUE(e.out.empty());
  // Knot-vector B-splines have no GPU kernel: with --require-device that is an error too.
  if (vulkanDevice()) {
    const fs::path out = dir / "knots";
    const CliResult k = sample(exampleModel("clamped_bspline.json"), out, "k.obj", "--device vulkan --require-device");
    if (k.rc != 0) expectCleanFailure(k, 3, {"--require-device"}, out, "knot-vector");
  }
}

TEST(CliHardeningFaults, FullDiskIsExit3WithNoPartialFile) {
  ScratchDir dir("fault_fsize");
  // ~2 MB of CSV / ~1 MB of f64 against a 64 KiB file size limit: the first flush fails with EFBIG.
  for (const char* file : {"c.csv", "c.f64", "c.obj", "c.ply"}) {
    const fs::path out = dir / (std::string("o_") + file);
    const CliResult r = sample(exampleModel("open_aeb.json"), out, file, "--device cpu --samples 20000 --derivatives", "", 64);
    expectCleanFailure(r, 3, {"-o: cannot write", "File too large", "temporary file was removed"}, out, file);
  }
  // 720 KB of records, one block: written by the sampler's own thread (no writer thread); the
  // failed write still ends the job the same way.
  for (const char* file : {"one_block.f64", "one_block.npy"}) {
    const fs::path out = dir / (std::string("o_") + file);
    const CliResult r = sample(exampleModel("open_aeb.json"), out, file, "--device cpu --samples 2000 --derivatives", "", 64);
    expectCleanFailure(r, 3, {"-o: cannot write", "File too large", "temporary file was removed"}, out, file);
  }
  // A small job fits under the limit: the limit itself is not what fails.
  const CliResult ok = sample(exampleModel("open_aeb.json"), dir / "small", "c.csv", "--device cpu --samples 5", "", 64);
  EXPECT_EQ(ok.rc, 0) << ok.err;
}

TEST(CliHardeningFaults, UnwritableOutputIsExit2NamingO) {
  ScratchDir dir("fault_path");
  writeText(dir / "plain.txt", "x");
  fs::create_directory(dir / "sub");
  struct Case {
    std::string path, words;
  };
  for (const Case& c : {Case{(dir / "missing" / "c.obj").string(), "does not exist"},
                        Case{(dir / "plain.txt" / "c.obj").string(), "is not a folder"},
                        Case{"/proc/shapespline_hardening.obj", "cannot create a file"},
                        Case{"/proc/self/c.obj", "cannot create a file"},
                        Case{(dir / "sub").string() + "/", "unknown extension"}}) {
    const CliResult r = run("sample " + quote(exampleModel("open_aeb.json")) + " -o " + quote(c.path) + " --device cpu",
                            dir / "sub");
    EXPECT_EQ(r.rc, 2) << c.path << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "error: -o: ")) << c.path << ": " << r.err;
    EXPECT_TRUE(contains(r.err, c.words)) << c.path << ": " << r.err;
  }
  EXPECT_TRUE(entries(dir / "sub").empty()) << joined(entries(dir / "sub"));
  EXPECT_FALSE(fs::exists(dir / "missing"));

  // An existing device (reached through a symlink with a known extension) is refused, never replaced.
  fs::create_directory(dir / "dev");
  fs::create_symlink("/dev/full", dir / "dev" / "full.obj");
  const CliResult r = run("sample " + quote(exampleModel("open_aeb.json")) + " -o full.obj --device cpu", dir / "dev");
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "-o: ") && contains(r.err, "not a regular file")) << r.err;
  EXPECT_TRUE(fs::is_symlink(dir / "dev" / "full.obj"));
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
  EXPECT_EQ(entries(dir / "dev").size(), 1u) << joined(entries(dir / "dev"));

  // A folder without write permission (meaningless as root, who may write anyway).
  if (::geteuid() != 0) {
    fs::create_directory(dir / "ro");
    fs::permissions(dir / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    const CliResult q = run("sample " + quote(exampleModel("open_aeb.json")) + " -o ro/c.obj --device cpu", dir.path());
    EXPECT_EQ(q.rc, 2) << q.err;
    EXPECT_TRUE(contains(q.err, "-o: ")) << q.err;
    fs::permissions(dir / "ro", fs::perms::owner_all);
  }
}

TEST(CliHardeningFaults, InjectedNanNeverReachesAFile) {
  ScratchDir dir("fault_nan");
  std::vector<std::string> devices = {"--device cpu"};
  if (vulkanDevice()) devices.push_back("--device vulkan --precision float");
  for (const auto& dev : devices) {
    for (const char* file : {"c.obj", "c.ply", "c.csv", "c.f32", "c.f64", "c.svg"}) {
      const fs::path out = dir / ("o" + std::to_string(std::hash<std::string>{}(dev + file)));
      const CliResult r = sample(exampleModel("open_aeb.json"), out, file, dev + " --samples 6", "SHAPESPLINE_FAULT=nan");
      expectCleanFailure(r, 3, {"error: point: ", "non-finite", "nothing was written"}, out, dev + " " + file);
    }
    const fs::path out = dir / ("s" + std::to_string(std::hash<std::string>{}(dev)));
    const CliResult r = sample(exampleModel("surface_aeb.json"), out, "s.obj", dev + " --grid 4", "SHAPESPLINE_FAULT=nan");
    expectCleanFailure(r, 3, {"non-finite"}, out, dev + " surface");
  }
  writeText(dir / "at.json", R"({"samples": [{"span": 0, "t": 0.5}]})");
  const CliResult e = run("eval " + quote(exampleModel("open_aeb.json")) + " --at at.json --device cpu", dir.path(),
                          "SHAPESPLINE_FAULT=nan");
  EXPECT_EQ(e.rc, 3) << e.err;
  EXPECT_TRUE(contains(e.err, "non-finite")) << e.err;
  EXPECT_TRUE(e.out.empty()) << e.out;
}

// ---- Extreme values -----------------------------------------------------------------------------

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// A wavy net of n points (curve) or n x n points (surface), scaled by `scale` (coincident: every
// point at (scale, scale, scale)).
std::string curvePoints(int n, double scale, bool coincident) {
  std::string s = "[";
  for (int i = 0; i < n; ++i) {
    const double x = coincident ? 1.0 : i, y = coincident ? 1.0 : std::sin(1.3 * i), z = coincident ? 1.0 : 0.1 * i;
    s += std::string(i ? ", " : "") + "[" + num(x * scale) + ", " + num(y * scale) + ", " + num(z * scale) + "]";
  }
  return s + "]";
}

std::string surfacePoints(int n, double scale, bool coincident) {
  std::string s = "[";
  for (int i = 0; i < n; ++i) {
    s += i ? ", [" : "[";
    for (int j = 0; j < n; ++j) {
      const double x = coincident ? 1.0 : i, y = coincident ? 1.0 : j,
                   z = coincident ? 1.0 : std::sin(0.9 * i) * std::cos(0.7 * j);
      s += std::string(j ? ", " : "") + "[" + num(x * scale) + ", " + num(y * scale) + ", " + num(z * scale) + "]";
    }
    s += "]";
  }
  return s + "]";
}

struct Family {
  std::string tag, json;  // construction + parameters (without kind / points)
  bool warns = false;     // core/diagnostics.h warns for this family/parameter at any scale
  bool alphaTiny = false;
};

// Every family at both ends of its shape parameter range (docs/math.md §11), α at 1e-12 and 1.
std::vector<Family> families() {
  return {
      {"xw_lo", R"("construction": "extended_bspline", "degree": 4, "lambda": -8)"},
      {"xw_hi", R"("construction": "extended_bspline", "degree": 6, "lambda": 1)"},
      {"aeb_a1_lo", R"("construction": "alpha_eb", "degree": 5, "lambda": -15, "alpha": 1)"},
      {"aeb_tiny_hi", R"("construction": "alpha_eb", "degree": 4, "lambda": 1, "alpha": 1e-12)", true, true},
      {"gb_lo", R"("construction": "gb", "lambda": -8)"},
      {"gb_hi", R"("construction": "gb", "lambda": 1e13)", true},
      {"ubp_lo", R"("construction": "ubp", "order": 4, "lambda": -8)"},
      {"ubp_hi", R"("construction": "ubp", "order": 5, "lambda": 1)"},
      {"gubp_lo", R"("construction": "gubp", "order": 4, "mu": [0, 0.5, 1])"},
      {"gubp_hi", R"("construction": "gubp", "order": 4, "mu": [0.5, 0.5, 0])"},
      {"bspline", R"("construction": "bspline", "order": 4)"},
  };
}

struct Scale {
  std::string tag;
  double scale;
  bool coincident;
};

const std::vector<Scale> kScales = {{"1e30", 1e30, false}, {"1e-30", 1e-30, false}, {"same", 1e30, true}};

// Samples `modelPath` into every listed file; exit 0, every number finite, a warning exactly when
// `warns`.
void expectFiniteEverywhere(const std::string& modelPath, const fs::path& folder, const std::vector<std::string>& files,
                            const std::string& opts, bool warns, const std::string& what) {
  for (const auto& file : files) {
    const CliResult r = sample(modelPath, folder, file, opts);
    ASSERT_EQ(r.rc, 0) << what << " " << file << ": " << r.err;
    EXPECT_EQ(contains(r.err, "shapespline: warning: "), warns) << what << " " << file << ": " << r.err;
    expectFiniteOutput(folder / file, what + " " + file);
  }
}

TEST(CliHardeningExtremes, CurvesOnTheCpuEveryFormat) {
  ScratchDir dir("ext_cpu_curve");
  for (const auto& f : families()) {
    for (const auto& s : kScales) {
      const std::string name = "c_" + f.tag + "_" + s.tag;
      const fs::path m = dir / (name + ".json");
      writeText(m, R"({"kind": "curve", )" + f.json + R"(, "points": )" + curvePoints(7, s.scale, s.coincident) + "}");
      // Every format for one family per end; the raw fp64 file (all fields, every bit) for all.
      const bool all = f.tag == "aeb_tiny_hi" || f.tag == "xw_lo" || f.tag == "gb_hi";
      const std::vector<std::string> files =
          all ? std::vector<std::string>{"c.obj", "c.ply", "c.csv", "c.f32", "c.f64", "c.svg"}
              : std::vector<std::string>{"c.f64"};
      expectFiniteEverywhere(m.string(), dir / name, files, "--device cpu --samples 6 --derivatives", f.warns, name);
    }
  }
}

TEST(CliHardeningExtremes, SurfacesOnTheCpuEveryFormat) {
  ScratchDir dir("ext_cpu_surface");
  for (const auto& f : families()) {
    for (const auto& s : kScales) {
      const std::string name = "s_" + f.tag + "_" + s.tag;
      const fs::path m = dir / (name + ".json");
      writeText(m, R"({"kind": "surface", )" + f.json + R"(, "points": )" + surfacePoints(6, s.scale, s.coincident) +
                       "}");
      const bool all = f.tag == "aeb_tiny_hi" || f.tag == "ubp_lo";
      const std::vector<std::string> files =
          all ? std::vector<std::string>{"s.obj", "s.ply", "s.csv", "s.f32", "s.f64"} : std::vector<std::string>{"s.f64"};
      expectFiniteEverywhere(m.string(), dir / name, files, "--device cpu --grid 3 --derivatives --normals", f.warns,
                             name);
    }
  }
}

// Largest difference between two raw files (fp32 or fp64 records of `valuesPerRecord` values),
// relative to the largest |value| of each field of `b`, over the first `compared` values of each
// record.
double worstRelative(const std::string& a, const std::string& b, size_t valuesPerRecord, size_t compared, bool aFloat,
                     bool bFloat) {
  auto value = [](const std::string& s, bool f, size_t i) {
    if (f) {
      float v;
      std::memcpy(&v, s.data() + i * 4, 4);
      return static_cast<double>(v);
    }
    double v;
    std::memcpy(&v, s.data() + i * 8, 8);
    return v;
  };
  const size_t n = a.size() / (aFloat ? 4 : 8);
  if (n != b.size() / (bFloat ? 4 : 8)) return INFINITY;
  std::vector<double> scale(valuesPerRecord / 3, 0.0);
  for (size_t i = 0; i < n; ++i) scale[(i % valuesPerRecord) / 3] = std::max(scale[(i % valuesPerRecord) / 3], std::abs(value(b, bFloat, i)));
  double worst = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double s = scale[(i % valuesPerRecord) / 3];
    if (s > 0 && i % valuesPerRecord < compared) worst = std::max(worst, std::abs(value(a, aFloat, i) - value(b, bFloat, i)) / s);
  }
  return worst;
}

TEST(CliHardeningExtremes, VulkanFp64AndFp32StayFiniteAndMatchTheCpu) {
  REQUIRE_VULKAN();
  ScratchDir dir("ext_vk");
  // The GPU kernels are shared by all families: α-EB at both α ends, UBP at the low λ end and GB
  // at the high end, at both scales and with coincident points, curves and surfaces.
  struct Case {
    const char* family;
    size_t scale;
    bool surface;
  };
  const std::vector<Case> cases = {{"aeb_tiny_hi", 0, false}, {"ubp_lo", 1, false},     {"gb_hi", 0, false},
                                   {"aeb_a1_lo", 2, false},   {"aeb_tiny_hi", 1, true}, {"ubp_lo", 0, true},
                                   {"gb_hi", 1, true},        {"aeb_a1_lo", 0, true},   {"gb_hi", 2, true},
                                   {"ubp_lo", 2, true}};
  for (const Case& c : cases) {
    Family f;
    for (const auto& g : families())
      if (g.tag == c.family) f = g;
    const Scale& s = kScales[c.scale];
    const std::string name = std::string(c.surface ? "s_" : "c_") + c.family + "_" + s.tag;
    const fs::path m = dir / (name + ".json");
    writeText(m, std::string(R"({"kind": ")") + (c.surface ? "surface" : "curve") + "\", " + f.json +
                     R"(, "points": )" +
                     (c.surface ? surfacePoints(5, s.scale, s.coincident) : curvePoints(6, s.scale, s.coincident)) + "}");
    const std::string grid = c.surface ? "--grid 3 --derivatives --normals" : "--samples 5 --derivatives";
    const size_t values = c.surface ? 7 * 3 : 3 * 3;
    const CliResult cpu = sample(m.string(), dir / name, "cpu.f64", "--device cpu -q " + grid);
    ASSERT_EQ(cpu.rc, 0) << name << ": " << cpu.err;
    const std::string cpuBytes = readText(dir / name / "cpu.f64");
    for (const char* precision : {"double", "float"}) {
      const bool fp32 = std::string(precision) == "float";
      // GB λ = 1e13 is beyond the fp32 kernels: the CLI takes the CPU path with a notice.
      const bool fallback = fp32 && std::string(c.family) == "gb_hi";
      const std::string file = fp32 ? "vk.f32" : "vk.f64";
      const CliResult r = sample(m.string(), dir / name, file,
                                 grid + " --device vulkan --precision " + precision + (fallback ? "" : " --require-device"));
      ASSERT_EQ(r.rc, 0) << name << " " << precision << ": " << r.err;
      EXPECT_EQ(contains(r.err, "notice: GB lambda"), fallback) << name << " " << precision << ": " << r.err;
      EXPECT_EQ(contains(r.err, "shapespline: warning: "), f.warns) << name << " " << precision << ": " << r.err;
      if (f.alphaTiny) {
        EXPECT_TRUE(contains(r.err, "warning: alpha")) << r.err;
      }
      expectFiniteOutput(dir / name / file, name + " " + precision);
      if (!f.warns && !s.coincident) {
        // Away from warned precision loss the GPU agrees with the CPU to the precision's tolerance
        // at any scale (the net is scaled by a power of two on upload, the results scaled back).
        // fp32 normals are left out: near-degenerate points may take the other normal rule.
        const size_t compared = fp32 && c.surface ? values - 3 : values;
        const double worst = worstRelative(readText(dir / name / file), cpuBytes, values, compared, fp32, false);
        EXPECT_LE(worst, fp32 ? 1e-5 : 1e-10) << name << " " << precision;
      }
    }
  }
}

TEST(CliHardeningExtremes, EvalPrintsOnlyFiniteNumbers) {
  ScratchDir dir("ext_eval");
  writeText(dir / "c.json", R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, "lambda": 1, "alpha": 1e-12, "points": )" +
                                curvePoints(6, 1e30, false) + "}");
  writeText(dir / "s.json", R"({"kind": "surface", "construction": "ubp", "order": 4, "lambda": -8, "points": )" +
                                surfacePoints(5, 1e-30, false) + "}");
  writeText(dir / "same.json", R"({"kind": "surface", "construction": "alpha_eb", "degree": 4, "lambda": 1, "alpha": 1, "points": )" +
                                   surfacePoints(5, 1e30, true) + "}");
  writeText(dir / "cat.json", R"({"samples": [{"span": 0, "t": 0}, {"span": 1, "t": 0.5}, {"span": 2, "t": 1}]})");
  writeText(dir / "sat.json", R"({"samples": [{"patch": [1, 1], "uv": [0, 0]}, {"patch": [2, 2], "uv": [0.5, 1]}]})");
  writeText(dir / "aat.json", R"({"samples": [{"patch": [0, 0], "uv": [0, 0]}, {"patch": [3, 3], "uv": [0.5, 1]}]})");
  std::vector<std::string> devices = {"--device cpu", "--device cpu --precision float"};
  if (vulkanDevice()) {
    devices.push_back("--device vulkan --require-device");
    devices.push_back("--device vulkan --require-device --precision float");
  }
  for (const auto& dev : devices) {
    for (const auto& [m, at] : {std::pair{"c.json", "cat.json"}, std::pair{"s.json", "sat.json"},
                                std::pair{"same.json", "aat.json"}}) {
      const CliResult r = run(std::string("eval ") + m + " --at " + at + " " + dev, dir.path());
      ASSERT_EQ(r.rc, 0) << m << " " << dev << ": " << r.err;
      EXPECT_GT(expectFiniteText(r.out, std::string(m) + " " + dev), 20u) << r.out;
      EXPECT_FALSE(contains(r.out, "nan") || contains(r.out, "inf")) << r.out;
      EXPECT_EQ(contains(r.err, "warning: alpha"), std::string(m) == "c.json") << m << " " << dev << ": " << r.err;
    }
  }
}

TEST(CliHardeningExtremes, Fp32RefusesNetsBeyondItsRange) {
  ScratchDir dir("ext_fp32_range");
  writeText(dir / "c.json", R"({"kind": "curve", "construction": "ubp", "order": 4, "lambda": 0, "points": )" +
                                curvePoints(5, 1e37, false) + "}");
  const CliResult r = sample((dir / "c.json").string(), dir / "o", "c.f32", "--device cpu --precision float");
  expectCleanFailure(r, 2, {"--precision", "use --precision double"}, dir / "o", "fp32 1e37");
  // fp64 has the range: exit 0, finite.
  const CliResult d = sample((dir / "c.json").string(), dir / "d", "c.f64", "--device cpu --derivatives");
  ASSERT_EQ(d.rc, 0) << d.err;
  expectFiniteOutput(dir / "d" / "c.f64", "fp64 1e37");
  // An fp64 job into an fp32 file whose derivatives pass 3.4e38: caught before anything is written.
  writeText(dir / "big.json", R"({"kind": "curve", "construction": "ubp", "order": 4, "lambda": 0, "points": )"
                              R"([[3e38, 0], [-3e38, 2], [3e38, 3], [-3e38, 1e38]]})");
  const CliResult f = sample((dir / "big.json").string(), dir / "f", "c.f32", "--device cpu --derivatives");
  expectCleanFailure(f, 3, {"error: d2: ", "exceeds the fp32 range"}, dir / "f", "f32 file overflow");
}

}  // namespace
}  // namespace shapespline::test
