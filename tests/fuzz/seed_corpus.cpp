// Writes the fuzz seed corpus into a folder: every examples/models/*.json, the `model` of every
// golden case (tests/data/golden or $SHAPESPLINE_GOLDEN_DIR, read in place) and every entry of the
// bad-input catalog (tests/support/bad_models.h).
// Usage: model_fuzz_seeds OUT_DIR. Files are named by origin so that a finding can be traced back.
#include <cctype>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "support/bad_models.h"
#include "support/golden.h"
#include "seed_files.h"

namespace fs = std::filesystem;

namespace {

using shapespline::fuzz::seedName;
using shapespline::fuzz::writeSeed;

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: model_fuzz_seeds OUT_DIR\n");
    return 2;
  }
  try {
    const fs::path out = argv[1];
    fs::create_directories(out);
    size_t examples = 0, golden = 0, bad = 0;
    const fs::path models = fs::path(SHAPESPLINE_SOURCE_DIR) / "examples" / "models";
    if (fs::is_directory(models))
      for (const auto& entry : fs::directory_iterator(models)) {
        if (entry.path().extension() != ".json") continue;
        std::ifstream in(entry.path(), std::ios::binary);
        writeSeed(out / ("example_" + seedName(entry.path().filename().string())),
              std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
        ++examples;
      }
    for (const auto& file : shapespline::test::loadGoldenFiles())
      for (const auto& c : file.doc.at("cases"))
        if (c.contains("model")) {
          writeSeed(out / ("golden_" + seedName(c.at("id").get<std::string>()) + ".json"), c.at("model").dump());
          ++golden;
        }
    for (const auto& b : shapespline::test::badModelCatalog()) {
      writeSeed(out / ("bad_" + seedName(b.name) + ".json"), b.json_text);
      ++bad;
    }
    std::printf("model_fuzz_seeds: %zu examples, %zu golden models, %zu bad models -> %s\n", examples, golden,
                bad, out.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "model_fuzz_seeds: %s\n", e.what());
    return 1;
  }
}
