#include <shapespline/gpu/surface_evaluator.h>

#include <shapespline/gpu/kernel_runs.h>
#include <shapespline/gpu/kernels.h>
#include <shapespline/gpu/list_packing.h>
#include <shapespline/gpu/plane_pool.h>

namespace shapespline::gpu {

SurfaceEvaluator::SurfaceEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision, EvaluatorOptions options)
    : kernels_(std::make_unique<KernelSet>(std::move(ctx), precision, options.workgroupSize, options.packedStores)),
      planes_(std::make_unique<PlanePool>()),
      options_(options) {}
SurfaceEvaluator::~SurfaceEvaluator() = default;
Precision SurfaceEvaluator::precision() const { return kernels_->precision(); }

void SurfaceEvaluator::evaluateGrid(GpuSurface& surface, const GridSpec& grid, FieldMask fields,
                                    const ChunkConsumer& consumer) {
  checkPrecision(*kernels_, surface);
  if (surface.knotVector()) {
    if (const auto job = knotPatchGridJob(surface, grid, fields)) {
      runGrid(*kernels_, *planes_, surface, *job, grid, fields, consumer, options_.maxPlaneBytes);
      return;
    }
    std::optional<KnotGridTable> table;
    runGrid(*kernels_, *planes_, surface, knotGridJob(*kernels_, surface, grid, table), grid, fields, consumer,
            options_.maxPlaneBytes);
    return;
  }
  // surface_grid.comp: tensor and α-EB surfaces, with or without normals, RUN_LENGTH samples (whole
  // rows) per invocation sharing the patch net, the α-EB corner data and the u contraction (needs
  // samplesV % 4 == 0; rare normals fall back to the §5.3 code shared with surface_eval.comp).
  const bool fast = grid.samplesV % 4 == 0;
  GridJob<layout::EvalPush> job{fast ? Kernel::SurfaceGrid : Kernel::SurfaceEval, true, false, kSurfaceFields,
                                surfacePush(surface), surface.patchCount()};
  runGrid(*kernels_, *planes_, surface, job, grid, fields, consumer, options_.maxPlaneBytes);
}

std::vector<SurfacePoint> SurfaceEvaluator::evaluateList(GpuSurface& surface, std::span<const SurfaceSample> samples,
                                                         FieldMask fields) {
  checkPrecision(*kernels_, surface);
  fields = listFields(fields, kSurfaceFields);
  const std::vector<layout::ListSampleD> s = surfaceListSamples(surface, samples);
  const auto planes =
      surface.knotVector()
          ? runList(*kernels_, surface, Kernel::BSplineSurfaceEval, true, fields,
                    knotPush(surface, uint32_t(surface.gridItemsV()), surface.netCols()), s, options_.maxPlaneBytes)
          : runList(*kernels_, surface, Kernel::SurfaceEval, true, fields, surfacePush(surface), s,
                    options_.maxPlaneBytes);
  std::vector<SurfacePoint> out(samples.size());
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].point = planePoint(planes[int(Field::Point)], i);
    out[i].du = planePoint(planes[int(Field::Du)], i);
    out[i].dv = planePoint(planes[int(Field::Dv)], i);
    out[i].duu = planePoint(planes[int(Field::Duu)], i);
    out[i].duv = planePoint(planes[int(Field::Duv)], i);
    out[i].dvv = planePoint(planes[int(Field::Dvv)], i);
    out[i].normal = planePoint(planes[int(Field::Normal)], i);
  }
  return out;
}

std::vector<SurfacePoint> SurfaceEvaluator::evaluateListAt(GpuSurface& surface,
                                                           std::span<const std::pair<double, double>> uv,
                                                           FieldMask fields) {
  const std::vector<SurfaceSample> local = surfaceSamplesAt(surface, uv);
  return evaluateList(surface, local, fields);
}

}  // namespace shapespline::gpu
