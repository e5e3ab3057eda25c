#include <shapespline/sampling/session.h>

#include <shapespline/core/cores.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/gpu/evaluator.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/sampling/gpu_limits.h>
#include <shapespline/sampling/net_scale.h>
#include <shapespline/vk/error.h>

#include <algorithm>
#include <exception>
#include <optional>
#include <thread>
#include <type_traits>
#include <vector>
#include <utility>

namespace shapespline::sampling {
namespace {


[[noreturn]] void throwDeviceError(const vk::VulkanError& e) {
  const char* hint = "--device cpu avoids the GPU";
  switch (e.result()) {
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      hint = "out of GPU memory: try a smaller --chunk-points, or --device cpu";
      break;
    case VK_ERROR_DEVICE_LOST:
      hint = "retry, or use --device cpu";
      break;
    default:
      break;
  }
  throw DeviceError(std::string(e.what()) + "; " + hint, false);
}

// Runs a GPU job; every Vulkan failure leaves as DeviceError.
template <class Job>
decltype(auto) onDevice(Job&& job) {
  try {
    return job();
  } catch (const vk::VulkanError& e) {
    throwDeviceError(e);
  }
}

const Curve& pick(const std::optional<Curve>& scaled, const Curve& model) { return scaled ? *scaled : model; }
const Surface& pick(const std::optional<Surface>& scaled, const Surface& model) { return scaled ? *scaled : model; }
std::optional<Curve> scaledOrNot(const Curve& c, int k) { return k ? std::optional(scaledCurve(c, k)) : std::nullopt; }
std::optional<Surface> scaledOrNot(const Surface& s, int k) {
  return k ? std::optional(scaledSurface(s, k)) : std::nullopt;
}

gpu::EvaluatorOptions evaluatorOptions(const GridOptions& options, Precision precision) {
  gpu::EvaluatorOptions e;
  if (options.chunkPoints > 0) {
    // Planes of chunkPoints points: the evaluator cuts an item larger than that into row ranges.
    const size_t real = precision == Precision::Double ? 8 : 4;
    e.maxPlaneBytes = (options.chunkPoints * 3 + 4) * real;
  }
  return e;
}

SamplerOptions samplerOptions(const GridOptions& options) {
  SamplerOptions s;
  s.threads = options.threads;
  s.maxChunkPoints = options.chunkPoints > 0 ? options.chunkPoints : kDefaultCpuChunkPoints;
  s.slice = options.slice;
  s.records = options.records;
  s.jobPlanes = options.jobPlanes;
  return s;
}

// The GPU side of each model kind: its mirror, evaluator and list sample type.
template <class Model>
struct Gpu;
template <>
struct Gpu<Curve> {
  using Mirror = gpu::GpuCurve;
  using Evaluator = gpu::CurveEvaluator;
  using Point = CurvePoint;
  using First = CurveFirst;
  using Query = CurveQuery;
  static CurveFirst first(const CurvePoint& p) { return {p.point, p.d1}; }
  static gpu::CurveSample local(const CurveQuery& q) { return {q.span, q.t}; }
  static double global(const CurveQuery& q) { return q.u; }
  static CurvePoint cpu(const Curve& c, const CurveQuery& q) { return q.global ? c.evaluateAt(q.u) : c.evaluate(q.span, q.t); }
};
template <>
struct Gpu<Surface> {
  using Mirror = gpu::GpuSurface;
  using Evaluator = gpu::SurfaceEvaluator;
  using Point = SurfacePoint;
  using First = SurfaceFirst;
  using Query = SurfaceQuery;
  static SurfaceFirst first(const SurfacePoint& p) { return {p.point, p.du, p.dv}; }
  static gpu::SurfaceSample local(const SurfaceQuery& q) { return {q.i, q.j, q.u, q.v}; }
  static std::pair<double, double> global(const SurfaceQuery& q) { return {q.u, q.v}; }
  static SurfacePoint cpu(const Surface& s, const SurfaceQuery& q) {
    return q.global ? s.evaluateAt(q.u, q.v) : s.evaluate(q.i, q.j, q.u, q.v);
  }
};

void sampleCpuGrid(const Curve& c, const GridSpec& g, FieldMask f, const ChunkConsumer& k, const SamplerOptions& o) {
  sampleCurveGrid(c, g, f, k, o);
}
void sampleCpuGrid(const Surface& s, const GridSpec& g, FieldMask f, const ChunkConsumer& k, const SamplerOptions& o) {
  sampleSurfaceGrid(s, g, f, k, o);
}

// A net beyond 2^200 is evaluated as 2^k * net (k < 0), as on the GPU, so that both paths overflow
// only where a value itself leaves fp64. The sampler's workers then see scaled values: the slices
// and the records run after the unscaling instead, on the planes.
template <class Model>
void sampleOnCpuFor(const Model& model, const Report& r, const GridSpec& g, FieldMask f, const ChunkConsumer& consumer,
                    const GridOptions& o) {
  if (r.netScaleExponent == 0) return sampleCpuGrid(model, g, f, consumer, samplerOptions(o));
  SamplerOptions plain = samplerOptions(o);
  plain.slice = nullptr;
  plain.records = {};
  plain.jobPlanes = {};  // the workers' values are scaled: `slice` copies the unscaled ones
  ChunkUnscaler unscale(r.netScaleExponent);
  sampleCpuGrid(*scaledOrNot(model, r.netScaleExponent), g, f, unscaledDelivery(unscale, o.slice, consumer), plain);
}

}  // namespace

Session::Session() = default;
Session::Session(vk::ContextOptions options) : options_(std::move(options)) {}
Session::Session(std::shared_ptr<vk::Context> ctx) : ctx_(std::move(ctx)) {
  if (!ctx_) throw std::invalid_argument("sampling::Session: the context must not be null");
}
Session::~Session() = default;

void Session::createContext(Precision precision) {
  vk::ContextOptions options = options_;
  options.preferFp64 = options.preferFp64 || precision == Precision::Double;
  try {
    ctx_ = vk::Context::create(options);
  } catch (const vk::NoDeviceError& e) {
    noDevice_ = e.reason();
  } catch (const vk::VulkanError& e) {
    throwDeviceError(e);
  }
}

void Session::prepare(const DeviceRequest& request) {
  if (request.device == DeviceKind::Cpu || ctx_ || noDevice_ || preparing_.valid()) return;
  preparing_ = std::async(std::launch::async, [this, precision = request.precision] { createContext(precision); });
}

const std::shared_ptr<vk::Context>& Session::vulkanContext() const {
  static const std::shared_ptr<vk::Context> none;
  return preparing_.valid() ? none : ctx_;  // ctx_ may still be being written by prepare()'s thread
}

const std::shared_ptr<vk::Context>& Session::context(Precision precision) {
  if (preparing_.valid()) preparing_.get();  // its DeviceError, if creating the context failed
  if (!ctx_ && !noDevice_) createContext(precision);
  return ctx_;
}

namespace {

// The evaluator of `cache` for this precision and plane size, made on first use.
template <class Evaluator>
Evaluator& cachedEvaluator(std::map<std::pair<Precision, size_t>, std::unique_ptr<Evaluator>>& cache,
                           const std::shared_ptr<vk::Context>& ctx, Precision precision, size_t maxPlaneBytes) {
  auto& e = cache[{precision, maxPlaneBytes}];
  if (!e) {
    gpu::EvaluatorOptions options;
    options.maxPlaneBytes = maxPlaneBytes;
    e = std::make_unique<Evaluator>(ctx, precision, options);
  }
  return *e;
}

}  // namespace

gpu::CurveEvaluator& Session::curveEvaluator(Precision precision, size_t maxPlaneBytes) {
  return cachedEvaluator(curveEvaluators_, ctx_, precision, maxPlaneBytes);
}
gpu::SurfaceEvaluator& Session::surfaceEvaluator(Precision precision, size_t maxPlaneBytes) {
  return cachedEvaluator(surfaceEvaluators_, ctx_, precision, maxPlaneBytes);
}

namespace {

// Patch rows per band so that every buffer of a band's mirror fits `limit`; 0 when the model is
// not split (curves, knot-vector surfaces) or not even one row fits. The bytes grow linearly with
// the rows, so bands of one and two rows give the slope.
int patchRowsPerBand(const Curve&, Precision, uint64_t) { return 0; }
int patchRowsPerBand(const Surface& s, Precision precision, uint64_t limit) {
  if (s.usesKnotVector()) return 0;
  const PatchRange r = s.patches();
  const int rows = r.u.last - r.u.first + 1;
  const gpu::ModelBufferBytes one = gpu::modelBufferBytes(s.patchRows(r.u.first, r.u.first), precision);
  if (one.largest() > limit) return 0;
  if (rows == 1) return 1;
  const gpu::ModelBufferBytes two = gpu::modelBufferBytes(s.patchRows(r.u.first, r.u.first + 1), precision);
  uint64_t n = static_cast<uint64_t>(rows);
  for (const auto& [a, b] : {std::pair{one.net, two.net}, {one.params, two.params}, {one.verts, two.verts}}) {
    if (b > a) n = std::min(n, 1 + (limit - a) / (b - a));
  }
  return static_cast<int>(n);
}

}  // namespace

uint64_t Session::bufferLimit(const vk::Context& ctx) const {
  uint64_t limit = ctx.limits().maxStorageBufferRange;
  if (ctx.limits().maxMemoryAllocationSize) limit = std::min<uint64_t>(limit, ctx.limits().maxMemoryAllocationSize);
  return maxBufferBytes_ ? std::min(limit, maxBufferBytes_) : limit;
}

namespace {

// `r` (a CPU report) with the reason the GPU was not used, or DeviceError when the request requires it.
Report cpuFallback(Report& r, const DeviceRequest& request, const std::string& why) {
  if (request.require) throw DeviceError(why + "; the CPU fallback is disabled", true);
  r.fallbacks.push_back(why);
  return r;
}

}  // namespace

template <class Model>
Report Session::planFor(const Model& model, const DeviceRequest& request) {
  Report r;
  r.outputPrecision = request.precision;
  // The CPU's exponent (net_scale.h cpuNetScaleFor); the GPU's is set below.
  const double magnitude = largestCoordinate(model);  // one pass over the net for both exponents
  r.netScaleExponent = cpuNetScaleFor(magnitude);
  if (request.device == DeviceKind::Cpu) return r;
  auto fallBack = [&](const std::string& why) { return cpuFallback(r, request, why); };
  if (auto why = deviceUnusable(request)) return fallBack(*why);
  const std::shared_ptr<vk::Context>& ctx = context(request.precision);
  if (auto why = gpuLimitation(model, request.precision)) return fallBack(*why);
  // A net that does not fit one device buffer: a grid job samples it in bands of patch rows that
  // do; anything else goes to the CPU with the sizes, rather than failing at the bind.
  const uint64_t largest = gpu::modelBufferBytes(model, request.precision).largest();
  const uint64_t limit = bufferLimit(*ctx);
  // A grid job's buffers are also kept within the band budget (host memory: a band's surface, and
  // the device buffers themselves on llvmpipe or while staged), where the net can be split.
  const uint64_t budget = bandBudgetBytes_ ? std::min(limit, bandBudgetBytes_) : limit;
  if (request.grid && largest > budget) r.bandRows = patchRowsPerBand(model, request.precision, budget);
  if (largest > limit && r.bandRows == 0) {
    r.bandRows = request.grid ? patchRowsPerBand(model, request.precision, limit) : 0;
    if (r.bandRows == 0) {
      return fallBack("the model needs a " + std::to_string(largest) + "-byte device buffer in " +
                      (request.precision == Precision::Double ? "fp64" : "fp32") + ", over the " +
                      std::to_string(limit) + "-byte limit of Vulkan device '" + ctx->deviceName() +
                      "' (maxStorageBufferRange " + std::to_string(ctx->limits().maxStorageBufferRange) +
                      (request.grid ? "; knot-vector nets and curves are not split into bands"
                                    : "; only grid jobs are split into bands") + ")");
    }
  }
  r.gpu = true;
  r.device = ctx->deviceName();
  r.computedPrecision = request.precision;
  r.netScaleExponent = netScaleFor(magnitude, request.precision);
  return r;
}

std::optional<std::string> Session::deviceUnusable(const DeviceRequest& request) {
  const std::shared_ptr<vk::Context>& ctx = context(request.precision);
  if (!ctx) return "no Vulkan device (" + *noDevice_ + ")";
  if (request.precision == Precision::Double && !ctx->supportsFloat64())
    return "Vulkan device '" + ctx->deviceName() + "' has no shaderFloat64 (use --precision float for the GPU)";
  return std::nullopt;
}

Report Session::planDevice(const DeviceRequest& request) {
  Report r;
  r.outputPrecision = request.precision;
  if (request.device == DeviceKind::Cpu) return r;
  if (auto why = deviceUnusable(request)) return cpuFallback(r, request, *why);
  r.gpu = true;
  r.device = context(request.precision)->deviceName();
  r.computedPrecision = request.precision;
  return r;
}

Report Session::plan(const Curve& curve, const DeviceRequest& request) { return planFor(curve, request); }
Report Session::plan(const Surface& surface, const DeviceRequest& request) { return planFor(surface, request); }

namespace {

template <class Model>
void sampleOnGpu(const std::shared_ptr<vk::Context>& ctx, typename Gpu<Model>::Evaluator& evaluator, const Model& model,
                 const Report& r, const GridSpec& grid, FieldMask fields, const ChunkConsumer& consumer,
                 const GridOptions& options) {
  ChunkUnscaler unscale(r.netScaleExponent);
  const ChunkConsumer deliver = unscaledDelivery(unscale, options.slice, consumer);
  onDevice([&] {
    const auto scaled = scaledOrNot(model, r.netScaleExponent);
    typename Gpu<Model>::Mirror mirror(ctx, pick(scaled, model), r.computedPrecision);
    evaluator.evaluateGrid(mirror, grid, fields, deliver);
    return 0;
  });
}

// A grid on a net too large for one device buffer (Report::bandRows > 0): each band of patch rows
// the job touches gets its own mirror (the same bits as the whole surface's patches,
// Surface::patchRows), evaluated in turn; chunks carry the whole surface's item numbers.
void sampleOnGpuInBands(const std::shared_ptr<vk::Context>& ctx, gpu::SurfaceEvaluator& evaluator, const Surface& model,
                        const Report& r, const GridSpec& grid, FieldMask fields, const ChunkConsumer& consumer,
                        const GridOptions& options) {
  ChunkUnscaler unscale(r.netScaleExponent);
  const ChunkConsumer deliver = unscaledDelivery(unscale, options.slice, consumer);
  onDevice([&] {
    const auto scaled = scaledOrNot(model, r.netScaleExponent);
    const Surface& s = pick(scaled, model);
    const PatchRange pr = s.patches();
    const size_t itemsV = static_cast<size_t>(pr.v.last - pr.v.first + 1);
    const size_t rows = static_cast<size_t>(pr.u.last - pr.u.first + 1), perBand = static_cast<size_t>(r.bandRows);
    const size_t jobFirst = grid.firstItem, jobEnd = grid.itemCount ? grid.firstItem + grid.itemCount : rows * itemsV;
    for (size_t row = jobFirst / itemsV; row * itemsV < jobEnd; row += perBand) {
      // A band ends at the job's last row: a shard of one row builds a mirror of one row.
      const size_t lastRow = std::min({row + perBand, rows, (jobEnd + itemsV - 1) / itemsV}) - 1;
      const size_t bandFirst = row * itemsV, bandEnd = (lastRow + 1) * itemsV;
      const size_t first = std::max(jobFirst, bandFirst), end = std::min(jobEnd, bandEnd);
      gpu::GpuSurface mirror(ctx, s.patchRows(pr.u.first + int(row), pr.u.first + int(lastRow)), r.computedPrecision);
      GridSpec g = grid;
      g.firstItem = first - bandFirst;
      g.itemCount = end - first;
      evaluator.evaluateGrid(mirror, g, fields, [&](const GridChunk& c) {
        GridChunk whole = c;
        whole.firstItem += bandFirst;
        deliver(whole);
      });
    }
    return 0;
  });
}

// Local and global queries go to evaluateList / evaluateListAt; the results are put back in order.
// A list on a model already on the device: local and global queries go to evaluateList /
// evaluateListAt, and the results are put back in order, unscaled.
template <class Model>
std::vector<typename Gpu<Model>::Point> evaluateOnMirror(typename Gpu<Model>::Evaluator& evaluator,
                                                         typename Gpu<Model>::Mirror& mirror, const Report& r,
                                                         std::span<const typename Gpu<Model>::Query> queries,
                                                         FieldMask fields) {
  using G = Gpu<Model>;
  std::vector<decltype(G::local(queries[0]))> local;
  std::vector<decltype(G::global(queries[0]))> global;
  for (const auto& q : queries) q.global ? global.push_back(G::global(q)) : local.push_back(G::local(q));
  std::vector<typename G::Point> out(queries.size()), atLocal, atGlobal;
  onDevice([&] {
    const FieldMask asked = fields ? fields : (std::is_same_v<Model, Curve> ? kCurveFields : kSurfaceFields);
    if (!local.empty()) atLocal = evaluator.evaluateList(mirror, local, asked);
    if (!global.empty()) atGlobal = evaluator.evaluateListAt(mirror, global, asked);
    return 0;
  });
  for (size_t i = 0, l = 0, g = 0; i < queries.size(); ++i) {
    out[i] = queries[i].global ? atGlobal[g++] : atLocal[l++];
  }
  unscale(out, r.netScaleExponent);
  return out;
}

template <class Model>
std::vector<typename Gpu<Model>::Point> evaluateOnGpu(const std::shared_ptr<vk::Context>& ctx, const Model& model,
                                                      const Report& r,
                                                      std::span<const typename Gpu<Model>::Query> queries,
                                                      FieldMask fields = 0) {
  return onDevice([&] {
    const auto scaled = scaledOrNot(model, r.netScaleExponent);
    typename Gpu<Model>::Evaluator evaluator(ctx, r.computedPrecision);
    typename Gpu<Model>::Mirror mirror(ctx, pick(scaled, model), r.computedPrecision);
    return evaluateOnMirror<Model>(evaluator, mirror, r, queries, fields);
  });
}

template <class Model>
std::vector<typename Gpu<Model>::Point> evaluateOnCpuFor(const Model& model, const Report& r,
                                                         std::span<const typename Gpu<Model>::Query> queries) {
  const auto scaled = scaledOrNot(model, r.netScaleExponent);
  std::vector<typename Gpu<Model>::Point> out(queries.size());
  for (size_t i = 0; i < queries.size(); ++i) {
    try {
      out[i] = Gpu<Model>::cpu(pick(scaled, model), queries[i]);
    } catch (const std::out_of_range& e) {
      throw QueryRangeError(i, e.what());
    }
  }
  unscale(out, r.netScaleExponent);
  return out;
}

// The lean list (core/list_eval.h) on the CPU.
template <class Model>
std::vector<typename Gpu<Model>::First> evaluateFirstOnCpu(const Model& model, const Report& r,
                                                           std::span<const typename Gpu<Model>::Query> queries,
                                                           ListFields fields) {
  const auto scaled = scaledOrNot(model, r.netScaleExponent);
  std::vector<typename Gpu<Model>::First> out(queries.size());
  evaluateList(pick(scaled, model), queries, fields, out);
  unscale(out, r.netScaleExponent);
  return out;
}

// The list kernels with only the lean list's fields written.
template <class Model>
std::vector<typename Gpu<Model>::First> evaluateFirstOnGpu(const std::shared_ptr<vk::Context>& ctx, const Model& model,
                                                           const Report& r,
                                                           std::span<const typename Gpu<Model>::Query> queries,
                                                           ListFields fields) {
  using G = Gpu<Model>;
  const std::vector<typename G::Point> all = evaluateOnGpu(ctx, model, r, queries, fieldMaskOf(fields, std::is_same_v<Model, Surface>));
  std::vector<typename G::First> out(all.size());
  for (size_t i = 0; i < all.size(); ++i) out[i] = G::first(all[i]);
  return out;
}

}  // namespace

std::vector<CurveFirst> evaluateOnCpu(const Curve& curve, const Report& report, std::span<const CurveQuery> queries,
                                      ListFields fields) {
  return evaluateFirstOnCpu(curve, report, queries, fields);
}
std::vector<SurfaceFirst> evaluateOnCpu(const Surface& surface, const Report& report,
                                        std::span<const SurfaceQuery> queries, ListFields fields) {
  return evaluateFirstOnCpu(surface, report, queries, fields);
}

void sampleOnCpu(const Curve& curve, const Report& report, const GridSpec& grid, FieldMask fields,
                 const ChunkConsumer& consumer, const GridOptions& options) {
  sampleOnCpuFor(curve, report, grid, fields, consumer, options);
}
void sampleOnCpu(const Surface& surface, const Report& report, const GridSpec& grid, FieldMask fields,
                 const ChunkConsumer& consumer, const GridOptions& options) {
  sampleOnCpuFor(surface, report, grid, fields, consumer, options);
}
std::vector<CurvePoint> evaluateOnCpu(const Curve& curve, const Report& report, std::span<const CurveQuery> queries) {
  return evaluateOnCpuFor(curve, report, queries);
}
std::vector<SurfacePoint> evaluateOnCpu(const Surface& surface, const Report& report,
                                        std::span<const SurfaceQuery> queries) {
  return evaluateOnCpuFor(surface, report, queries);
}

template <class Model>
Report Session::sampleGridFor(const Model& model, const DeviceRequest& request, const GridSpec& grid,
                              FieldMask fields, const ChunkConsumer& consumer, const GridOptions& options) {
  DeviceRequest gridRequest = request;
  gridRequest.grid = true;
  const Report r = planFor(model, gridRequest);
  if (r.gpu) {
    const size_t planeBytes = evaluatorOptions(options, r.computedPrecision).maxPlaneBytes;
    auto& evaluator = onDevice([&]() -> typename Gpu<Model>::Evaluator& {
      if constexpr (std::is_same_v<Model, Curve>) {
        return curveEvaluator(r.computedPrecision, planeBytes);
      } else {
        return surfaceEvaluator(r.computedPrecision, planeBytes);
      }
    });
    if constexpr (std::is_same_v<Model, Surface>) {
      if (r.bandRows > 0) {
        sampleOnGpuInBands(ctx_, evaluator, model, r, grid, fields, consumer, options);
        return r;
      }
    }
    sampleOnGpu(ctx_, evaluator, model, r, grid, fields, consumer, options);
  } else {
    sampleOnCpu(model, r, grid, fields, consumer, options);
  }
  return r;
}

template <class Model, class Query>
auto Session::evaluateFor(const Model& model, const DeviceRequest& request, std::span<const Query> queries) {
  ListResult<typename Gpu<Model>::Point> result{{}, planFor(model, request)};
  if (queries.empty()) return result;
  result.points = result.report.gpu ? evaluateOnGpu(ctx_, model, result.report, queries) : evaluateOnCpu(model, result.report, queries);
  return result;
}

Report Session::sampleGrid(const Curve& curve, const DeviceRequest& request, const GridSpec& grid, FieldMask fields,
                           const ChunkConsumer& consumer, const GridOptions& options) {
  return sampleGridFor(curve, request, grid, fields, consumer, options);
}
Report Session::sampleGrid(const Surface& surface, const DeviceRequest& request, const GridSpec& grid, FieldMask fields,
                           const ChunkConsumer& consumer, const GridOptions& options) {
  return sampleGridFor(surface, request, grid, fields, consumer, options);
}
template <class Model, class Query>
auto Session::evaluateFirstFor(const Model& model, const DeviceRequest& request, std::span<const Query> queries,
                               ListFields fields) {
  ListResult<typename Gpu<Model>::First> result{{}, planFor(model, request)};
  if (queries.empty()) return result;
  result.points = result.report.gpu ? evaluateFirstOnGpu(ctx_, model, result.report, queries, fields)
                                    : evaluateFirstOnCpu(model, result.report, queries, fields);
  return result;
}

struct Session::ResidentSurface::Impl {
  const Surface& model;
  Report report;
  std::optional<gpu::SurfaceEvaluator> evaluator;  // on the GPU path
  std::optional<gpu::GpuSurface> mirror;
};

Session::ResidentSurface::ResidentSurface(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Session::ResidentSurface::~ResidentSurface() = default;
const Report& Session::ResidentSurface::report() const { return impl_->report; }

std::vector<SurfaceFirst> Session::ResidentSurface::evaluate(std::span<const SurfaceQuery> queries, ListFields fields) {
  Impl& r = *impl_;
  if (queries.empty()) return {};
  if (!r.mirror) return evaluateFirstOnCpu(r.model, r.report, queries, fields);
  const std::vector<SurfacePoint> all =
      evaluateOnMirror<Surface>(*r.evaluator, *r.mirror, r.report, queries, fieldMaskOf(fields, true));
  std::vector<SurfaceFirst> out(all.size());
  for (size_t i = 0; i < all.size(); ++i) out[i] = Gpu<Surface>::first(all[i]);
  return out;
}

std::unique_ptr<Session::ResidentSurface> Session::resident(const Surface& surface, const DeviceRequest& request) {
  auto impl = std::unique_ptr<ResidentSurface::Impl>(new ResidentSurface::Impl{surface, planFor(surface, request), {}, {}});
  if (impl->report.gpu) {
    onDevice([&] {
      const auto scaled = scaledOrNot(surface, impl->report.netScaleExponent);
      impl->evaluator.emplace(ctx_, impl->report.computedPrecision);
      impl->mirror.emplace(ctx_, pick(scaled, surface), impl->report.computedPrecision);
      return 0;
    });
  }
  return std::unique_ptr<ResidentSurface>(new ResidentSurface(std::move(impl)));
}

ListResult<CurveFirst> Session::evaluate(const Curve& curve, const DeviceRequest& request,
                                         std::span<const CurveQuery> queries, ListFields fields) {
  return evaluateFirstFor(curve, request, queries, fields);
}
ListResult<SurfaceFirst> Session::evaluate(const Surface& surface, const DeviceRequest& request,
                                           std::span<const SurfaceQuery> queries, ListFields fields) {
  return evaluateFirstFor(surface, request, queries, fields);
}
ListResult<CurvePoint> Session::evaluate(const Curve& curve, const DeviceRequest& request,
                                         std::span<const CurveQuery> queries) {
  return evaluateFor(curve, request, queries);
}
ListResult<SurfacePoint> Session::evaluate(const Surface& surface, const DeviceRequest& request,
                                           std::span<const SurfaceQuery> queries) {
  return evaluateFor(surface, request, queries);
}

}  // namespace shapespline::sampling
