// Benchmark driver: cross-checks every evaluator on sample points first (exit status 2 on a
// mismatch, before any timing), records the machine in the benchmark context, then runs.
#include "workloads.h"

#include <shapespline/io/model_json.h>

#include <benchmark/benchmark.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

int main(int argc, char** argv) {
  using namespace shapespline::bench;
  // --write-model=PATH: the speed workload as a model file (bench/e2e samples it with the CLI).
  const std::string writeModel = "--write-model=";
  if (argc == 2 && std::string(argv[1]).rfind(writeModel, 0) == 0) {
    std::ofstream(std::string(argv[1]).substr(writeModel.size())) << shapespline::io::toJson(bsplineWorkloadModel()).dump()
                                                                   << "\n";
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  benchmark::AddCustomContext("hardware_threads", std::to_string(std::thread::hardware_concurrency()));
#ifdef SHAPESPLINE_HAVE_OPENSUBDIV
  benchmark::AddCustomContext("opensubdiv", "found");
#else
  std::fprintf(stderr, "OpenSubdiv not found at configure time (libosd-dev): its baselines are not built\n");
  benchmark::AddCustomContext("opensubdiv", "not built (libosd-dev missing)");
#endif
  if (const auto ctx = gpuContext()) {
    benchmark::AddCustomContext("vulkan_device", ctx->deviceName());
    benchmark::AddCustomContext("vulkan_fp64", ctx->supportsFloat64() ? "yes" : "no");
  } else {
    std::fprintf(stderr, "%s: Vulkan benchmarks are skipped\n", gpuUnavailableReason().c_str());
    benchmark::AddCustomContext("vulkan_device", "none (" + gpuUnavailableReason() + ")");
  }

  crossCheckSurfaces();
  crossCheckAlphaEB();
  if (!allChecksPassed()) {
    std::fprintf(stderr, "cross-check FAILED: not timing evaluators that disagree\n");
    return 2;
  }
  registerSurfaceBenchmarks();
  registerAlphaEBBenchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
