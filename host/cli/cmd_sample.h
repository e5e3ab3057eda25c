#pragma once
// The `sample` command's arguments and entry point, also used by `demo`.
#include <string>

namespace shapespline::cli {

struct SampleArgs {
  std::string model, out, grid, device = "auto", precision = "double", shard;
  std::string samples;  // --samples as given ("" = not given: the default)
  std::string shardCount;  // --shard-count as given ("" = not given; --shard auto only)
  std::string meshLayout = "welded";
  std::string fields;  // --fields as given ("" = from --derivatives / --normals)  // --mesh-layout: welded or per-item (OBJ, PLY)
  int threads = 0;
  long long chunkPoints = 0;  // 0 = default (CPU sampler and GPU evaluator defaults)
  bool derivatives = false, normals = false, quiet = false, requireDevice = false;
};

void runSample(const SampleArgs& args);

}  // namespace shapespline::cli
