// Items larger than a chunk (gpu/evaluator.h, issue 12 requirement 5): with maxPlaneBytes below one
// patch's (span's) plane, every kernel (surface_grid, surface_eval, curve_grid, curve_eval and the
// knot-vector bspline_*_eval) is run on row ranges of the item. Each chunk's plane stays within the
// budget, the row ranges arrive in order and cover the item once, and the bytes equal a run with
// the whole item in one chunk.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>
#include <shapespline/gpu/evaluator.h>
#include "support/vk_fixture.h"

namespace shapespline::test {
namespace {

Surface alphaEBSurface() {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.family.lambda = 0.5;
  m.rows = 8;
  m.cols = 8;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-0.3, 0.3), a(0.3, 1.0);
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) m.points.push_back({i + d(rng), j + d(rng), std::cos(i + 0.5 * j) + d(rng)});
  for (int i = 0; i < m.rows * m.cols; ++i) m.alpha.push_back(a(rng));
  return Surface::create(std::move(m));
}

// A clamped cubic B-spline patch with knot vectors (the bspline_surface_eval kernel).
Surface knotSurface() {
  SurfaceModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 4;
  m.orderV = 4;
  m.rows = m.cols = 5;
  m.knotsU = m.knotsV = {0, 0, 0, 0, 0.4, 1, 1, 1, 1};
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) m.points.push_back({double(i), double(j), std::sin(0.9 * i) * std::cos(0.7 * j)});
  return Surface::create(std::move(m));
}

Curve alphaEBCurve() {
  CurveModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.family.lambda = 0.5;
  for (int i = 0; i < 8; ++i) m.points.push_back({double(i), std::sin(1.3 * i), 0.0});
  m.alpha.assign(8, 0.6);
  return Curve::create(std::move(m));
}

Curve knotCurve() {
  CurveModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 4;
  m.knots = {0, 0, 0, 0, 0.3, 0.7, 1, 1, 1, 1};
  for (int i = 0; i < 6; ++i) m.points.push_back({double(i), std::sin(1.3 * i), 0.0});
  return Curve::create(std::move(m));
}

struct Collected {
  std::vector<std::byte> bytes[kFieldCount];
  size_t chunks = 0, partialChunks = 0, maxPlaneBytes = 0;
  size_t items = 0, itemPoint = 0;  // next expected item / point inside it
  bool ordered = true;
};

ChunkConsumer collector(Collected& out, size_t realBytes) {
  return [&out, realBytes](const GridChunk& c) {
    ++out.chunks;
    if (c.partial()) ++out.partialChunks;
    if (c.firstItem != out.items || c.firstItemPoint() != out.itemPoint) out.ordered = false;
    if (c.endsItem()) {
      out.items += c.itemCount, out.itemPoint = 0;
    } else {
      out.itemPoint = c.firstItemPoint() + c.pointCount();
    }
    for (int f = 0; f < kFieldCount; ++f) {
      if (!c.planes[f]) continue;
      const size_t n = c.pointCount() * 3 * realBytes;
      const auto* p = static_cast<const std::byte*>(c.planes[f]);
      out.bytes[f].insert(out.bytes[f].end(), p, p + n);
      out.maxPlaneBytes = std::max(out.maxPlaneBytes, n);
    }
  };
}

void expectSame(const Collected& whole, const Collected& rows, const std::string& what) {
  for (int f = 0; f < kFieldCount; ++f) {
    ASSERT_EQ(whole.bytes[f].size(), rows.bytes[f].size()) << what << ", field " << f;
    EXPECT_TRUE(whole.bytes[f].empty() ||
                std::memcmp(whole.bytes[f].data(), rows.bytes[f].data(), whole.bytes[f].size()) == 0)
        << what << ", field " << f << ": row-range chunks differ from whole-item chunks";
  }
}

class GpuRowChunks : public VulkanTest, public ::testing::WithParamInterface<Precision> {
 protected:
  void SetUp() override {
    VulkanTest::SetUp();
    if (IsSkipped()) return;
    if (GetParam() == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  }
  size_t rs() const { return GetParam() == Precision::Double ? 8 : 4; }

  // Runs the job whole (large planes) and with a budget of `budgetPoints` points per plane.
  template <class Evaluator, class Model>
  void check(Model& model, const GridSpec& grid, FieldMask fields, size_t budgetPoints,
             const std::string& what) {
    gpu::EvaluatorOptions big, small;
    big.maxPlaneBytes = size_t(64) << 20;
    small.maxPlaneBytes = budgetPoints * 3 * rs();
    Collected whole, rows;
    whole.items = rows.items = grid.firstItem;
    Evaluator(ctx_, GetParam(), big).evaluateGrid(model, grid, fields, collector(whole, rs()));
    Evaluator(ctx_, GetParam(), small).evaluateGrid(model, grid, fields, collector(rows, rs()));
    EXPECT_EQ(whole.partialChunks, 0u) << what;
    EXPECT_GT(rows.partialChunks, 2u) << what << ": the items were not cut into row ranges";
    EXPECT_LE(rows.maxPlaneBytes, small.maxPlaneBytes) << what << ": a chunk's plane exceeds the budget";
    EXPECT_TRUE(rows.ordered) << what << ": row ranges out of order";
    expectSame(whole, rows, what);
  }
};

TEST_P(GpuRowChunks, SurfaceGridKernel) {
  gpu::GpuSurface s(ctx_, alphaEBSurface(), GetParam());
  // Sv = 24: 16 rows per invocation would not divide 40, so 8; a 200-point budget cuts a patch into
  // 5 ranges of 8 rows. Sv = 300: runs of 4 samples within a row; ranges of 2 rows.
  check<gpu::SurfaceEvaluator>(s, {40, 24, 3, 4}, kSurfaceFields, 200, "surface_grid 40x24");
  check<gpu::SurfaceEvaluator>(s, {6, 300, 0, 2}, fieldBit(Field::Point) | fieldBit(Field::Normal), 700,
                               "surface_grid 6x300");
}

TEST_P(GpuRowChunks, SurfaceGeneralKernel) {
  gpu::GpuSurface s(ctx_, alphaEBSurface(), GetParam());
  check<gpu::SurfaceEvaluator>(s, {37, 23, 1, 3}, kSurfaceFields, 100, "surface_eval 37x23");
  check<gpu::SurfaceEvaluator>(s, {20, 17, 0, 2}, kSurfaceFields, 50, "surface_eval 20x17");
}

TEST_P(GpuRowChunks, KnotVectorSurface) {
  gpu::GpuSurface s(ctx_, knotSurface(), GetParam());
  check<gpu::SurfaceEvaluator>(s, {21, 13, 0, 0}, kSurfaceFields, 40, "bspline_surface_eval 21x13");
}

TEST_P(GpuRowChunks, CurveKernels) {
  gpu::GpuCurve c(ctx_, alphaEBCurve(), GetParam());
  check<gpu::CurveEvaluator>(c, {1024, 1, 0, 0}, kCurveFields, 200, "curve_grid S = 1024 (runs of 64)");
  check<gpu::CurveEvaluator>(c, {700, 1, 1, 2}, kCurveFields, 90, "curve_grid S = 700 (runs of 4)");
  check<gpu::CurveEvaluator>(c, {702, 1, 0, 3}, kCurveFields, 90, "curve_eval S = 702");
  gpu::GpuCurve k(ctx_, knotCurve(), GetParam());
  check<gpu::CurveEvaluator>(k, {301, 1, 0, 0}, kCurveFields, 50, "bspline_curve_eval S = 301");
}

// A span of at most 256 samples is one grid-kernel invocation: a budget below it keeps it whole.
TEST_P(GpuRowChunks, ShortSpansStayWhole) {
  gpu::GpuCurve c(ctx_, alphaEBCurve(), GetParam());
  gpu::EvaluatorOptions tiny;
  tiny.maxPlaneBytes = 8 * 3 * rs();
  Collected out;  // from item 0
  gpu::CurveEvaluator(ctx_, GetParam(), tiny).evaluateGrid(c, {64, 1, 0, 0}, kCurveFields, collector(out, rs()));
  EXPECT_EQ(out.partialChunks, 0u);
  EXPECT_TRUE(out.ordered);
  EXPECT_EQ(out.chunks, c.spanCount());
}

INSTANTIATE_TEST_SUITE_P(Precisions, GpuRowChunks, ::testing::Values(Precision::Float, Precision::Double),
                         [](const auto& i) { return std::string(i.param == Precision::Double ? "fp64" : "fp32"); });

}  // namespace
}  // namespace shapespline::test
