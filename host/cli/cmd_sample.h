#pragma once
// The `sample` command's arguments and entry point, also used by `demo`.
#include <string>

namespace shapespline::cli {

struct SampleArgs {
  std::string model, out, grid, device = "vulkan", precision = "double", shard;
  int samples = 0, threads = 0;
  bool derivatives = false, normals = false, quiet = false;
};

void runSample(const SampleArgs& args);

}  // namespace shapespline::cli
