// Uniform cubic B-spline surface (Xu-Wang degree 4 at λ = 0), 64 x 64 net, 3721 patches, S x S
// samples per patch, point + ∂u + ∂v: OpenSubdiv 3.5 (Osd::CpuEvaluator, Osd::OmpEvaluator) against
// our CPU fp64 sampler on 1 and 2 threads and our Vulkan fp32/fp64 grid evaluators.
//
// OpenSubdiv side: the 64 x 64 vertex quad grid as a Far::TopologyDescriptor, scheme Catmark with
// VTX_BOUNDARY_NONE, so faces touching the boundary are holes and the patch table holds exactly the
// 61 x 61 interior regular B-spline patches; adaptive "refinement" to isolation level 0 only marks
// the refiner adaptive (nothing is subdivided) so the factory emits B-spline patches of the base
// faces instead of the bilinear quads of a uniform table. Face (a,b) has vertices (a,b), (a+1,b),
// (a+1,b+1), (a,b+1), so the patch parameter s runs along our u (rows) and t along our v; the
// cross-check confirms it. Both sides chunk the job the same way (2^15 points per chunk, whole
// patches) and touch each chunk with the same cheap consumer. Excluded from timing: patch
// table, patch coordinates (OpenSubdiv's input, built once as a user would), net upload, pipelines.
#include "workloads.h"

#include <shapespline/core/grid_sampler.h>
#include <shapespline/gpu/evaluator.h>
#include <shapespline/gpu/gpu_model.h>

#include <benchmark/benchmark.h>

#ifdef SHAPESPLINE_HAVE_OPENSUBDIV
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/osd/cpuEvaluator.h>
#include <opensubdiv/osd/cpuPatchTable.h>
#include <opensubdiv/osd/ompEvaluator.h>
#endif

#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <stdexcept>
#include <string>

namespace shapespline::bench {
namespace {

// Both CPU sides deliver chunks of 2^15 points (whole patches): the chunk buffers (2.4 MB for
// fp64 P/du/dv) stay in the last-level cache. With 2^20-point chunks (the sampler's default) the
// output goes to DRAM and both sides measure memory write bandwidth instead of evaluation.
constexpr size_t kChunkPoints = size_t{1} << 15;
// Cross-check grid: 12 x 12 per patch, edges included; a multiple of 4, so the GPU runs the same
// grid kernel (surface_grid.comp) as in the timed S = 32 and 64 runs.
constexpr int kCheckSamples = 12;
constexpr int kSampleCounts[] = {32, 64};

}  // namespace

SurfaceModel bsplineWorkloadModel() {
  return gridSurfaceModel({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, kNetSize, 17);
}

SurfaceModel knotWorkloadModel(bool randomKnots, bool rational) {
  SurfaceModel m = bsplineWorkloadModel();
  m.family = {Construction::BSpline, 0, 4, 0.0, {}};
  m.orderV = 4;
  // Uniform: knots 0, 1, ..., 67 (unclamped), the same surface as the uniform workload (the cubic
  // B-spline on integer knots is Xu-Wang degree 4 at λ = 0), derivatives included. Random: clamped,
  // interior intervals of lengths in [0.25, 1.75].
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> length(0.25, 1.75);
  for (std::vector<double>* knots : {&m.knotsU, &m.knotsV}) {
    for (int k = 0; k < kNetSize + 4; ++k) knots->push_back(k);
    if (!randomKnots) continue;
    double t = 0.0;
    for (int k = 0; k < kNetSize + 4; ++k) {
      if (k > 3 && k <= kNetSize) t += length(rng);
      (*knots)[size_t(k)] = t;
    }
  }
  if (rational) {
    std::uniform_real_distribution<double> weight(0.5, 2.0);
    for (size_t k = 0; k < m.points.size(); ++k) m.weights.push_back(weight(rng));
  }
  return m;
}

namespace {

struct BSplineWorkload {
  Surface surface;
  double scale = 0.0;
  size_t patches = 0;
};

// The nets of the surface benchmarks: the uniform bicubic workload and the same net as a
// knot-vector B-spline (the general path) with uniform and with random knots, and the latter with
// random weights in [0.5, 2] (a NURBS surface).
enum class Net { Uniform, KnotUniform, KnotRandom, NurbsRandom };
constexpr Net kNets[] = {Net::Uniform, Net::KnotUniform, Net::KnotRandom, Net::NurbsRandom};
const char* netName(Net n) {
  switch (n) {
    case Net::Uniform: return "bspline3";
    case Net::KnotUniform: return "knot3_uniform";
    case Net::KnotRandom: return "knot3_random";
    case Net::NurbsRandom: return "nurbs3_random";
  }
  return "?";
}

const BSplineWorkload& workload(Net net = Net::Uniform) {
  static const std::array<BSplineWorkload, 4> w = [] {
    auto make = [](SurfaceModel m) {
      BSplineWorkload b{Surface::create(std::move(m)), 0.0, 0};
      b.scale = boxDiagonal(b.surface.controlPoints());
      b.patches = surfaceGridItems(b.surface).size();
      if (b.patches != 3721) throw std::logic_error("B-spline workload: expected 3721 patches");
      return b;
    };
    return std::array<BSplineWorkload, 4>{make(bsplineWorkloadModel()), make(knotWorkloadModel(false, false)),
                                          make(knotWorkloadModel(true, false)), make(knotWorkloadModel(true, true))};
  }();
  return w[size_t(net)];
}

// ---- OpenSubdiv -------------------------------------------------------------------------------

#ifdef SHAPESPLINE_HAVE_OPENSUBDIV
namespace Far = OpenSubdiv::Far;
namespace Osd = OpenSubdiv::Osd;
namespace Sdc = OpenSubdiv::Sdc;

struct OsdWorkload {
  std::unique_ptr<Far::PatchTable> table;
  std::unique_ptr<Osd::CpuPatchTable> cpuTable;
  std::vector<float> net;                               // 64 x 64 vertices, xyz
  std::vector<Far::PatchTable::PatchHandle> handles;    // per our patch item, row-major
  std::map<int, std::vector<Osd::PatchCoord>> coords;   // per S: S x S per patch, our point order
};

OsdWorkload& osdWorkload() {
  static OsdWorkload w = [] {
    const Surface& s = workload().surface;
    const int n = kNetSize, faces = n - 1;
    std::vector<int> verts, counts(static_cast<size_t>(faces) * faces, 4);
    for (int a = 0; a < faces; ++a)
      for (int b = 0; b < faces; ++b)
        for (int v : {a * n + b, (a + 1) * n + b, (a + 1) * n + b + 1, a * n + b + 1}) verts.push_back(v);
    Far::TopologyDescriptor desc;
    desc.numVertices = n * n;
    desc.numFaces = faces * faces;
    desc.numVertsPerFace = counts.data();
    desc.vertIndicesPerFace = verts.data();
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_NONE);
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> refiner(
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
    if (!refiner) throw std::runtime_error("OpenSubdiv: TopologyRefinerFactory failed");
    refiner->RefineAdaptive(Far::TopologyRefiner::AdaptiveOptions(0));
    Far::PatchTableFactory::Options options;
    options.SetPatchPrecision<float>();
    OsdWorkload o;
    o.table.reset(Far::PatchTableFactory::Create(*refiner, options));
    if (o.table->GetNumPatchArrays() != 1 || o.table->GetNumPatches(0) != 3721 ||
        o.table->GetPatchArrayDescriptor(0).GetType() != Far::PatchDescriptor::REGULAR)
      throw std::logic_error("OpenSubdiv: expected one array of 3721 regular patches, got " +
                             std::to_string(o.table->GetNumPatchesTotal()) + " patches in " +
                             std::to_string(o.table->GetNumPatchArrays()) + " arrays");
    o.cpuTable.reset(Osd::CpuPatchTable::Create(o.table.get()));
    for (const auto& p : s.controlPoints())
      for (int k = 0; k < 3; ++k) o.net.push_back(static_cast<float>(p[k]));
    // Our patch (i, j) spans net rows i..i+1 and columns j..j+1: OSD face (i, j).
    const Far::PatchMap map(*o.table);
    for (const auto& [i, j] : surfaceGridItems(s)) {
      const auto* h = map.FindPatch(i * faces + j, 0.5, 0.5);
      if (!h) throw std::logic_error("OpenSubdiv: no patch for face " + std::to_string(i * faces + j));
      o.handles.push_back(*h);
    }
    return o;
  }();
  return w;
}

const std::vector<Osd::PatchCoord>& osdCoords(int S) {
  OsdWorkload& o = osdWorkload();
  auto& c = o.coords[S];
  if (c.empty()) {
    c.reserve(o.handles.size() * S * S);
    for (const auto& h : o.handles)
      for (int a = 0; a < S; ++a)
        for (int b = 0; b < S; ++b) c.emplace_back(h, float(a) / float(S - 1), float(b) / float(S - 1));
  }
  return c;
}

// Evaluates coords[begin, begin + count) into xyz float planes (P, ∂u, ∂v).
template <class Evaluator>
void osdEvaluate(const std::vector<Osd::PatchCoord>& coords, size_t begin, size_t count, float* p, float* du,
                 float* dv) {
  const OsdWorkload& o = osdWorkload();
  const Osd::BufferDescriptor src(0, 3, 3), dst(0, 3, 3);
  Evaluator::EvalPatches(o.net.data(), src, p, dst, du, dst, dv, dst, static_cast<int>(count), coords.data() + begin,
                         o.cpuTable->GetPatchArrayBuffer(), o.cpuTable->GetPatchIndexBuffer(),
                         o.cpuTable->GetPatchParamBuffer());
}

// The whole grid in chunks of whole patches, each chunk handed to `consumer` like our samplers do.
template <class Evaluator>
void osdGrid(int S, const ChunkConsumer& consumer) {
  const auto& coords = osdCoords(S);
  const size_t perPatch = size_t(S) * S, patches = workload().patches;
  const size_t perChunk = std::max<size_t>(1, kChunkPoints / perPatch);
  std::vector<float> planes[3];
  for (auto& v : planes) v.resize(perChunk * perPatch * 3);
  for (size_t first = 0; first < patches; first += perChunk) {
    const size_t n = std::min(perChunk, patches - first);
    osdEvaluate<Evaluator>(coords, first * perPatch, n * perPatch, planes[0].data(), planes[1].data(),
                           planes[2].data());
    GridChunk chunk;
    chunk.firstItem = first;
    chunk.itemCount = n;
    chunk.pointsPerItem = perPatch;
    chunk.precision = Precision::Float;
    chunk.planes[size_t(Field::Point)] = planes[0].data();
    chunk.planes[size_t(Field::Du)] = planes[1].data();
    chunk.planes[size_t(Field::Dv)] = planes[2].data();
    consumer(chunk);
  }
}
#endif

// ---- Ours -------------------------------------------------------------------------------------

struct GpuSurfaceSet {
  std::unique_ptr<gpu::SurfaceEvaluator> evaluator;
  std::unique_ptr<gpu::GpuSurface> model;
  std::string skip;  // why this precision cannot run
};

GpuSurfaceSet& gpuSurface(Net net, Precision p) {
  static std::map<std::pair<Net, Precision>, GpuSurfaceSet> sets;
  auto [it, fresh] = sets.try_emplace({net, p});
  if (fresh) {
    const auto ctx = gpuContext();
    if (!ctx)
      it->second.skip = gpuUnavailableReason();
    else if (p == Precision::Double && !ctx->supportsFloat64())
      it->second.skip = ctx->deviceName() + " has no shaderFloat64";
    else {
      it->second.evaluator = std::make_unique<gpu::SurfaceEvaluator>(ctx, p);
      it->second.model = std::make_unique<gpu::GpuSurface>(ctx, workload(net).surface, p);
    }
  }
  return it->second;
}

enum class Impl { OsdCpu, OsdOmp, Cpu1, Cpu2, VkFp32, VkFp64 };

// Runs one whole grid with `impl`; returns false (with the reason) when it cannot run here.
bool runGrid(Impl impl, int S, const ChunkConsumer& consumer, std::string& skip, Net net = Net::Uniform) {
  const GridSpec grid{S, S, 0, 0};
  switch (impl) {
    case Impl::OsdCpu:
    case Impl::OsdOmp:
#ifdef SHAPESPLINE_HAVE_OPENSUBDIV
      if (net != Net::Uniform) {
        skip = "OpenSubdiv evaluates uniform B-spline patches only";
        return false;
      }
      if (impl == Impl::OsdCpu)
        osdGrid<Osd::CpuEvaluator>(S, consumer);
      else
        osdGrid<Osd::OmpEvaluator>(S, consumer);
      return true;
#else
      skip = "OpenSubdiv not built (libosd-dev missing)";
      return false;
#endif
    case Impl::Cpu1:
    case Impl::Cpu2:
      sampleSurfaceGrid(workload(net).surface, grid, kPointDuDv, consumer, {impl == Impl::Cpu1 ? 1 : 2, kChunkPoints});
      return true;
    case Impl::VkFp32:
    case Impl::VkFp64: {
      GpuSurfaceSet& g = gpuSurface(net, impl == Impl::VkFp32 ? Precision::Float : Precision::Double);
      if (!g.skip.empty()) {
        skip = g.skip;
        return false;
      }
      g.evaluator->evaluateGrid(*g.model, grid, kPointDuDv, consumer);
      return true;
    }
  }
  return false;
}

const char* implName(Impl impl) {
  switch (impl) {
    case Impl::OsdCpu: return "osd_cpu_evaluator";
    case Impl::OsdOmp: return "osd_omp_evaluator";
    case Impl::Cpu1: return "cpu_fp64_1thread";
    case Impl::Cpu2: return "cpu_fp64_2threads";
    case Impl::VkFp32: return "vulkan_fp32";
    case Impl::VkFp64: return "vulkan_fp64";
  }
  return "?";
}

constexpr Impl kImpls[] = {Impl::OsdCpu, Impl::OsdOmp, Impl::Cpu1, Impl::Cpu2, Impl::VkFp32, Impl::VkFp64};

}  // namespace

void crossCheckSurfaces() {
  const BSplineWorkload& w = workload();
  Collected reference;
  std::string skip;
  runGrid(Impl::Cpu1, kCheckSamples, reference.consumer(), skip);
  Collected twoThreads;
  runGrid(Impl::Cpu2, kCheckSamples, twoThreads.consumer(), skip);
  reportCheck("bspline cpu_fp64_2threads vs 1thread (must be identical)", maxDiff(twoThreads, reference, kPointDuDv),
              0.0);
  for (Impl impl : {Impl::OsdCpu, Impl::OsdOmp, Impl::VkFp32, Impl::VkFp64}) {
    Collected got;
    const std::string what = std::string("bspline ") + implName(impl) + " vs cpu_fp64, " +
                             std::to_string(w.patches * kCheckSamples * kCheckSamples) + " points, P/du/dv";
    if (!runGrid(impl, kCheckSamples, got.consumer(), skip)) {
      reportSkip(what, skip);
      continue;
    }
    const double rel = impl == Impl::VkFp64 ? kDoubleRel : kFloatRel;
    reportCheck(what, maxDiff(got, reference, kPointDuDv), rel * w.scale);
  }
  // The uniform-knot net is the same surface through the knot-vector path, on every implementation.
  for (Impl impl : {Impl::Cpu1, Impl::Cpu2, Impl::VkFp32, Impl::VkFp64}) {
    Collected got;
    const std::string what = std::string("knot3_uniform ") + implName(impl) + " vs bspline3 cpu_fp64, P/du/dv";
    if (!runGrid(impl, kCheckSamples, got.consumer(), skip, Net::KnotUniform)) {
      reportSkip(what, skip);
      continue;
    }
    const double rel = impl == Impl::VkFp32 ? kFloatRel : kDoubleRel;
    reportCheck(what, maxDiff(got, reference, kPointDuDv), rel * w.scale);
  }
}

void registerSurfaceBenchmarks() {
  for (Net net : kNets)
    for (int S : kSampleCounts)
      for (Impl impl : kImpls) {
        if (net != Net::Uniform && (impl == Impl::OsdCpu || impl == Impl::OsdOmp)) continue;
        const std::string name = std::string(netName(net)) + "_S" + std::to_string(S) + "/" + implName(impl);
        benchmark::RegisterBenchmark(name.c_str(), [impl, S, net](benchmark::State& state) {
          double sink = 0.0;
          const ChunkConsumer consumer = touchConsumer(sink);
          std::string skip;
          if (!runGrid(impl, S, consumer, skip, net)) {  // untimed warm-up; also tells whether it can run
            state.SkipWithError(skip.c_str());
            return;
          }
          for (auto _ : state) {
            runGrid(impl, S, consumer, skip, net);
            benchmark::DoNotOptimize(sink);
          }
          const double points = double(workload(net).patches) * S * S;
          state.counters["Mpts/s"] = benchmark::Counter(points / 1e6, benchmark::Counter::kIsIterationInvariantRate);
          state.SetLabel("point+du+dv, " + std::to_string(workload(net).patches) + " patches");
        })
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
      }
}

}  // namespace shapespline::bench
