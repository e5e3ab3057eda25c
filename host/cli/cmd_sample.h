#pragma once
// The `sample` command's arguments and entry point, also used by `demo`.
#include <string>

namespace shapespline::cli {

struct SampleArgs {
  std::string model, out, grid, device = "vulkan", precision = "double", shard;
  int samples = 0, threads = 0;
  long long chunkPoints = 0;  // 0 = default (CPU 2^18 points; GPU 64 MiB planes)
  bool derivatives = false, normals = false, quiet = false, requireDevice = false;
};

void runSample(const SampleArgs& args);

}  // namespace shapespline::cli
