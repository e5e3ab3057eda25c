// Checks every case of every golden file against the CPU fp64 core. Unknown families and
// expected fields that no checker compares fail the test (see support/golden.h).
#include <gtest/gtest.h>

#include "core/golden_registry.h"

namespace shapespline::test {

GoldenRegistry& coreGoldenRegistry() {
  static GoldenRegistry registry;
  return registry;
}

namespace {

class CoreGolden : public ::testing::TestWithParam<std::string> {};

TEST_P(CoreGolden, EveryCaseMatches) {
  const auto files = loadGoldenFiles();
  bool found = false;
  for (const auto& f : files) {
    if (f.name != GetParam()) continue;
    found = true;
    const auto failures = runGoldenFile(f, coreGoldenRegistry(), "cpu-fp64");
    for (const auto& msg : failures) ADD_FAILURE() << msg;
  }
  EXPECT_TRUE(found) << GetParam() << " not in " << goldenDir();
}

// Any golden file the list below does not name still runs here, so a new file cannot be missed.
TEST(CoreGoldenFolder, golden_NoFileIsLeftOut) {
  const std::set<std::string> known = {
      "basis_gb.json",     "basis_gubp.json",   "basis_singular_blend.json", "basis_ubp.json",
      "basis_xuwang.json", "curves_alpha_eb.json", "curves_plain.json",      "extension.json",
      "gb_modify.json",    "surfaces.json",     "validation.json"};
  for (const auto& f : loadGoldenFiles()) {
    if (known.count(f.name)) continue;
    for (const auto& msg : runGoldenFile(f, coreGoldenRegistry(), "cpu-fp64")) ADD_FAILURE() << msg;
  }
}

std::string fileParamName(const ::testing::TestParamInfo<std::string>& info) {
  std::string s = info.param.substr(0, info.param.find('.'));
  return s;
}

INSTANTIATE_TEST_SUITE_P(golden, CoreGolden,
                         ::testing::Values("basis_gb.json", "basis_gubp.json", "basis_singular_blend.json",
                                           "basis_ubp.json", "basis_xuwang.json", "curves_alpha_eb.json",
                                           "curves_plain.json", "extension.json", "gb_modify.json",
                                           "surfaces.json", "validation.json"),
                         fileParamName);

}  // namespace
}  // namespace shapespline::test
