#pragma once
// SurfaceEvaluator: grids and lists of points, partials and normals of any GpuSurface of its
// precision (kernels surface_grid.comp, surface_eval.comp, bspline_surface_eval.comp; chunking as
// gpu/evaluator.h says).
#include <shapespline/core/surface.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/gpu/evaluator_options.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/vk/context.h>

#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace shapespline::gpu {

class KernelSet;
class PlanePool;

struct SurfaceSample {
  int i = 0, j = 0;  // model patch indices (Surface::patches())
  double u = 0.0, v = 0.0;
};

class SurfaceEvaluator {
 public:
  SurfaceEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision, EvaluatorOptions options = {});
  ~SurfaceEvaluator();
  Precision precision() const;

  // fields ⊆ {Point, Du, Dv, Duu, Duv, Dvv, Normal}: Su x Sv samples per patch (u_a = a/(Su-1)),
  // patches row-major over Surface::patches(); normals by the docs/math.md §5.3 convention.
  void evaluateGrid(GpuSurface& surface, const GridSpec& grid, FieldMask fields, const ChunkConsumer& consumer);
  // Every field at arbitrary (patch, u, v); normalRule is not reported (always Regular).
  // Knot-vector B-splines: (i, j) = knot interval pair, as Surface::evaluate.
  // `fields` ⊆ kSurfaceFields: only those are computed and written (the kernel's OUTPUT_MASK: no
  // normal unless asked, and what feeds no asked field is dead code after specialization); the
  // others come back 0.
  std::vector<SurfacePoint> evaluateList(GpuSurface& surface, std::span<const SurfaceSample> samples,
                                         FieldMask fields = kSurfaceFields);
  // Every field at global (U, V) (as Surface::evaluateAt).
  std::vector<SurfacePoint> evaluateListAt(GpuSurface& surface, std::span<const std::pair<double, double>> uv,
                                           FieldMask fields = kSurfaceFields);

 private:
  std::unique_ptr<KernelSet> kernels_;
  std::unique_ptr<PlanePool> planes_;  // readback planes reused by successive grid jobs
  EvaluatorOptions options_;
};

}  // namespace shapespline::gpu
