#pragma once
// The sampling layer's entry point: a Session evaluates grids and lists of samples of a core Curve
// or Surface on the device a DeviceRequest asks for, and returns a Report of the path it took.
//  * Path: DeviceKind::Cpu is the CPU fp64 path (core/grid_sampler.h, Curve/Surface::evaluate);
//    Auto and Vulkan use the GPU evaluators (gpu/) unless there is no Vulkan device, fp64 is asked
//    of a device without shaderFloat64, or gpuLimitation (gpu_limits.h) names a reason; then the
//    CPU path with the reason in Report::fallbacks, or DeviceError when the request requires the
//    device. Knot-vector B-splines run on the GPU like every other construction.
//  * Scaling: a net outside the precision's band (net_scale.h) is evaluated as 2^k * net and the
//    results scaled back: on the GPU both ways, on the CPU nets beyond 2^200 (fp64 holds tiny ones
//    as they are), so both paths overflow only where a value itself leaves the output's range.
//  * Memory: grids stream chunk by chunk in bounded memory on either path (GridOptions).
//  * Errors: every Vulkan failure becomes DeviceError with a hint what to change.
// The Vulkan context is created on first GPU use and lives as long as the session.
#include <shapespline/core/curve.h>
#include <shapespline/core/list_eval.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/core/surface.h>
#include <shapespline/sampling/report.h>
#include <shapespline/vk/context.h>

#include <array>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapespline::gpu {
class CurveEvaluator;
class SurfaceEvaluator;
}  // namespace shapespline::gpu

namespace shapespline::sampling {

// The CPU sampler's chunk when the caller names none: large enough to amortise the per-chunk work
// of the consumers, small enough that a worker's slice of a chunk stays in its core's L2 while the
// slice stage reads it (e2e .f32 at 2^18: 0.90 s, at 2^15: 0.66 s and 23 MB instead of 87 MB
// resident, 15.2 M points with second derivatives on a 2-core machine).
inline constexpr size_t kDefaultCpuChunkPoints = size_t{1} << 15;
// Session::setBandBudgetBytes's default (docs/performance.md, "One big net").
inline constexpr uint64_t kDefaultBandBudgetBytes = uint64_t{8} << 20;

struct GridOptions {
  int threads = 0;         // CPU sampler threads (0 = one per available core: SamplerOptions::threads)
  size_t chunkPoints = 0;  // points per chunk (0: kDefaultCpuChunkPoints on the CPU, 4 MiB planes on the GPU)
  // Optional per-slice work (core/grid_sampler.h SliceConsumer): on the CPU run by the workers as
  // they finish their rows; on the GPU on the calling thread, the whole chunk as one slice, just
  // before the consumer.
  SliceConsumer slice = {};
  // Optional, CPU only (core/grid_sampler.h SamplerOptions::records): a file whose records the
  // CPU sampler's workers encode as they compute them; needs `slice`, which GPU chunks go through.
  RecordSink records = {};
  // Optional, CPU only (SamplerOptions::jobPlanes): fp64 arrays of the whole job, one per sampled
  // field, that the CPU sampler's workers fill directly; GPU chunks still go through `slice`.
  std::array<double*, kFieldCount> jobPlanes{};
};

// One sample of a list, and the error naming a sample outside the model: core/list_eval.h.
using shapespline::CurveQuery;
using shapespline::QueryRangeError;
using shapespline::SurfaceQuery;

template <class Point>
struct ListResult {
  std::vector<Point> points;  // one per query, in order, as computed (Report::computedPrecision)
  Report report;
};

// The CPU path of a planned job (the report's netScaleExponent honoured; QueryRangeError for a
// query outside the model): what Session runs when its plan says CPU, and what a front end that
// plans with the session but keeps its own models (the Python module) runs on the CPU.
void sampleOnCpu(const Curve& curve, const Report& report, const GridSpec& grid, FieldMask fields,
                 const ChunkConsumer& consumer, const GridOptions& options = {});
void sampleOnCpu(const Surface& surface, const Report& report, const GridSpec& grid, FieldMask fields,
                 const ChunkConsumer& consumer, const GridOptions& options = {});
std::vector<CurvePoint> evaluateOnCpu(const Curve& curve, const Report& report, std::span<const CurveQuery> queries);
std::vector<SurfacePoint> evaluateOnCpu(const Surface& surface, const Report& report,
                                        std::span<const SurfaceQuery> queries);
// The same, computing only `fields` (core/list_eval.h, the lean list kernel).
std::vector<CurveFirst> evaluateOnCpu(const Curve& curve, const Report& report, std::span<const CurveQuery> queries,
                                      ListFields fields);
std::vector<SurfaceFirst> evaluateOnCpu(const Surface& surface, const Report& report,
                                        std::span<const SurfaceQuery> queries, ListFields fields);

class Session {
 public:
  Session();                                           // default context options
  explicit Session(vk::ContextOptions options);        // used when the context is created
  explicit Session(std::shared_ptr<vk::Context> ctx);  // an existing context (non-null)
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // The path a job on this model would take, without running it (for notices and file metadata
  // written before the first chunk). Throws DeviceError as the jobs do.
  Report plan(const Curve& curve, const DeviceRequest& request);
  Report plan(const Surface& surface, const DeviceRequest& request);
  // The device part of plan() alone, for a job that samples nothing (a shard with no items, whose
  // net is never built): the CPU, or the Vulkan device the request can use at all; the limits a
  // net would add (buffer sizes, ranges) are not looked at.
  Report planDevice(const DeviceRequest& request);

  // Streams the grid (itemCount 0: every item from firstItem on) to `consumer` in item order.
  // Chunks hold the computed precision (GridChunk::precision); the sink rounds to the output
  // precision. Fields as sampleCurveGrid / sampleSurfaceGrid.
  Report sampleGrid(const Curve& curve, const DeviceRequest& request, const GridSpec& grid, FieldMask fields,
                    const ChunkConsumer& consumer, const GridOptions& options = {});
  Report sampleGrid(const Surface& surface, const DeviceRequest& request, const GridSpec& grid, FieldMask fields,
                    const ChunkConsumer& consumer, const GridOptions& options = {});

  // Every field at each query (as Curve::evaluate / evaluateAt, Surface::evaluate / evaluateAt;
  // on the GPU the surface normalRule is not reported). Throws QueryRangeError (CPU path).
  ListResult<CurvePoint> evaluate(const Curve& curve, const DeviceRequest& request, std::span<const CurveQuery> queries);
  ListResult<SurfacePoint> evaluate(const Surface& surface, const DeviceRequest& request,
                                    std::span<const SurfaceQuery> queries);
  // Only the point, or the point and first derivatives, at each query: on the CPU the lean list
  // kernel (core/list_eval.h; the same bits as the fields of evaluate() above), on the GPU the list
  // kernels with those fields alone written. Throws QueryRangeError (CPU path).
  ListResult<CurveFirst> evaluate(const Curve& curve, const DeviceRequest& request, std::span<const CurveQuery> queries,
                                  ListFields fields);
  ListResult<SurfaceFirst> evaluate(const Surface& surface, const DeviceRequest& request,
                                    std::span<const SurfaceQuery> queries, ListFields fields);

  // A surface kept on the session's device for many lists (the part mesher asks a few per face and
  // refinement round): planned once, its net uploaded once, each list then one evaluation. Where
  // the plan chose the CPU, the lists run on core's lean list kernel, as evaluate() would; the
  // results are evaluate()'s with `fields`. The surface must outlive it; not thread-safe.
  class ResidentSurface {
   public:
    ~ResidentSurface();
    const Report& report() const;
    std::vector<SurfaceFirst> evaluate(std::span<const SurfaceQuery> queries, ListFields fields);

   private:
    friend class Session;
    struct Impl;
    explicit ResidentSurface(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
  };
  // Throws DeviceError as the jobs do.
  std::unique_ptr<ResidentSurface> resident(const Surface& surface, const DeviceRequest& request);

  // The Vulkan context once a plan or job on the GPU path created it (nullptr before that and when
  // there is no device). A front end that keeps device-side models between jobs (the Python
  // module's gpu::GpuCurve/GpuSurface, so parameter changes need no net upload) builds them on it,
  // after plan() chose the GPU. A context that prepare() is still creating is not shown (nullptr)
  // until a plan has collected it.
  const std::shared_ptr<vk::Context>& vulkanContext() const;

  // Starts creating the Vulkan context a job of `request` will plan on, on a thread of its own, so
  // that the caller can read its model meanwhile (instance, device and driver take 0.1-0.2 s on
  // llvmpipe); the next plan waits for it and reports as it would have. Nothing for a CPU request
  // or when the context exists.
  void prepare(const DeviceRequest& request);

  // The most bytes one device buffer of a model may take (0, the default: the device's
  // maxStorageBufferRange and maxMemoryAllocationSize). A grid job on a larger net is sampled in
  // bands of patch rows (Report::bandRows); a list job goes to the CPU. Tests force tiny bands with
  // it; a caller may keep device memory for itself.
  void setMaxBufferBytes(uint64_t bytes) { maxBufferBytes_ = bytes; }
  // The most bytes one buffer of a grid job's model may take before its net is split into bands,
  // although the device would hold it whole (kDefaultBandBudgetBytes; 0: the device's limits only).
  // A band's surface is host memory, and so are its device buffers on llvmpipe and while staged
  // on other devices: without it, a 4096² α-EB job on llvmpipe held 1 GB for a 537 MB model.
  void setBandBudgetBytes(uint64_t bytes) { bandBudgetBytes_ = bytes; }

 private:
  // One body for curves and surfaces each (session.cpp).
  template <class Model>
  Report planFor(const Model& model, const DeviceRequest& request);
  // Why the request cannot use a Vulkan device at all (none; fp64 asked of a device without it).
  std::optional<std::string> deviceUnusable(const DeviceRequest& request);
  // maxStorageBufferRange, maxMemoryAllocationSize and maxBufferBytes_, the least of them.
  uint64_t bufferLimit(const vk::Context& ctx) const;
  template <class Model>
  Report sampleGridFor(const Model& model, const DeviceRequest& request, const GridSpec& grid, FieldMask fields,
                       const ChunkConsumer& consumer, const GridOptions& options);
  template <class Model, class Query>
  auto evaluateFor(const Model& model, const DeviceRequest& request, std::span<const Query> queries);
  template <class Model, class Query>
  auto evaluateFirstFor(const Model& model, const DeviceRequest& request, std::span<const Query> queries,
                        ListFields fields);
  // The context, created on first call (or by prepare()); nullptr (and noDevice_ set) when there
  // is no device.
  const std::shared_ptr<vk::Context>& context(Precision precision);
  void createContext(Precision precision);
  // The grid evaluator of this precision and plane size, made on first use and kept: a session
  // that samples many models (`sample A.json B.json ...`) compiles each pipeline once.
  gpu::CurveEvaluator& curveEvaluator(Precision precision, size_t maxPlaneBytes);
  gpu::SurfaceEvaluator& surfaceEvaluator(Precision precision, size_t maxPlaneBytes);

  vk::ContextOptions options_;
  std::shared_ptr<vk::Context> ctx_;
  std::optional<std::string> noDevice_;  // why creating the context failed
  std::future<void> preparing_;          // prepare()'s createContext, until context() collects it
  uint64_t maxBufferBytes_ = 0;
  uint64_t bandBudgetBytes_ = kDefaultBandBudgetBytes;
  std::map<std::pair<Precision, size_t>, std::unique_ptr<gpu::CurveEvaluator>> curveEvaluators_;
  std::map<std::pair<Precision, size_t>, std::unique_ptr<gpu::SurfaceEvaluator>> surfaceEvaluators_;
};

}  // namespace shapespline::sampling
