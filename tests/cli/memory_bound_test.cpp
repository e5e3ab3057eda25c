// Issue 12, requirement 5: a patch (span) larger than a chunk is cut into rows of samples; the
// output bytes do not depend on where the rows are cut, on the CPU and on the Vulkan path. (The
// peak-RSS bounds that the cutting buys: tests/memory/cli_rss_test.cpp.)
#include "cli_runner.h"
#include "one_patch_models.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// ---- The bytes do not depend on where the rows are cut ------------------------------------------

struct Case {
  std::string tag, model, file, opts;
};

// Every variant cuts the item differently: whole (default chunk), 1-point chunks (one row per
// chunk), a budget that is not a multiple of the row, 2 threads sharing the rows of one chunk.
const std::vector<std::string> kCpuCuts = {"", "--chunk-points 1", "--chunk-points 100 --threads 1",
                                           "--chunk-points 333 --threads 2", "--chunk-points 4194304 --threads 2"};
const std::vector<std::string> kGpuCuts = {"", "--chunk-points 1", "--chunk-points 333"};

void expectSameBytesAcrossCuts(const Case& c, const std::string& device, const std::vector<std::string>& cuts) {
  ScratchDir dir("cuts_" + c.tag);
  writeText(dir / "model.json", c.model);
  std::string first, firstSidecar;
  for (size_t i = 0; i < cuts.size(); ++i) {
    const fs::path out = dir / ("run" + std::to_string(i)) / c.file;
    fs::create_directories(out.parent_path());
    const CliResult r = runCli("sample " + quote((dir / "model.json").string()) + " -o " + quote(out.string()) + " " +
                                   device + " " + c.opts + " " + cuts[i] + " -q",
                               dir.path());
    ASSERT_EQ(r.rc, 0) << c.tag << " [" << cuts[i] << "]: " << r.err;
    const std::string bytes = readText(out);
    const bool raw = out.extension() == ".f32" || out.extension() == ".f64";
    const std::string sidecar = raw ? readText(out.string() + ".json") : "";
    ASSERT_FALSE(bytes.empty()) << c.tag;
    if (i == 0) {
      first = bytes, firstSidecar = sidecar;
      continue;
    }
    EXPECT_TRUE(bytes == first) << c.tag << ": output differs between [" << cuts[0] << "] and [" << cuts[i] << "] ("
                                << first.size() << " vs " << bytes.size() << " bytes)";
    EXPECT_TRUE(sidecar == firstSidecar) << c.tag << ": sidecar differs for [" << cuts[i] << "]";
  }
}

std::string aebSurface() { return readText(examplesDir() + "/surface_aeb.json"); }
std::string aebCurve() { return readText(examplesDir() + "/open_aeb.json"); }

// Surfaces: grids of 40 x 24 (960 points per patch, Sv % 4 == 0: the GPU grid kernel) and
// 37 x 23 (the general kernel); curves: spans of 700 samples.
std::vector<Case> cases() {
  return {
      {"patch_obj", kOnePatch, "s.obj", "--grid 40x24"},
      {"patch_ply", kOnePatch, "s.ply", "--grid 37x23 --derivatives"},
      {"patch_csv", kOnePatch, "s.csv", "--grid 40x24 --derivatives --normals"},
      {"patch_f32", kOnePatch, "s.f32", "--grid 37x23 --derivatives --normals"},
      {"aeb_f64", aebSurface(), "s.f64", "--grid 40x24 --derivatives --normals"},
      {"aeb_obj", aebSurface(), "s.obj", "--grid 37x23"},
      {"span_obj", kOneSpan, "c.obj", "--samples 700"},
      {"span_ply", kOneSpan, "c.ply", "--samples 700 --derivatives"},
      {"span_csv", aebCurve(), "c.csv", "--samples 700 --derivatives"},
      {"span_f64", aebCurve(), "c.f64", "--samples 702 --derivatives"},
      {"span_svg", aebCurve(), "c.svg", "--samples 700"},
  };
}

TEST(MemoryBoundCuts, CpuEveryFormat) {
  for (const Case& c : cases()) expectSameBytesAcrossCuts(c, "--device cpu", kCpuCuts);
}

// The Vulkan kernels take the row range from their push constants (surface_grid, surface_eval,
// curve_grid with runs of a span, curve_eval); lavapipe is slow, so fewer cases per precision.
void vulkanCuts(const std::string& precision) {
  const std::string device = "--device vulkan --require-device --precision " + precision;
  for (const Case& c : cases()) {
    const bool pick = c.tag == "patch_f32" || c.tag == "aeb_f64" || c.tag == "span_obj" || c.tag == "span_f64" ||
                      (precision == "float" && c.tag == "patch_obj");
    if (!pick) continue;
    Case v = c;
    v.tag += "_vk_" + precision;
    expectSameBytesAcrossCuts(v, device, kGpuCuts);
  }
}

TEST(MemoryBoundCuts, VulkanFloat) {
  REQUIRE_VULKAN();
  vulkanCuts("float");
}

TEST(MemoryBoundCuts, VulkanDouble) {
  REQUIRE_VULKAN();
  vulkanCuts("double");
}

}  // namespace
}  // namespace shapespline::test
