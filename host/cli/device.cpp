// Device choice and the grid / list dispatch between the CPU fp64 path (core) and the Vulkan
// evaluators (host/gpu). `--device vulkan` falls back to the CPU with a notice on stderr when no
// Vulkan device exists, when fp64 is asked of a device without shaderFloat64, or for knot-vector
// B-splines (which the GPU evaluators do not handle); with --require-device each of those is an
// error instead (exit 3). Any other Vulkan failure is exit code 3 with a hint.
#include <shapespline/cli/common.h>
#include <shapespline/cli/sampling.h>
#include <shapespline/gpu/evaluator.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/vk/context.h>
#include <shapespline/vk/error.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>

namespace shapespline::cli {
namespace {

std::shared_ptr<vk::Context>& gpuContext() {
  static std::shared_ptr<vk::Context> ctx;
  return ctx;
}

void notice(bool quiet, const std::string& text) {
  if (!quiet) std::fprintf(stderr, "shapespline: notice: %s\n", text.c_str());
}

// The CPU fallback, or (with --require-device) the error that replaces it.
Device fallBack(bool require, bool quiet, const std::string& why) {
  if (require) throw RuntimeError("--require-device", "", why + "; the CPU fallback is disabled (no output written)");
  notice(quiet, why + "; falling back to the CPU fp64 path");
  return Device::Cpu;
}

[[noreturn]] void rethrowVulkan(const vk::VulkanError& e) {
  std::string hint;
  switch (e.result()) {
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      hint = "out of GPU memory: try a smaller --chunk-points, or --device cpu";
      break;
    case VK_ERROR_DEVICE_LOST:
      hint = "retry, or use --device cpu";
      break;
    default:
      hint = "--device cpu avoids the GPU";
      break;
  }
  throw RuntimeError("vulkan", "", std::string(e.what()) + "; " + hint + " (no output written)");
}

glm::dvec3 ldexp3(const glm::dvec3& p, int k) { return {std::ldexp(p.x, k), std::ldexp(p.y, k), std::ldexp(p.z, k)}; }

std::vector<glm::dvec3> scaled(std::vector<glm::dvec3> points, int k) {
  for (auto& p : points) p = ldexp3(p, k);
  return points;
}

// The GPU sees 2^k * net; every field but the unit normal is linear in the net, so it is scaled
// back by 2^-k (exact unless the value leaves the precision's range, where it rounds once).
class Rescale {
 public:
  explicit Rescale(int exponent) : k_(-exponent) {}
  void operator()(const GridChunk& chunk, const ChunkConsumer& consumer) {
    if (k_ == 0) return consumer(chunk);
    GridChunk out = chunk;
    const size_t n = chunk.pointCount() * 3;
    for (int f = 0; f < kFieldCount; ++f) {
      const void* src = chunk.planes[static_cast<size_t>(f)];
      if (!src || f == static_cast<int>(Field::Normal)) continue;
      if (chunk.precision == Precision::Double) {
        auto& buf = doubles_[static_cast<size_t>(f)];
        buf.resize(n);
        for (size_t i = 0; i < n; ++i) buf[i] = std::ldexp(static_cast<const double*>(src)[i], k_);
        out.planes[static_cast<size_t>(f)] = buf.data();
      } else {
        auto& buf = floats_[static_cast<size_t>(f)];
        buf.resize(n);
        for (size_t i = 0; i < n; ++i) {
          buf[i] = static_cast<float>(std::ldexp(static_cast<double>(static_cast<const float*>(src)[i]), k_));
        }
        out.planes[static_cast<size_t>(f)] = buf.data();
      }
    }
    consumer(out);
  }

 private:
  int k_;
  std::array<std::vector<double>, kFieldCount> doubles_;
  std::array<std::vector<float>, kFieldCount> floats_;
};

Curve scaledCurve(const Curve& curve, int s) {
  CurveModel m = curve.model();
  m.points = scaled(std::move(m.points), s);
  return Curve::create(std::move(m));
}

Surface scaledSurface(const Surface& surface, int s) {
  SurfaceModel m = surface.model();
  m.points = scaled(std::move(m.points), s);
  return Surface::create(std::move(m));
}

}  // namespace

int netScale(const std::vector<glm::dvec3>& points, Precision precision) {
  double m = 0.0;
  for (const auto& p : points) m = std::max({m, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  if (!(m > 0.0) || !std::isfinite(m)) return 0;
  const int e = std::ilogb(m);  // m in [2^e, 2^(e+1)), also for subnormal m (e down to -1074)
  const int band = precision == Precision::Float ? 20 : 200;
  return e >= -band && e < band ? 0 : -e;
}

Device resolveDevice(Device requested, Precision precision, bool quiet, bool require) {
  if (requested == Device::Cpu) {
    if (precision == Precision::Float) notice(quiet, "the CPU path computes in fp64; --precision float only rounds the output");
    return Device::Cpu;
  }
  try {
    vk::ContextOptions options;
    options.preferFp64 = precision == Precision::Double;
    gpuContext() = vk::Context::create(options);
  } catch (const vk::NoDeviceError& e) {
    return fallBack(require, quiet, std::string("no Vulkan device (") + e.reason() + ")");
  } catch (const vk::VulkanError& e) {
    rethrowVulkan(e);
  }
  if (precision == Precision::Double && !gpuContext()->supportsFloat64()) {
    const std::string name = gpuContext()->deviceName();
    gpuContext().reset();
    return fallBack(require, quiet,
                    "Vulkan device '" + name + "' has no shaderFloat64 (use --precision float for the GPU)");
  }
  return Device::Vulkan;
}

bool gpuHandles(const Curve* curve, const Surface* surface, Precision precision, bool quiet, bool require) {
  const bool knots = curve ? curve->usesKnotVector() : surface->usesKnotVector();
  if (knots) {
    fallBack(require, quiet, "knot-vector B-splines have no GPU kernel");
    return false;
  }
  const FamilySpec& family = curve ? curve->model().family : surface->model().family;
  if (precision == Precision::Float && family.construction == Construction::GB && family.lambda > kMaxGBLambdaFloat) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", family.lambda);
    fallBack(require, quiet,
             std::string("GB lambda = ") + text + " is beyond what the fp32 GPU kernels resolve (above 1e4 normals "
                 "lose more than 3 of 7 digits)");
    return false;
  }
  if (family.construction == Construction::AlphaEB) {
    const std::vector<double>& alpha = curve ? curve->model().alpha : surface->model().alpha;
    const double limit = precision == Precision::Float ? kMinAlphaGpuFloat : kMinAlphaGpuDouble;
    const auto lowest = std::min_element(alpha.begin(), alpha.end());
    if (lowest != alpha.end() && *lowest < limit) {
      char text[64];
      std::snprintf(text, sizeof text, "alpha = %.3g is below %.0e", *lowest, limit);
      fallBack(require, quiet,
               std::string(text) + ", the smallest the " + (precision == Precision::Float ? "fp32" : "fp64") +
                   " GPU kernels represent in V = P + ((1-alpha)/alpha)(P - node)");
      return false;
    }
  }
  return true;
}

void runGrid(const GridJob& job, const ChunkConsumer& consumer) {
  if (job.device == Device::Vulkan && gpuContext()) {
    gpu::EvaluatorOptions options;
    if (job.chunkPoints > 0) {
      // Planes of chunkPoints points: the evaluator cuts an item larger than that into row ranges.
      const size_t real = job.precision == Precision::Double ? 8 : 4;
      options.maxPlaneBytes = (job.chunkPoints * 3 + 4) * real;
    }
    const int s = netScale(job.curve ? job.curve->model().points : job.surface->model().points, job.precision);
    Rescale rescale(s);
    const ChunkConsumer deliver = [&](const GridChunk& chunk) { rescale(chunk, consumer); };
    try {
      if (job.curve) {
        const std::optional<Curve> copy = s != 0 ? std::optional(scaledCurve(*job.curve, s)) : std::nullopt;
        gpu::CurveEvaluator evaluator(gpuContext(), job.precision, options);
        gpu::GpuCurve model(gpuContext(), copy ? *copy : *job.curve, job.precision);
        evaluator.evaluateGrid(model, job.grid, job.fields, deliver);
      } else {
        const std::optional<Surface> copy = s != 0 ? std::optional(scaledSurface(*job.surface, s)) : std::nullopt;
        gpu::SurfaceEvaluator evaluator(gpuContext(), job.precision, options);
        gpu::GpuSurface model(gpuContext(), copy ? *copy : *job.surface, job.precision);
        evaluator.evaluateGrid(model, job.grid, job.fields, deliver);
      }
    } catch (const vk::VulkanError& e) {
      rethrowVulkan(e);
    }
    return;
  }
  SamplerOptions options;
  options.threads = job.threads;
  options.maxChunkPoints = job.chunkPoints > 0 ? job.chunkPoints : size_t{1} << 18;
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
  const int s = netScale(curve.model().points, precision);
  std::vector<CurvePoint> out;
  try {
    const std::optional<Curve> copy = s != 0 ? std::optional(scaledCurve(curve, s)) : std::nullopt;
    gpu::CurveEvaluator evaluator(gpuContext(), precision);
    gpu::GpuCurve model(gpuContext(), copy ? *copy : curve, precision);
    out = evaluator.evaluateList(model, list);
  } catch (const vk::VulkanError& e) {
    rethrowVulkan(e);
  }
  if (s != 0) {
    for (auto& p : out) p.point = ldexp3(p.point, -s), p.d1 = ldexp3(p.d1, -s), p.d2 = ldexp3(p.d2, -s);
  }
  return out;
}

std::vector<SurfacePoint> gpuEvaluateSurface(const Surface& surface, const std::vector<std::array<double, 4>>& samples,
                                             Precision precision) {
  std::vector<gpu::SurfaceSample> list;
  list.reserve(samples.size());
  for (const auto& q : samples) list.push_back({static_cast<int>(q[0]), static_cast<int>(q[1]), q[2], q[3]});
  const int s = netScale(surface.model().points, precision);
  std::vector<SurfacePoint> out;
  try {
    const std::optional<Surface> copy = s != 0 ? std::optional(scaledSurface(surface, s)) : std::nullopt;
    gpu::SurfaceEvaluator evaluator(gpuContext(), precision);
    gpu::GpuSurface model(gpuContext(), copy ? *copy : surface, precision);
    out = evaluator.evaluateList(model, list);
  } catch (const vk::VulkanError& e) {
    rethrowVulkan(e);
  }
  if (s != 0) {
    for (auto& p : out) {
      p.point = ldexp3(p.point, -s), p.du = ldexp3(p.du, -s), p.dv = ldexp3(p.dv, -s);  // normal: unit
      p.duu = ldexp3(p.duu, -s), p.duv = ldexp3(p.duv, -s), p.dvv = ldexp3(p.dvv, -s);
    }
  }
  return out;
}

}  // namespace shapespline::cli
