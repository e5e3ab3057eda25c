#pragma once
// Models the GPU kernels do not resolve in a given precision, with the reason the sampling layer
// reports when it hands them to the CPU fp64 path instead.
#include <shapespline/core/curve.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/core/surface.h>

#include <optional>
#include <string>

namespace shapespline::sampling {

// Beyond this GB λ the fp32 kernels lose more than 3 of 7 digits of the normals (and produce NaN
// normals for degenerate nets from about 1e12); fp64 kernels are unaffected.
inline constexpr double kMaxGBLambdaFloat = 1e4;

// The kernels compute V = P + ((1-α)/α)(P - node) in their own precision on a net scaled into
// [2^-20, 2^20] (fp32) / [2^-200, 2^200] (fp64): below these α the factor 1/α leaves the fp32 range
// (V up to 2^21 / α must stay below 3.4e38), or α itself is near the subnormals that GPUs may flush
// to zero. The CPU fp64 path evaluates such models (it refuses only an α whose V exceeds fp64).
inline constexpr double kMinAlphaGpuFloat = 1e-30;
inline constexpr double kMinAlphaGpuDouble = 1e-300;

// The B-spline kernels run the de Boor–Cox recursion in their own precision, dividing by knot
// differences: a non-empty knot interval below these is near the subnormals GPUs may flush to zero
// (NaN instead of a value); in fp32 an interval must also survive rounding its knots to fp32.
inline constexpr double kMinKnotIntervalGpuFloat = 1e-30;
inline constexpr double kMinKnotIntervalGpuDouble = 1e-300;
// The fp32 kernels read PARAMS indices (spans, first control points, record offsets; up to 118
// values per knot: knots, interval and knot patch records, shaders/layout.h) as fp32 values, exact
// below 2^24: at most this many knots per direction.
inline constexpr size_t kMaxKnotsGpuFloat = 65536;

// Why the `precision` kernels cannot evaluate the model, or nullopt when they can.
std::optional<std::string> gpuLimitation(const Curve& curve, Precision precision);
std::optional<std::string> gpuLimitation(const Surface& surface, Precision precision);
// The same for a uniform-span surface of this shape whose smallest α is `smallestAlpha` (a net
// streamed from its files, never built).
std::optional<std::string> gpuLimitation(const SurfaceShape& shape, double smallestAlpha, Precision precision);

}  // namespace shapespline::sampling
