#pragma once
// The one place the CLI chooses between the CPU fp64 grid sampler (core/grid_sampler.h) and the
// GPU evaluators (host/gpu). Delivers GridChunks in item order either way.
#include <shapespline/cli/common.h>
#include <shapespline/core/grid_sampler.h>

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

// Exponent k such that the GPU evaluates 2^k * net: 0 for nets of ordinary magnitude; for nets
// whose largest coordinate M lies outside [2^-20, 2^20] (fp32) or [2^-200, 2^200] (fp64), the k
// that brings M into [1, 2). Products of coordinates inside the kernels (normals, squared lengths)
// then stay in range. An exponent, not the factor: for a subnormal net (M down to 2^-1074) 2^k is
// beyond the fp64 range, while std::ldexp(x, k) scales every coordinate exactly.
int netScale(const std::vector<glm::dvec3>& points, Precision precision);

// False (with a notice) for models the GPU evaluators do not handle: knot-vector B-splines, in
// fp32 GB λ above kMaxGBLambdaFloat, and α-EB models with α below kMinAlphaGpuFloat / Double; with
// `require` (--require-device) a RuntimeError instead.
bool gpuHandles(const Curve* curve, const Surface* surface, Precision precision, bool quiet, bool require = false);

// Beyond this GB λ the fp32 kernels lose more than 3 of 7 digits of the normals (and produce NaN
// normals for degenerate nets from about 1e12); fp64 kernels are unaffected.
inline constexpr double kMaxGBLambdaFloat = 1e4;

// The kernels compute V = P + ((1-α)/α)(P - node) in their own precision on a net scaled into
// [2^-20, 2^20] (fp32) / [2^-200, 2^200] (fp64): below these α the factor 1/α leaves the fp32 range
// (V up to 2^21 / α must stay below 3.4e38), or α itself is near the subnormals that GPUs may flush
// to zero. The CPU fp64 path evaluates such models (it refuses only an α whose V exceeds fp64).
inline constexpr double kMinAlphaGpuFloat = 1e-30;
inline constexpr double kMinAlphaGpuDouble = 1e-300;

// GPU list evaluation (device must be Device::Vulkan from resolveDevice): (span, t) / (i, j, u, v).
std::vector<CurvePoint> gpuEvaluateCurve(const Curve& curve, const std::vector<std::pair<int, double>>& samples,
                                         Precision precision);
std::vector<SurfacePoint> gpuEvaluateSurface(const Surface& surface, const std::vector<std::array<double, 4>>& samples,
                                             Precision precision);

}  // namespace shapespline::cli
