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
  int threads = 0;                   // CPU sampler threads (0 = all)
  size_t chunkPoints = 0;            // points per chunk (0 = default); GPU: planes of this many points
};

// Vulkan failures become RuntimeError("vulkan", ...) (exit 3) with a hint. On the GPU the net is
// scaled by a power of two (exact) when its magnitude is outside what the precision's kernels
// handle without overflow/underflow (netScale), and the results are scaled back.
void runGrid(const GridJob& job, const ChunkConsumer& consumer);

// Power of two s such that the GPU evaluates s * net: 1 for nets of ordinary magnitude; for nets
// whose largest coordinate M lies outside [2^-20, 2^20] (fp32) or [2^-200, 2^200] (fp64), the s
// that brings M into [1, 2). Products of coordinates inside the kernels (normals, squared lengths)
// then stay in range.
double netScale(const std::vector<glm::dvec3>& points, Precision precision);

// False (with a notice) for models the GPU evaluators do not handle: knot-vector B-splines, and in
// fp32 GB λ above kMaxGBLambdaFloat; with `require` (--require-device) a RuntimeError instead.
bool gpuHandles(const Curve* curve, const Surface* surface, Precision precision, bool quiet, bool require = false);

// Beyond this GB λ the fp32 kernels lose more than 3 of 7 digits of the normals (and produce NaN
// normals for degenerate nets from about 1e12); fp64 kernels are unaffected.
inline constexpr double kMaxGBLambdaFloat = 1e4;

// GPU list evaluation (device must be Device::Vulkan from resolveDevice): (span, t) / (i, j, u, v).
std::vector<CurvePoint> gpuEvaluateCurve(const Curve& curve, const std::vector<std::pair<int, double>>& samples,
                                         Precision precision);
std::vector<SurfacePoint> gpuEvaluateSurface(const Surface& surface, const std::vector<std::array<double, 4>>& samples,
                                             Precision precision);

}  // namespace shapespline::cli
