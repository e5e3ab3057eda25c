// α-EB (docs/math.md §4, §5), Xu-Wang degree 5: a 64 x 64 open surface net (63 x 63 = 3969 patches,
// S x S samples per patch, point + unit normal by the §5.3 convention) and a closed 10,000-point
// curve (64 samples per span, point + first derivative), on our CPU fp64 sampler (1 and 2 threads)
// and Vulkan fp32/fp64. No OpenSubdiv counterpart exists. Excluded from timing: model construction,
// net upload, pipeline creation (the cross-check before it compiles every pipeline used here).
#include "workloads.h"

#include <shapespline/core/grid_sampler.h>
#include <shapespline/gpu/evaluator.h>
#include <shapespline/gpu/gpu_model.h>

#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>

namespace shapespline::bench {
namespace {

// Cross-check grid: a multiple of 4, so the GPU runs the same grid kernels (surface_grid.comp,
// curve_grid.comp) as in the timed S = 32 and 64 runs.
constexpr int kCheckSamples = 12;
constexpr size_t kCpuChunkPoints = size_t{1} << 15;  // cache-sized chunks, as in surface_bench.cpp
constexpr int kSampleCounts[] = {32, 64};
const FamilySpec kFamily{Construction::AlphaEB, 5, 0, 0.5, {}};

// Unit normals: fp32 loses relative precision in ∂u x ∂v where the surface bends sharply (we see
// up to about 6e-5); 1e-3 leaves room and is far below a wrong rule of §5.3 (O(1) differences).
constexpr double kFloatNormal = 1e-3;
constexpr double kDoubleNormal = 1e-9;

const Surface& surface() {
  static const Surface s = Surface::create(gridSurfaceModel(kFamily, kNetSize, 23));
  return s;
}
const Curve& curve() {
  static const Curve c = Curve::create(closedCurveModel(kFamily, kCurvePoints, 29));
  return c;
}

enum class Impl { Cpu1, Cpu2, VkFp32, VkFp64 };
constexpr Impl kImpls[] = {Impl::Cpu1, Impl::Cpu2, Impl::VkFp32, Impl::VkFp64};

const char* implName(Impl impl) {
  switch (impl) {
    case Impl::Cpu1: return "cpu_fp64_1thread";
    case Impl::Cpu2: return "cpu_fp64_2threads";
    case Impl::VkFp32: return "vulkan_fp32";
    case Impl::VkFp64: return "vulkan_fp64";
  }
  return "?";
}

struct GpuSet {
  std::unique_ptr<gpu::SurfaceEvaluator> surfaceEval;
  std::unique_ptr<gpu::CurveEvaluator> curveEval;
  std::unique_ptr<gpu::GpuSurface> surface;
  std::unique_ptr<gpu::GpuCurve> curve;
  std::string skip;
};

GpuSet& gpuSet(Precision p) {
  static std::map<Precision, GpuSet> sets;
  auto [it, fresh] = sets.try_emplace(p);
  if (fresh) {
    const auto ctx = gpuContext();
    GpuSet& g = it->second;
    if (!ctx)
      g.skip = gpuUnavailableReason();
    else if (p == Precision::Double && !ctx->supportsFloat64())
      g.skip = ctx->deviceName() + " has no shaderFloat64";
    else {
      g.surfaceEval = std::make_unique<gpu::SurfaceEvaluator>(ctx, p);
      g.curveEval = std::make_unique<gpu::CurveEvaluator>(ctx, p);
      g.surface = std::make_unique<gpu::GpuSurface>(ctx, surface(), p);
      g.curve = std::make_unique<gpu::GpuCurve>(ctx, curve(), p);
    }
  }
  return it->second;
}

bool runSurface(Impl impl, int S, const ChunkConsumer& consumer, std::string& skip) {
  const GridSpec grid{S, S, 0, 0};
  if (impl == Impl::Cpu1 || impl == Impl::Cpu2) {
    sampleSurfaceGrid(surface(), grid, kPointNormal, consumer, {impl == Impl::Cpu1 ? 1 : 2, kCpuChunkPoints});
    return true;
  }
  GpuSet& g = gpuSet(impl == Impl::VkFp32 ? Precision::Float : Precision::Double);
  if (!g.skip.empty()) return skip = g.skip, false;
  g.surfaceEval->evaluateGrid(*g.surface, grid, kPointNormal, consumer);
  return true;
}

bool runCurve(Impl impl, int S, const ChunkConsumer& consumer, std::string& skip) {
  const GridSpec grid{S, 1, 0, 0};
  if (impl == Impl::Cpu1 || impl == Impl::Cpu2) {
    sampleCurveGrid(curve(), grid, kPointD1, consumer, {impl == Impl::Cpu1 ? 1 : 2, kCpuChunkPoints});
    return true;
  }
  GpuSet& g = gpuSet(impl == Impl::VkFp32 ? Precision::Float : Precision::Double);
  if (!g.skip.empty()) return skip = g.skip, false;
  g.curveEval->evaluateGrid(*g.curve, grid, kPointD1, consumer);
  return true;
}

// Max |diff| of the points (relative tolerance of the box) and of the second field separately.
void check(const std::string& what, const Collected& got, const Collected& ref, Field second, double pointTol,
           double secondTol) {
  reportCheck(what + ", point", maxDiff(got, ref, fieldBit(Field::Point)), pointTol);
  size_t worst = 0;
  const double d = maxDiff(got, ref, fieldBit(second), &worst);
  reportCheck(what + ", " + (second == Field::Normal ? "normal" : "d1"), d, secondTol);
  if (d > secondTol) {
    const size_t perItem = second == Field::Normal ? kCheckSamples * kCheckSamples : kCheckSamples;
    const auto& x = got.planes[size_t(second)];
    const auto& y = ref.planes[size_t(second)];
    std::fprintf(stderr, "  worst at item %zu, sample %zu (a = %zu, b = %zu): got (%.9g, %.9g, %.9g), expected (%.9g, %.9g, %.9g)\n",
                 worst / perItem, worst % perItem, (worst % perItem) / kCheckSamples, (worst % perItem) % kCheckSamples,
                 x[worst * 3], x[worst * 3 + 1], x[worst * 3 + 2], y[worst * 3], y[worst * 3 + 1], y[worst * 3 + 2]);
  }
}

template <class Run>
void registerOne(const std::string& name, const std::string& label, double points, Run run) {
  benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
    double sink = 0.0;
    const ChunkConsumer consumer = touchConsumer(sink);
    std::string skip;
    if (!run(consumer, skip)) {
      state.SkipWithError(skip.c_str());
      return;
    }
    for (auto _ : state) {
      run(consumer, skip);
      benchmark::DoNotOptimize(sink);
    }
    state.counters["Mpts/s"] = benchmark::Counter(points / 1e6, benchmark::Counter::kIsIterationInvariantRate);
    state.SetLabel(label);
  })
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
}

}  // namespace

void crossCheckAlphaEB() {
  const double surfaceScale = boxDiagonal(surface().controlPoints());
  const double curveScale = boxDiagonal(curve().model().points);
  std::string skip;
  Collected sRef, cRef;
  runSurface(Impl::Cpu1, kCheckSamples, sRef.consumer(), skip);
  runCurve(Impl::Cpu1, kCheckSamples, cRef.consumer(), skip);
  for (Impl impl : {Impl::Cpu2, Impl::VkFp32, Impl::VkFp64}) {
    const bool exact = impl == Impl::Cpu2, fp64 = impl == Impl::VkFp64;
    const double rel = exact ? 0.0 : fp64 ? kDoubleRel : kFloatRel;
    const std::string vs = std::string(implName(impl)) + " vs cpu_fp64_1thread" + (exact ? " (must be identical)" : "");
    Collected s, c;
    if (!runSurface(impl, kCheckSamples, s.consumer(), skip)) {
      reportSkip("alpha_eb5 surface " + vs, skip);
      reportSkip("alpha_eb5 curve " + vs, skip);
      continue;
    }
    check("alpha_eb5 surface " + vs, s, sRef, Field::Normal, rel * surfaceScale,
          exact ? 0.0 : fp64 ? kDoubleNormal : kFloatNormal);
    runCurve(impl, kCheckSamples, c.consumer(), skip);
    // d1 = dC/du is bounded by (sum |B'|) * extent of one span's points, far below the box.
    check("alpha_eb5 curve " + vs, c, cRef, Field::D1, rel * curveScale, rel * curveScale);
  }
}

void registerAlphaEBBenchmarks() {
  const double patches = double(surfaceGridItems(surface()).size());
  for (int S : kSampleCounts)
    for (Impl impl : kImpls)
      registerOne("alpha_eb5_surface_S" + std::to_string(S) + "/" + implName(impl),
                  "point+normal, " + std::to_string(int(patches)) + " patches", patches * S * S,
                  [impl, S](const ChunkConsumer& c, std::string& skip) { return runSurface(impl, S, c, skip); });
  const double spans = double(curveGridItems(curve()).size());
  for (Impl impl : kImpls)
    registerOne("alpha_eb5_curve_S" + std::to_string(kCurveSamplesPerSpan) + "/" + implName(impl),
                "point+d1, " + std::to_string(int(spans)) + " spans", spans * kCurveSamplesPerSpan,
                [impl](const ChunkConsumer& c, std::string& skip) {
                  return runCurve(impl, kCurveSamplesPerSpan, c, skip);
                });
}

}  // namespace shapespline::bench
