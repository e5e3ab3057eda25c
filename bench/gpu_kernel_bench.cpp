// GPU kernel variants on the issue-3 speed workload: 64 x 64 open net, 61 x 61 = 3721 patches,
// 64 x 64 samples per patch (15.2 M points). Uniform bicubic (Xu-Wang degree 4, λ = 0) with
// point + du + dv in fp32 and fp64, α-EB degree 5 with point + normal (fp32), and the knot-vector
// B-spline kernel on a bicubic clamped net of the same size. Each run is one whole grid job
// (all chunks, streamed through the 2-slot ring, consumer touching each chunk); the first compile
// happens in the untimed warm-up. Counters: points/s ("Mpts/s" = items_per_second / 1e6).
// Run: shapespline_bench --benchmark_filter=GpuKernel
#include "workloads.h"

#include <shapespline/gpu/evaluator.h>

#include <benchmark/benchmark.h>

#include <memory>

namespace shapespline::bench {
namespace {

constexpr int kSamples = 64;

FamilySpec xuWang(int degree, double lambda) {
  FamilySpec f;
  f.construction = Construction::ExtendedBSpline;
  f.degree = degree;
  f.lambda = lambda;
  return f;
}

FamilySpec alphaEB(int degree, double lambda) {
  FamilySpec f;
  f.construction = Construction::AlphaEB;
  f.degree = degree;
  f.lambda = lambda;
  return f;
}

Surface knotVectorSurface() {
  FamilySpec f;
  f.construction = Construction::BSpline;
  f.order = 4;
  SurfaceModel m = gridSurfaceModel(f, kNetSize, 7);
  m.orderV = 4;
  for (auto* k : {&m.knotsU, &m.knotsV}) {
    k->assign(4, 0.0);
    for (int i = 1; i <= kNetSize - 4; ++i) k->push_back(i);
    k->insert(k->end(), 4, double(kNetSize - 3));
  }
  return Surface::create(std::move(m));
}

// planeKiB (bicubic: range(1), 0 = default): EvaluatorOptions::maxPlaneBytes in KiB. The output planes are allocated per
// evaluateGrid call, so large chunks pay first-touch page faults on every run (lavapipe: ~0.25 s of
// system time per 15 M points at the 64 MiB default); 2 MiB chunks stay in the reused 2-slot ring.
void runSurface(benchmark::State& state, const Surface& cpu, Precision pr, FieldMask fields, uint32_t workgroup,
                int64_t planeKiB = 0) {
  const auto ctx = gpuContext();
  if (!ctx) return state.SkipWithError(gpuUnavailableReason().c_str());
  if (pr == Precision::Double && !ctx->supportsFloat64()) return state.SkipWithError("no shaderFloat64");
  gpu::EvaluatorOptions opt;
  opt.workgroupSize = workgroup;
  if (planeKiB > 0) opt.maxPlaneBytes = size_t(planeKiB) << 10;
  gpu::GpuSurface model(ctx, cpu, pr);
  gpu::SurfaceEvaluator ev(ctx, pr, opt);
  GridSpec grid;
  grid.samplesU = grid.samplesV = kSamples;
  double sink = 0.0;
  ev.evaluateGrid(model, grid, fields, touchConsumer(sink));  // first compile, untimed
  for (auto _ : state) ev.evaluateGrid(model, grid, fields, touchConsumer(sink));
  benchmark::DoNotOptimize(sink);
  const double points = double(model.gridItemCount()) * kSamples * kSamples;
  state.SetItemsProcessed(int64_t(points * double(state.iterations())));
  state.counters["points"] = points;
}

void GpuKernel_Bicubic_PointDuDv_fp32(benchmark::State& s) {
  static const Surface cpu = Surface::create(gridSurfaceModel(xuWang(4, 0.0), kNetSize, 1));
  runSurface(s, cpu, Precision::Float, kPointDuDv, uint32_t(s.range(0)), s.range(1));
}
void GpuKernel_Bicubic_PointDuDv_fp64(benchmark::State& s) {
  static const Surface cpu = Surface::create(gridSurfaceModel(xuWang(4, 0.0), kNetSize, 1));
  runSurface(s, cpu, Precision::Double, kPointDuDv, uint32_t(s.range(0)), s.range(1));
}
void GpuKernel_AlphaEB5_PointNormal_fp32(benchmark::State& s) {
  static const Surface cpu = Surface::create(gridSurfaceModel(alphaEB(5, 0.0), kNetSize, 2));
  runSurface(s, cpu, Precision::Float, kPointNormal, uint32_t(s.range(0)));
}
void GpuKernel_KnotBicubic_PointDuDv_fp32(benchmark::State& s) {
  static const Surface cpu = knotVectorSurface();
  runSurface(s, cpu, Precision::Float, kPointDuDv, uint32_t(s.range(0)));
}

BENCHMARK(GpuKernel_Bicubic_PointDuDv_fp32)
    ->ArgsProduct({{64, 128, 256}, {0, 2048}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(GpuKernel_Bicubic_PointDuDv_fp64)->ArgsProduct({{64}, {0, 2048}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(GpuKernel_AlphaEB5_PointNormal_fp32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(GpuKernel_KnotBicubic_PointDuDv_fp32)->Arg(64)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace shapespline::bench
