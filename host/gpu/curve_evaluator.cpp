#include <shapespline/gpu/curve_evaluator.h>

#include <shapespline/gpu/kernel_runs.h>
#include <shapespline/gpu/kernels.h>
#include <shapespline/gpu/list_packing.h>
#include <shapespline/gpu/plane_pool.h>

namespace shapespline::gpu {
namespace {

std::vector<CurvePoint> runCurveList(KernelSet& k, GpuCurve& curve, const std::vector<layout::ListSampleD>& s,
                                     FieldMask fields, size_t maxPlaneBytes) {
  const auto planes = curve.knotVector() ? runList(k, curve, Kernel::BSplineCurveEval, false, fields,
                                                   knotPush(curve, 1, 1), s, maxPlaneBytes)
                                         : runList(k, curve, Kernel::CurveEval, false, fields,
                                                   curvePush(curve), s, maxPlaneBytes);
  std::vector<CurvePoint> out(s.size());
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].point = planePoint(planes[int(Field::Point)], i);
    out[i].d1 = planePoint(planes[int(Field::D1)], i);
    out[i].d2 = planePoint(planes[int(Field::D2)], i);
  }
  return out;
}

}  // namespace

CurveEvaluator::CurveEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision, EvaluatorOptions options)
    : kernels_(std::make_unique<KernelSet>(std::move(ctx), precision, options.workgroupSize, options.packedStores)),
      planes_(std::make_unique<PlanePool>()),
      options_(options) {}
CurveEvaluator::~CurveEvaluator() = default;
Precision CurveEvaluator::precision() const { return kernels_->precision(); }

void CurveEvaluator::evaluateGrid(GpuCurve& curve, const GridSpec& grid, FieldMask fields,
                                  const ChunkConsumer& consumer) {
  checkPrecision(*kernels_, curve);
  if (curve.knotVector()) {
    std::optional<KnotGridTable> table;
    runGrid(*kernels_, *planes_, curve, knotGridJob(*kernels_, curve, grid, table), grid, fields, consumer,
            options_.maxPlaneBytes);
    return;
  }
  // curve_grid.comp when the samples come in whole groups of 4 (the packed stores of 4 points).
  const bool fast = grid.samplesU % 4 == 0;
  GridJob<layout::EvalPush> job{fast ? Kernel::CurveGrid : Kernel::CurveEval, false, false, kCurveFields,
                                curvePush(curve), curve.spanCount()};
  runGrid(*kernels_, *planes_, curve, job, grid, fields, consumer, options_.maxPlaneBytes);
}

std::vector<CurvePoint> CurveEvaluator::evaluateList(GpuCurve& curve, std::span<const CurveSample> samples,
                                                     FieldMask fields) {
  checkPrecision(*kernels_, curve);
  return runCurveList(*kernels_, curve, curveListSamples(curve, samples), listFields(fields, kCurveFields),
                      options_.maxPlaneBytes);
}

std::vector<CurvePoint> CurveEvaluator::evaluateListAt(GpuCurve& curve, std::span<const double> u, FieldMask fields) {
  checkPrecision(*kernels_, curve);
  return runCurveList(*kernels_, curve, curveListSamplesAt(curve, u), listFields(fields, kCurveFields),
                      options_.maxPlaneBytes);
}

}  // namespace shapespline::gpu
