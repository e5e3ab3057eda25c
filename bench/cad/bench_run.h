#pragma once
// What every CAD bench does alike: time a run (once, or the best of several after an untimed one
// that warms caches and pipelines), and walk its arguments (`--name value` options, part files).
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapespline::bench {

inline double seconds(const std::function<void()>& run) {
  const auto t0 = std::chrono::steady_clock::now();
  run();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The best of `reps` timed runs after one untimed run.
inline double bestSeconds(int reps, const std::function<void()>& run) {
  run();
  double best = 1e300;
  for (int r = 0; r < reps; ++r) best = std::min(best, seconds(run));
  return best;
}

// Reads the next argument as an option's value (std::invalid_argument when there is none).
using OptionValue = std::function<std::string()>;

// Walks argv: each argument starting with '-' goes to option(name, value), which returns false for
// a name it does not know (std::invalid_argument "unknown option"); every other argument is a part
// file, returned in order.
inline std::vector<std::filesystem::path> parseArguments(
    int argc, char** argv, const std::function<bool(const std::string&, const OptionValue&)>& option) {
  std::vector<std::filesystem::path> parts;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const OptionValue value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a.empty() || a[0] != '-') {
      parts.emplace_back(a);
    } else if (!option(a, value)) {
      throw std::invalid_argument("unknown option " + a);
    }
  }
  return parts;
}

}  // namespace shapespline::bench
