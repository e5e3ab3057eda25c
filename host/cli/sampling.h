#pragma once
// The one place the CLI chooses between the CPU fp64 grid sampler (core/grid_sampler.h) and the
// GPU evaluators (host/gpu). Delivers GridChunks in item order either way.
#include "cli/common.h"
#include "core/grid_sampler.h"

#include <array>
#include <utility>
#include <vector>

namespace shapespline::cli {

struct GridJob {
  const Curve* curve = nullptr;      // exactly one of curve / surface
  const Surface* surface = nullptr;
  GridSpec grid;                     // itemCount > 0
  FieldMask fields = 0;
  Precision precision = Precision::Double;
  Device device = Device::Cpu;       // as returned by resolveDevice
  int threads = 0;
};

void runGrid(const GridJob& job, const ChunkConsumer& consumer);

// False (with a notice) for models the GPU evaluators do not handle: knot-vector B-splines.
bool gpuHandles(const Curve* curve, const Surface* surface, bool quiet);

// GPU list evaluation (device must be Device::Vulkan from resolveDevice): (span, t) / (i, j, u, v).
std::vector<CurvePoint> gpuEvaluateCurve(const Curve& curve, const std::vector<std::pair<int, double>>& samples,
                                         Precision precision);
std::vector<SurfacePoint> gpuEvaluateSurface(const Surface& surface, const std::vector<std::array<double, 4>>& samples,
                                             Precision precision);

}  // namespace shapespline::cli
