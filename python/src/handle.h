#pragma once
// The state behind one Python Curve / Surface object: the current core model (what the CPU path
// evaluates) and, per precision, a resident GPU mirror (gpu::GpuCurve / GpuSurface and its
// evaluator) built on the module's sampling::Session context the first time Session::plan chooses
// the GPU. Parameter setters validate through Curve/Surface::create and then call the mirror's
// setters, so a later job re-evaluates without re-uploading the net (UploadStats prove it).
//
// Device policy is the Session's alone: every job starts with Session::plan (GPU or CPU, fallbacks,
// the power-of-two net scale); this file only keeps the mirror that plan's answer asks for.
// Thread safety: CPU jobs read the model under a shared lock; GPU jobs (the mirror is mutable) and
// setters take the lock exclusively. Nothing here touches Python.
#include <shapespline/core/curve.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/gpu/evaluator.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/sampling/net_scale.h>
#include <shapespline/sampling/session.h>
#include <shapespline/vk/error.h>

#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <span>
#include <vector>

namespace shapespline::python {

// The module's one Session (Vulkan starts on the first GPU request; device=cpu never touches it).
sampling::Session& session();
// Session::plan, with the lazy creation of the session's context serialized across threads.
template <class Model>
sampling::Report plan(const Model& model, const sampling::DeviceRequest& request);

// Every Vulkan failure of a resident job becomes sampling::DeviceError, as in the Session.
[[noreturn]] void rethrowDeviceError();

template <class Model>
struct Kind;
template <>
struct Kind<Curve> {
  using Mirror = gpu::GpuCurve;
  using Evaluator = gpu::CurveEvaluator;
  using Point = CurvePoint;
  using Query = sampling::CurveQuery;
  using ModelData = CurveModel;
  static constexpr FieldMask kAll = kCurveFields;
  static ModelData dataOf(const Curve& c) { return c.model(); }
};
template <>
struct Kind<Surface> {
  using Mirror = gpu::GpuSurface;
  using Evaluator = gpu::SurfaceEvaluator;
  using Point = SurfacePoint;
  using Query = sampling::SurfaceQuery;
  using ModelData = SurfaceModel;
  static constexpr FieldMask kAll = kSurfaceFields;
  static ModelData dataOf(const Surface& s) { return s.toModel(); }
};

// Upload counters of a handle: those of its current mirror of one precision, and how many mirrors
// (full net uploads) the handle has built for it.
struct ResidentStats {
  bool resident = false;
  gpu::UploadStats upload;
  uint64_t mirrorsBuilt = 0;
};

template <class Model>
class Handle {
 public:
  using K = Kind<Model>;
  explicit Handle(Model model) : model_(std::make_shared<const Model>(std::move(model))) {}

  // The current model, as an immutable snapshot the caller may use without the lock: a setter
  // replaces the handle's snapshot and leaves this one as it was. Not a copy (a 2048² surface is
  // 130 MB, and every property read took one).
  std::shared_ptr<const Model> model() const {
    std::shared_lock lock(mutex_);
    return model_;
  }

  sampling::Report plan(const sampling::DeviceRequest& request) const {
    std::shared_lock lock(mutex_);
    return python::plan(*model_, request);
  }

  // A grid job: Session::plan decides; the CPU path runs the core sampler, the GPU path the
  // resident mirror. Chunks arrive on the calling thread in item order.
  // `slice` (optional): order-free per-slice work, on the CPU sampler's workers; GPU chunks are
  // handed to it whole, before the consumer.
  // `jobPlanes` (optional): fp64 arrays of the whole job the CPU sampler fills directly
  // (sampling::GridOptions::jobPlanes); `slice` then sees the chunks over them.
  sampling::Report sampleGrid(const sampling::DeviceRequest& request, const GridSpec& grid, FieldMask fields,
                              const ChunkConsumer& consumer, size_t chunkPoints, const SliceConsumer& slice = {},
                              const std::array<double*, kFieldCount>& jobPlanes = {}) {
    {
      std::shared_lock lock(mutex_);
      sampling::Report r = python::plan(*model_, request);
      if (!r.gpu) {
        sampling::GridOptions o;
        o.chunkPoints = chunkPoints;
        o.slice = slice;
        o.jobPlanes = jobPlanes;
        sampling::sampleOnCpu(*model_, r, grid, fields, consumer, o);
        return r;
      }
    }
    std::unique_lock lock(mutex_);
    sampling::Report r = python::plan(*model_, request);  // again: the model may have changed
    if (!r.gpu) {
      lock.unlock();
      return sampleGrid(request, grid, fields, consumer, chunkPoints, slice, jobPlanes);
    }
    if (r.bandRows > 0) {
      // A net too large for one device buffer: no resident mirror; the session samples it in bands.
      sampling::GridOptions o;
      o.chunkPoints = chunkPoints;
      o.slice = slice;
      return session().sampleGrid(*model_, request, grid, fields, consumer, o);
    }
    try {
      Resident& res = resident(r, chunkPoints);
      sampling::ChunkUnscaler unscale(r.netScaleExponent);
      res.evaluator->evaluateGrid(*res.mirror, grid, fields, sampling::unscaledDelivery(unscale, slice, consumer));
    } catch (const vk::VulkanError&) {
      rethrowDeviceError();
    }
    return r;
  }

  // `fields` (within K::kAll) at each query, the others 0; CPU: Curve/Surface::evaluate(At), or
  // the lean list kernel (core/list_eval.h) when the fields are the point and first derivatives at
  // most; GPU: the mirror's list kernels writing those fields alone.
  sampling::ListResult<typename K::Point> evaluate(const sampling::DeviceRequest& request,
                                                   std::span<const typename K::Query> queries,
                                                   FieldMask fields = K::kAll) {
    sampling::ListResult<typename K::Point> out;
    {
      std::shared_lock lock(mutex_);
      out.report = python::plan(*model_, request);
      checkQueries(queries);
      if (!out.report.gpu) {
        const std::optional<ListFields> leanFields = listFieldsFor(fields, std::is_same_v<Model, Surface>);
        if (!leanFields) {
          out.points = sampling::evaluateOnCpu(*model_, out.report, queries);
          return out;
        }
        const auto lean = sampling::evaluateOnCpu(*model_, out.report, queries, *leanFields);
        out.points.reserve(lean.size());
        for (const auto& f : lean) out.points.push_back(pointOf(f));
        return out;
      }
    }
    std::unique_lock lock(mutex_);
    out.report = python::plan(*model_, request);
    if (!out.report.gpu) {
      lock.unlock();
      return evaluate(request, queries, fields);
    }
    checkQueries(queries);
    if (queries.empty()) return out;
    try {
      Resident& res = resident(out.report, 0);
      out.points = gpuPoints(res, queries, fields);
    } catch (const vk::VulkanError&) {
      rethrowDeviceError();
    }
    sampling::unscale(out.points, out.report.netScaleExponent);
    return out;
  }

  // Setters: `edit(data)` changes a copy of the model data; create validates it (ModelError:
  // nothing changes); `onMirror(mirror, scale)` applies the change to each resident mirror (PARAMS
  // or the changed net entries only). A mirror whose setter fails, or whose net scale would change,
  // is dropped and rebuilt by the next GPU job (counted in mirrorsBuilt).
  template <class Edit, class Change>
  void change(Edit&& edit, Change&& onMirror) {
    std::unique_lock lock(mutex_);
    typename K::ModelData data = K::dataOf(*model_);
    edit(data);
    Model created = Model::create(std::move(data));
    for (size_t p = 0; p < resident_.size(); ++p) {
      auto& res = resident_[p];
      if (!res) continue;
      const Precision precision = p == 0 ? Precision::Float : Precision::Double;
      bool keep = sampling::netScale(created, precision) == res->scale;
      if (keep) {
        try {
          onMirror(*res->mirror, res->scale);
        } catch (...) {
          keep = false;
        }
      }
      if (!keep) res.reset();
    }
    model_ = std::make_shared<const Model>(std::move(created));
  }

  ResidentStats stats(Precision precision) const {
    std::shared_lock lock(mutex_);
    const size_t p = precision == Precision::Float ? 0 : 1;
    ResidentStats s;
    s.mirrorsBuilt = built_[p];
    if (resident_[p]) {
      s.resident = true;
      s.upload = resident_[p]->mirror->uploadStats();
    }
    return s;
  }

  // Runs `job(ctx, mirror, report)` on the resident mirror when the plan chose the GPU (exclusive
  // lock), else `cpu(model, report)` (shared lock). Used by tessellation.
  template <class GpuJob, class CpuJob>
  auto withDevice(const sampling::DeviceRequest& request, GpuJob&& job, CpuJob&& cpu) {
    {
      std::shared_lock lock(mutex_);
      const sampling::Report r = python::plan(*model_, request);
      if (!r.gpu) return cpu(*model_, r);
    }
    std::unique_lock lock(mutex_);
    const sampling::Report r = python::plan(*model_, request);
    if (!r.gpu) return cpu(*model_, r);
    try {
      Resident& res = resident(r, 0);
      return job(session().vulkanContext(), *res.mirror, r);
    } catch (const vk::VulkanError&) {
      rethrowDeviceError();
    }
  }

 private:
  struct Resident {
    int scale = 0;
    size_t chunkPoints = 0;
    std::unique_ptr<typename K::Mirror> mirror;
    std::unique_ptr<typename K::Evaluator> evaluator;
  };

  // The mirror of the report's precision and scale (built, or rebuilt when the scale changed; the
  // evaluator is rebuilt when the plane size changes). Caller holds the exclusive lock.
  Resident& resident(const sampling::Report& r, size_t chunkPoints) {
    const size_t p = r.computedPrecision == Precision::Float ? 0 : 1;
    auto& res = resident_[p];
    const auto& ctx = session().vulkanContext();
    if (res && res->scale != r.netScaleExponent) res.reset();
    if (!res) {
      Resident fresh;
      fresh.scale = r.netScaleExponent;
      if (fresh.scale != 0) {
        Model scaled = scaledModel(fresh.scale);
        fresh.mirror = std::make_unique<typename K::Mirror>(ctx, scaled, r.computedPrecision);
      } else {
        fresh.mirror = std::make_unique<typename K::Mirror>(ctx, *model_, r.computedPrecision);
      }
      ++built_[p];
      res = std::move(fresh);
    }
    if (!res->evaluator || res->chunkPoints != chunkPoints) {
      gpu::EvaluatorOptions o;
      if (chunkPoints > 0) {
        const size_t real = r.computedPrecision == Precision::Double ? 8 : 4;
        o.maxPlaneBytes = (chunkPoints * 3 + 4) * real;
      }
      res->evaluator = std::make_unique<typename K::Evaluator>(ctx, r.computedPrecision, o);
      res->chunkPoints = chunkPoints;
    }
    return *res;
  }

  Model scaledModel(int k) const {
    if constexpr (std::is_same_v<Model, Curve>) {
      return sampling::scaledCurve(*model_, k);
    } else {
      return sampling::scaledSurface(*model_, k);
    }
  }

  // Queries outside the model are refused before any device work (QueryRangeError names the index).
  void checkQueries(std::span<const typename K::Query> queries) const;
  std::vector<typename K::Point> gpuPoints(Resident& res, std::span<const typename K::Query> queries,
                                           FieldMask fields);

  mutable std::shared_mutex mutex_;
  std::shared_ptr<const Model> model_;  // never null; replaced whole by change()
  std::array<std::optional<Resident>, 2> resident_;  // [fp32, fp64]
  std::array<uint64_t, 2> built_{};
};

template <>
void Handle<Curve>::checkQueries(std::span<const sampling::CurveQuery> queries) const;
template <>
void Handle<Surface>::checkQueries(std::span<const sampling::SurfaceQuery> queries) const;
template <>
std::vector<CurvePoint> Handle<Curve>::gpuPoints(Resident& res, std::span<const sampling::CurveQuery> queries,
                                                 FieldMask fields);
template <>
std::vector<SurfacePoint> Handle<Surface>::gpuPoints(Resident& res, std::span<const sampling::SurfaceQuery> queries,
                                                     FieldMask fields);

using CurveHandle = Handle<Curve>;
using SurfaceHandle = Handle<Surface>;

}  // namespace shapespline::python
