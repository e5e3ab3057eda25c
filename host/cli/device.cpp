// Device choice and the grid / list dispatch between the CPU fp64 path (core) and the Vulkan
// evaluators (host/gpu). `--device vulkan` falls back to the CPU with a notice on stderr when no
// Vulkan device exists, when fp64 is asked of a device without shaderFloat64, or for knot-vector
// B-splines (which the GPU evaluators do not handle); any other Vulkan failure is exit code 3.
#include "cli/common.h"
#include "cli/sampling.h"
#include "gpu/evaluator.h"
#include "gpu/gpu_model.h"
#include "vk/context.h"
#include "vk/error.h"

#include <cstdio>

namespace shapespline::cli {
namespace {

std::shared_ptr<vk::Context>& gpuContext() {
  static std::shared_ptr<vk::Context> ctx;
  return ctx;
}

void notice(bool quiet, const std::string& text) {
  if (!quiet) std::fprintf(stderr, "shapespline: notice: %s\n", text.c_str());
}

}  // namespace

Device resolveDevice(Device requested, Precision precision, bool quiet) {
  if (requested == Device::Cpu) {
    if (precision == Precision::Float) notice(quiet, "the CPU path computes in fp64; --precision float only rounds the output");
    return Device::Cpu;
  }
  try {
    vk::ContextOptions options;
    options.preferFp64 = precision == Precision::Double;
    gpuContext() = vk::Context::create(options);
  } catch (const vk::NoDeviceError& e) {
    notice(quiet, std::string("no Vulkan device (") + e.reason() + "); falling back to the CPU fp64 path");
    return Device::Cpu;
  }
  if (precision == Precision::Double && !gpuContext()->supportsFloat64()) {
    notice(quiet, "Vulkan device '" + gpuContext()->deviceName() +
                      "' has no shaderFloat64; falling back to the CPU fp64 path (use --precision float for the GPU)");
    gpuContext().reset();
    return Device::Cpu;
  }
  return Device::Vulkan;
}

bool gpuHandles(const Curve* curve, const Surface* surface, bool quiet) {
  const bool knots = curve ? curve->usesKnotVector() : surface->usesKnotVector();
  if (knots) notice(quiet, "knot-vector B-splines are evaluated on the CPU fp64 path (no GPU kernel for them)");
  return !knots;
}

void runGrid(const GridJob& job, const ChunkConsumer& consumer) {
  if (job.device == Device::Vulkan && gpuContext()) {
    if (job.curve) {
      gpu::CurveEvaluator evaluator(gpuContext(), job.precision);
      gpu::GpuCurve model(gpuContext(), *job.curve, job.precision);
      evaluator.evaluateGrid(model, job.grid, job.fields, consumer);
    } else {
      gpu::SurfaceEvaluator evaluator(gpuContext(), job.precision);
      gpu::GpuSurface model(gpuContext(), *job.surface, job.precision);
      evaluator.evaluateGrid(model, job.grid, job.fields, consumer);
    }
    return;
  }
  SamplerOptions options;
  options.threads = job.threads;
  options.maxChunkPoints = size_t{1} << 18;
  if (job.curve) {
    sampleCurveGrid(*job.curve, job.grid, job.fields, consumer, options);
  } else {
    sampleSurfaceGrid(*job.surface, job.grid, job.fields, consumer, options);
  }
}

std::vector<CurvePoint> gpuEvaluateCurve(const Curve& curve, const std::vector<std::pair<int, double>>& samples,
                                         Precision precision) {
  std::vector<gpu::CurveSample> list;
  list.reserve(samples.size());
  for (const auto& [s, t] : samples) list.push_back({s, t});
  gpu::CurveEvaluator evaluator(gpuContext(), precision);
  gpu::GpuCurve model(gpuContext(), curve, precision);
  return evaluator.evaluateList(model, list);
}

std::vector<SurfacePoint> gpuEvaluateSurface(const Surface& surface, const std::vector<std::array<double, 4>>& samples,
                                             Precision precision) {
  std::vector<gpu::SurfaceSample> list;
  list.reserve(samples.size());
  for (const auto& s : samples) list.push_back({static_cast<int>(s[0]), static_cast<int>(s[1]), s[2], s[3]});
  gpu::SurfaceEvaluator evaluator(gpuContext(), precision);
  gpu::GpuSurface model(gpuContext(), surface, precision);
  return evaluator.evaluateList(model, list);
}

}  // namespace shapespline::cli
