// A ~2·10^7-point job through 4 MiB planes (gpu/evaluator.h) keeps the process's peak memory
// bounded: max RSS grows by far less than the job's output.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <set>

#include <shapespline/core/curve.h>
#include <shapespline/gpu/evaluator.h>
#include "support/vk_fixture.h"

namespace shapespline::test {
namespace {

long maxRssKiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

// ~2·10^7 points (240 MB of fp32 xyz) through 4 MiB planes: the ring bounds memory by design
// (2 slots x 1 field x 4 MiB); peak RSS must grow by far less than the job's output.
class GpuStreamLarge : public VulkanTest {};

TEST_F(GpuStreamLarge, JobStreamsInBoundedMemory) {
  CurveModel m;
  m.family.construction = Construction::ExtendedBSpline;
  m.family.degree = 4;
  m.family.lambda = 0.0;
  m.dimension = 3;
  for (int i = 0; i < 1003; ++i) m.points.push_back({double(i), std::sin(0.1 * i), std::cos(0.07 * i)});
  const Curve cpu = Curve::create(m);
  gpu::GpuCurve state(ctx_, cpu, Precision::Float);
  gpu::EvaluatorOptions opt;
  opt.maxPlaneBytes = size_t(4) << 20;
  opt.workgroupSize = 128;
  gpu::CurveEvaluator ev(ctx_, Precision::Float, opt);
  GridSpec grid;
  grid.samplesU = 20000;
  const size_t items = state.gridItemCount();
  const size_t points = items * grid.samplesU;
  ASSERT_GE(points, size_t(2e7));
  // Warm-up (pipeline compile, driver pools) before the peak is measured.
  GridSpec warm = grid;
  warm.itemCount = 4;
  ev.evaluateGrid(state, warm, fieldBit(Field::Point), [](const GridChunk&) {});
  const long before = maxRssKiB();
  size_t seen = 0, chunks = 0;
  std::set<const void*> planes;
  double maxErr = 0.0;
  ev.evaluateGrid(state, grid, fieldBit(Field::Point), [&](const GridChunk& c) {
    ASSERT_LE(c.pointCount() * 3 * sizeof(float), opt.maxPlaneBytes);
    planes.insert(c.planes[0]);
    // Spot-check the first and last point of the chunk against the CPU core.
    for (size_t p : {size_t(0), c.pointCount() - 1}) {
      const size_t item = c.firstItem + p / grid.samplesU;
      const double t = double(p % grid.samplesU) / (grid.samplesU - 1);
      const CurvePoint e = cpu.evaluate(cpu.spans().first + int(item), t);
      for (int k = 0; k < 3; ++k) maxErr = std::max(maxErr, std::abs(e.point[k] - c.coord(Field::Point, p, k)));
    }
    seen += c.pointCount();
    ++chunks;
  });
  const long grownMiB = (maxRssKiB() - before) / 1024;
  EXPECT_EQ(seen, points);
  EXPECT_GT(chunks, 50u);
  EXPECT_LE(planes.size(), 2u);
  EXPECT_LT(maxErr, 1e-3);
  EXPECT_LT(grownMiB, 48) << "peak RSS grew by " << grownMiB << " MiB for a " << points * 12 / (1 << 20)
                          << " MiB job";
  std::printf("  streamed %zu points in %zu chunks; peak RSS grew by %ld MiB\n", points, chunks, grownMiB);
}

}  // namespace
}  // namespace shapespline::test
