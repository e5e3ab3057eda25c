#pragma once
// CurveEvaluator: grids and lists of points, d1, d2 of any GpuCurve of its precision (kernels
// curve_grid.comp, curve_eval.comp, bspline_curve_eval.comp; chunking as gpu/evaluator.h says).
#include <shapespline/core/curve.h>
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

struct CurveSample {
  int span = 0;      // model span index (Curve::spans())
  double t = 0.0;    // local parameter in [0,1]
};

class CurveEvaluator {
 public:
  // Throws std::runtime_error for Precision::Double on a device without shaderFloat64.
  CurveEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision, EvaluatorOptions options = {});
  ~CurveEvaluator();
  Precision precision() const;

  // fields ⊆ {Point, D1, D2}: S = grid.samplesU samples per span, t_s = s/(S-1); derivatives with
  // respect to the global u (span knots: 1/h^r).
  void evaluateGrid(GpuCurve& curve, const GridSpec& grid, FieldMask fields, const ChunkConsumer& consumer);
  // Point, d1, d2 at arbitrary (span, t). Knot-vector B-splines: span = knot interval, t local in
  // it, derivatives w.r.t. the knot parameter; as Curve::evaluate (an interior knot at t = 1 is
  // evaluated on the next non-empty interval).
  // `fields` ⊆ {Point, D1, D2}: only those are computed and written (the kernel's OUTPUT_MASK; what
  // feeds no asked field is dead code after specialization); the others come back 0.
  std::vector<CurvePoint> evaluateList(GpuCurve& curve, std::span<const CurveSample> samples,
                                       FieldMask fields = kCurveFields);
  // Point, d1, d2 at global parameters u (GpuCurve::parameterRange(); as Curve::evaluateAt).
  std::vector<CurvePoint> evaluateListAt(GpuCurve& curve, std::span<const double> u, FieldMask fields = kCurveFields);

 private:
  std::unique_ptr<KernelSet> kernels_;
  std::unique_ptr<PlanePool> planes_;  // readback planes reused by successive grid jobs
  EvaluatorOptions options_;
};

}  // namespace shapespline::gpu
