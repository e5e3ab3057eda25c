// Writes the `eval --at` fuzz seed corpus into a folder: the `inputs` of every curve and surface
// golden case (tests/data/golden, or $SHAPESPLINE_GOLDEN_DIR, read in place) and a set of good and
// bad sample lists (every form, every rule of io/sample_list.h, and the input limits of
// io/input_file.h), so that the fuzzer starts from both sides of every check.
// Usage: eval_at_fuzz_seeds OUT_DIR. Files are named by origin so that a finding can be traced back.
#include <cctype>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "support/golden.h"
#include "seed_files.h"

namespace fs = std::filesystem;

namespace {

using shapespline::fuzz::seedName;
using shapespline::fuzz::writeSeed;

std::string nested(size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

std::vector<std::pair<std::string, std::string>> handwritten() {
  std::string keys = "{\"samples\": [{\"span\": 0, \"t\": 0.5}]";
  for (int i = 0; i < 1100; ++i) keys += ", \"k" + std::to_string(i) + "\": 0";
  return {
      {"good_span_t", R"({"samples": [{"span": 0, "t": 0}, {"span": 1, "t": 0.5}, {"span": 2, "t": 1}]})"},
      {"good_global_u", R"({"samples": [{"u": 0}, {"u": 0.75}, {"u": 1}, {"u": 2}]})"},
      {"good_patch_uv", R"({"samples": [{"patch": [0, 0], "uv": [0, 0]}, {"patch": [1, 0], "uv": [0.5, 1]}]})"},
      {"good_mixed", R"({"samples": [{"span": 0, "t": 0.25}, {"u": 0.5}, {"patch": [0, 1], "uv": [0.25, 0.75]}]})"},
      {"good_empty", R"({"samples": []})"},
      {"bad_not_object", R"([{"span": 0, "t": 0}])"},
      {"bad_no_samples", R"({"sample": []})"},
      {"bad_sample_type", R"({"samples": [1, "x", null, [0, 0]]})"},
      {"bad_span_float", R"({"samples": [{"span": 0.5, "t": 0}]})"},
      {"bad_span_huge", R"({"samples": [{"span": 1e300, "t": 0}]})"},
      {"bad_span_negative", R"({"samples": [{"span": -1, "t": 0}]})"},
      {"bad_t_range", R"({"samples": [{"span": 0, "t": 1.0000000000000002}]})"},
      {"bad_t_string", R"({"samples": [{"span": 0, "t": "0.5"}]})"},
      {"bad_u_huge", R"({"samples": [{"u": 1e308}]})"},
      {"bad_u_overflow", R"({"samples": [{"u": 1e999}]})"},
      {"bad_patch_shape", R"({"samples": [{"patch": [0], "uv": [0, 0]}]})"},
      {"bad_patch_range", R"({"samples": [{"patch": [0, 99], "uv": [0, 0]}]})"},
      {"bad_uv_range", R"({"samples": [{"patch": [0, 0], "uv": [-0.0, 1.5]}]})"},
      {"bad_duplicate_key", R"({"samples": [{"span": 0, "t": 0, "t": 1}]})"},
      {"bad_malformed", R"({"samples": [{"span": 0, "t": )"},
      {"bad_deep", "{\"samples\": [" + nested(100) + "]}"},
      {"bad_many_keys", keys + "}"},
      {"bad_long_string", "{\"samples\": [\"" + std::string(2000, 'x') + "\"]}"},
  };
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: eval_at_fuzz_seeds OUT_DIR\n");
    return 2;
  }
  try {
    const fs::path out = argv[1];
    fs::create_directories(out);
    size_t golden = 0, written = 0;
    for (const auto& file : shapespline::test::loadGoldenFiles())
      for (const auto& c : file.doc.at("cases")) {
        const std::string family = c.value("family", "");
        if ((family != "curve" && family != "surface") || !c.contains("inputs")) continue;
        writeSeed(out / ("golden_" + seedName(c.at("id").get<std::string>()) + ".json"), c.at("inputs").dump());
        ++golden;
      }
    for (const auto& [name, text] : handwritten()) {
      writeSeed(out / (name + ".json"), text);
      ++written;
    }
    std::printf("eval_at_fuzz_seeds: %zu golden sample lists, %zu handwritten -> %s\n", golden, written, out.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "eval_at_fuzz_seeds: %s\n", e.what());
    return 1;
  }
}
