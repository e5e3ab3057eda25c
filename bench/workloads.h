#pragma once
// What every benchmark shares: the workloads (control nets, grids, fields), the Vulkan context,
// the cheap chunk consumer and the cross-check log. One-time costs (model construction, net upload,
// pipeline creation and first compile, OpenSubdiv patch table and patch coordinates) happen outside
// the timed loops; the cross-checks in main() run every evaluator once before any timing, which also
// warms the GPU pipelines.
#include <shapespline/core/curve.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/core/surface.h>
#include <shapespline/vk/context.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace shapespline::bench {

// 64 x 64 control net, open in both directions: 61 x 61 = 3721 uniform cubic B-spline patches
// (Xu-Wang degree 4 at λ = 0 is the uniform cubic B-spline, docs/math.md §2.1).
inline constexpr int kNetSize = 64;
inline constexpr int kCurvePoints = 10000;       // closed α-EB curve: 10,000 spans
inline constexpr int kCurveSamplesPerSpan = 64;

inline constexpr FieldMask kPointDuDv = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv);
inline constexpr FieldMask kPointNormal = fieldBit(Field::Point) | fieldBit(Field::Normal);
inline constexpr FieldMask kPointD1 = fieldBit(Field::Point) | fieldBit(Field::D1);

// Cross-check tolerances as fractions of the control net's bounding-box diagonal (derivatives are
// compared with the same absolute bound: |B'| sums to at most 2 on these bases). OpenSubdiv and our
// fp32 path round the net and every product to float: 16 products of values up to the extent, a few
// ulps each, stay well under 64 ulps of the extent.
inline constexpr double kFloatRel = 64 * 1.1920928955078125e-07;
inline constexpr double kDoubleRel = 1e-12;

// A wavy height field over the integer grid, deterministic (seeded), x along rows (u), y along
// columns (v). α-EB families get α in [0.3, 1].
SurfaceModel gridSurfaceModel(const FamilySpec& family, int n, unsigned seed);
// A closed planar-ish loop of n points with noise; α in [0.3, 1] for α-EB.
CurveModel closedCurveModel(const FamilySpec& family, int n, unsigned seed);
double boxDiagonal(const std::vector<glm::dvec3>& points);
// The speed workload of bspline3_S* (surface_bench.cpp): uniform bicubic (Xu-Wang degree 4, λ = 0)
// on the kNetSize x kNetSize net, 3721 patches; `shapespline_bench --write-model=PATH` writes it
// for bench/e2e.
SurfaceModel bsplineWorkloadModel();
// The same net as an order-4 knot-vector B-spline: knots 0..67 (the same surface), or clamped
// random knots (intervals of 0.25 to 1.75); rational: random weights in [0.5, 2].
SurfaceModel knotWorkloadModel(bool randomKnots, bool rational);

// The real-time workload (tessellation_bench.cpp, bench/realtime): an α-EB surface of degree 5,
// 25 x 40 patches (open/open) over a gentle height field, α = 0.6 with every 7th vertex at 1.
inline SurfaceModel thousandPatchAlphaEB() {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.family.lambda = 0.0;
  m.rows = 26;
  m.cols = 41;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j)
      m.points.push_back({double(i), double(j), 0.5 * std::sin(0.7 * i) * std::cos(0.45 * j)});
  m.alpha.assign(size_t(m.rows) * m.cols, 0.6);
  for (size_t k = 0; k < m.alpha.size(); k += 7) m.alpha[k] = 1.0;
  return m;
}

// The shared Vulkan context (fp64 devices preferred), or nullptr with the reason.
std::shared_ptr<vk::Context> gpuContext();
const std::string& gpuUnavailableReason();

// Touches each delivered chunk cheaply (first and last value of every plane) so no evaluation is
// optimised away while output I/O stays out of the measurement.
ChunkConsumer touchConsumer(double& sink);

// Every chunk's values, field by field, as doubles (cross-checks only).
struct Collected {
  std::vector<double> planes[kFieldCount];
  ChunkConsumer consumer();
};
// Largest |a - b| over the fields in `fields` (both must hold them, same size; else +inf);
// `worstPoint` (optional) receives the point index where it occurs.
double maxDiff(const Collected& a, const Collected& b, FieldMask fields, size_t* worstPoint = nullptr);

// Prints "check: <what>: max |diff| = d (tolerance t) ok|FAILED" to stderr and records it in the
// benchmark context (it lands in the JSON output).
void reportCheck(const std::string& what, double maxDiff, double tolerance);
void reportSkip(const std::string& what, const std::string& reason);
bool allChecksPassed();

// Cross-checks of each benchmark file, run by main() before the benchmarks are registered.
void crossCheckSurfaces();
void crossCheckAlphaEB();
void registerSurfaceBenchmarks();
void registerAlphaEBBenchmarks();

}  // namespace shapespline::bench
