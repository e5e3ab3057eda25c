// `eval` on every golden curve/surface case: the model and inputs are written to disk unchanged and
// the printed samples are compared with the exact expectations at the golden tolerances (fp64 on
// cpu and vulkan, fp32 on vulkan within the fp32 tolerance).
#include "cli_runner.h"
#include "support/golden.h"

#include <gtest/gtest.h>

#include <cmath>

namespace shapespline::test {
namespace {

struct Variant {
  const char* name;
  const char* args;
  bool fp32;
  bool gpu;
};

double tolFor(const json& tol, const std::string& field, bool fp32) {
  const char* key = fp32 ? "fp32" : "fp64";
  if (tol.contains("fields") && tol["fields"].contains(field)) return number(tol["fields"][field][key]);
  return number(tol[key]);
}

// Compares one expected vector (strings) with the printed one (numbers); returns the failures.
void compareVec(const std::string& label, const json& expected, const json& actual, double tol,
                std::vector<std::string>& failures, double& worst) {
  if (!actual.is_array() || actual.size() != expected.size()) {
    failures.push_back(label + ": expected " + expected.dump() + ", got " + actual.dump());
    return;
  }
  for (size_t k = 0; k < expected.size(); ++k) {
    const double e = number(expected[k]), a = actual[k].get<double>();
    const double err = std::fabs(e - a);
    worst = std::max(worst, err / tol);
    if (!(err <= tol)) {
      char buf[256];
      std::snprintf(buf, sizeof buf, "[%zu] expected %.17g got %.17g err %.3g tol %.3g", k, e, a, err, tol);
      failures.push_back(label + buf);
    }
  }
}

void runVariant(const Variant& v) {
  ScratchDir dir(std::string("golden_") + v.name);
  int cases = 0;
  double worst = 0.0;
  std::vector<std::string> failures;
  for (const auto& file : loadGoldenFiles()) {
    for (const auto& c : file.doc["cases"]) {
      const std::string family = c["family"];
      if (family != "curve" && family != "surface") continue;
      ++cases;
      const std::string id = c["id"];
      writeText(dir / "model.json", c["model"].dump());
      writeText(dir / "inputs.json", c["inputs"].dump());
      const CliResult r = runCli("eval " + quote((dir / "model.json").string()) + " --at " +
                                     quote((dir / "inputs.json").string()) + " " + v.args,
                                 dir.path());
      if (r.rc != 0) {
        failures.push_back(id + ": exit " + std::to_string(r.rc) + ": " + r.err);
        continue;
      }
      if (v.gpu && r.err.find("CPU fp64 path") != std::string::npos &&
          c["model"].value("construction", "") != "bspline") {
        failures.push_back(id + ": expected the GPU path, stderr: " + r.err);
      }
      const json out = json::parse(r.out);
      const json& exp = c["expected"]["samples"];
      if (out["samples"].size() != exp.size()) {
        failures.push_back(id + ": sample count " + std::to_string(out["samples"].size()));
        continue;
      }
      const json& tol = c["tolerance"];
      for (size_t i = 0; i < exp.size(); ++i) {
        const json& e = exp[i];
        const json& a = out["samples"][i];
        for (const auto& [key, value] : e.items()) {
          const std::string label = id + " sample " + std::to_string(i) + " " + key;
          if (key == "span" || key == "patch") {
            if (a[key] != value) failures.push_back(label + ": mismatch " + a[key].dump());
            continue;
          }
          if (key == "t" || key == "u") {
            if (!a.contains(key)) { failures.push_back(label + ": missing"); continue; }
            const double err = std::fabs(number(value) - a[key].get<double>());
            if (err > 1e-12 * std::max(1.0, std::fabs(number(value)))) failures.push_back(label + ": " + a[key].dump());
            continue;
          }
          if (key == "uv" || key == "UV") {
            compareVec(label, value, a[key], 1e-12, failures, worst);
            continue;
          }
          if (!a.contains(key)) {
            failures.push_back(label + ": missing in output");
            continue;
          }
          if (value.is_null()) {
            if (!a[key].is_null()) failures.push_back(label + ": expected null, got " + a[key].dump());
            continue;
          }
          if (a[key].is_null()) {
            failures.push_back(label + ": got null");
            continue;
          }
          compareVec(label, value, a[key], tolFor(tol, key, v.fp32), failures, worst);
        }
      }
    }
  }
  std::printf("[golden eval %s] %d cases, worst error/tolerance %.3g\n", v.name, cases, worst);
  EXPECT_GT(cases, 10);
  for (size_t i = 0; i < failures.size() && i < 40; ++i) ADD_FAILURE() << failures[i];
  EXPECT_TRUE(failures.empty()) << failures.size() << " failures";
}

bool vulkanDevice() {
  ScratchDir dir("info_probe");
  const CliResult r = runCli("info", dir.path());
  return r.rc == 0 && r.out.find("selected: none") == std::string::npos;
}

TEST(CliGoldenEval, CpuDouble) { runVariant({"cpu_fp64", "--device cpu", false, false}); }
TEST(CliGoldenEval, CpuFloatOutput) { runVariant({"cpu_fp32", "--device cpu --precision float -q", true, false}); }
TEST(CliGoldenEval, VulkanDouble) {
  if (!vulkanDevice()) GTEST_SKIP() << "no Vulkan device";
  runVariant({"vulkan_fp64", "--device vulkan", false, true});
}
TEST(CliGoldenEval, VulkanFloat) {
  if (!vulkanDevice()) GTEST_SKIP() << "no Vulkan device";
  runVariant({"vulkan_fp32", "--device vulkan --precision float", true, true});
}

}  // namespace
}  // namespace shapespline::test
