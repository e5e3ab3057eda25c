#pragma once
// GPU evaluators (OpenSubdiv style): each holds the compiled pipelines of one precision and
// evaluates any GpuCurve / GpuSurface (gpu_model.h) of that precision. Kernels: shaders/*.comp,
// buffer layouts: shaders/layout.h, math: docs/math.md §1–§6 mirrored from host/core.
//
// Grid jobs (core/sample_grid.h) run chunk by chunk: a chunk is a whole number of spans/patches
// whose output planes each fit in EvaluatorOptions::maxPlaneBytes, or, for an item larger than
// that, a range of its rows (whole kernel invocations: a span of up to 256 samples is never cut),
// so device and host memory stay bounded whatever the job or grid size; the consumer sees each
// chunk once, in order, while the output buffers are mapped. Two output slots stream: the GPU computes chunk
// k+1 while the consumer reads chunk k, so device + host memory stay at 2 chunks of planes
// (2 x fields x maxPlaneBytes) however many points the job has. The evaluator keeps those planes
// for its next grid job (gpu/plane_pool.h); an evaluator is used by one thread at a time.
#include <shapespline/core/curve.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/core/span_basis.h>
#include <shapespline/core/surface.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/vk/context.h>

#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace shapespline::gpu {

class KernelSet;
class PlanePool;

struct EvaluatorOptions {
  uint32_t workgroupSize = 64;                 // spec constant of every kernel
  // Bytes per output plane and chunk (items larger than this go in row ranges; only one granule
  // of rows, at most 16 rows of a patch or 64 samples of a span, may exceed it). Small planes stay
  // resident between chunks: 64 MiB planes cost ~1e5 first-touch page faults per 15 M-point job on
  // lavapipe and halved its throughput (measured 2–4 MiB: 113–124 vs 27–59 Mpts/s fp32).
  size_t maxPlaneBytes = size_t(4) << 20;
  bool generalKernelsOnly = false;             // never pick a specialised fast kernel (tests, benchmarks)
  // Store fp32 output planes as uint64 pairs where the device has shaderInt64 (half the stores on
  // llvmpipe; the same bytes). Off: the plain float stores every device runs (tests cover both).
  bool packedStores = true;
};

struct CurveSample {
  int span = 0;      // model span index (Curve::spans())
  double t = 0.0;    // local parameter in [0,1]
};
struct SurfaceSample {
  int i = 0, j = 0;  // model patch indices (Surface::patches())
  double u = 0.0, v = 0.0;
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
  std::vector<CurvePoint> evaluateList(GpuCurve& curve, std::span<const CurveSample> samples);
  // Point, d1, d2 at global parameters u (GpuCurve::parameterRange(); as Curve::evaluateAt).
  std::vector<CurvePoint> evaluateListAt(GpuCurve& curve, std::span<const double> u);

 private:
  std::unique_ptr<KernelSet> kernels_;
  std::unique_ptr<PlanePool> planes_;  // readback planes reused by successive grid jobs
  EvaluatorOptions options_;
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
  std::vector<SurfacePoint> evaluateList(GpuSurface& surface, std::span<const SurfaceSample> samples);
  // Every field at global (U, V) (as Surface::evaluateAt).
  std::vector<SurfacePoint> evaluateListAt(GpuSurface& surface, std::span<const std::pair<double, double>> uv);

 private:
  std::unique_ptr<KernelSet> kernels_;
  std::unique_ptr<PlanePool> planes_;  // readback planes reused by successive grid jobs
  EvaluatorOptions options_;
};

// B_r, B_r', B_r'' of a SpanBasis at N uniform parameters t_a = a/(N-1) (basis_table.comp); the
// same table the grid kernels read. Row a of the result holds values[0..m), d1[0..m), d2[0..m).
class BasisTableEvaluator {
 public:
  BasisTableEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision, EvaluatorOptions options = {});
  ~BasisTableEvaluator();
  // Returns N * 3 * m values (layout.h TABLE layout).
  std::vector<double> evaluate(const SpanBasis& basis, int sampleCount);
  // The same at arbitrary parameters t (each in [0,1]).
  std::vector<double> evaluateAt(const SpanBasis& basis, std::span<const double> t);

 private:
  std::vector<double> run(const SpanBasis& basis, int sampleCount, std::span<const double> list);
  std::unique_ptr<KernelSet> kernels_;
};

}  // namespace shapespline::gpu
