// Items larger than a chunk (core/grid_sampler.h, issue 12 requirement 5): the CPU sampler cuts a
// patch (span) whose points exceed maxChunkPoints into row ranges, so no chunk holds more than
// max(maxChunkPoints, Sv) points; the ranges arrive in row order, threads share the rows of one
// chunk, and the bytes equal a run with whole patches per chunk, for every path (plain tensor
// rows, α-EB with normals, knot-vector B-splines) and for curve spans cut into sample ranges.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include <shapespline/core/grid_sampler.h>

#include "support/test_models.h"

namespace shapespline {
namespace {

struct Collected {
  std::vector<double> data[kFieldCount];
  size_t chunks = 0, partialChunks = 0, maxPoints = 0;
  size_t items = 0, itemPoint = 0;  // next expected item / point inside it
  bool ordered = true;
  ChunkConsumer consumer() {
    return [this](const GridChunk& c) {
      ++chunks;
      if (c.partial()) {
        ++partialChunks;
        if (c.itemCount != 1 || c.firstRow * c.pointsPerRow >= c.pointsPerItem) ordered = false;
      }
      if (c.firstItem != items || c.firstItemPoint() != itemPoint) ordered = false;
      if (c.endsItem()) {
        items += c.itemCount, itemPoint = 0;
      } else {
        itemPoint = c.firstItemPoint() + c.pointCount();
      }
      maxPoints = std::max(maxPoints, c.pointCount());
      for (int f = 0; f < kFieldCount; ++f)
        if (c.planes[f]) {
          const auto* p = static_cast<const double*>(c.planes[f]);
          data[f].insert(data[f].end(), p, p + c.pointCount() * 3);
        }
    };
  }
};

void expectSame(const Collected& a, const Collected& b, const std::string& what) {
  for (int f = 0; f < kFieldCount; ++f) {
    ASSERT_EQ(a.data[f].size(), b.data[f].size()) << what << ", field " << f;
    if (a.data[f].empty()) continue;
    EXPECT_EQ(0, std::memcmp(a.data[f].data(), b.data[f].data(), a.data[f].size() * sizeof(double)))
        << what << ", field " << f << ": row-range chunks differ from whole-patch chunks";
  }
}

// Whole patches (a budget above the job) against row ranges under `budget` points, 1 and 3 threads.
void checkSurface(const Surface& s, const GridSpec& grid, FieldMask fields, size_t budget, const std::string& what) {
  Collected whole, one, three;
  whole.items = one.items = three.items = grid.firstItem;
  sampleSurfaceGrid(s, grid, fields, whole.consumer(), {1, size_t{1} << 24});
  sampleSurfaceGrid(s, grid, fields, one.consumer(), {1, budget});
  sampleSurfaceGrid(s, grid, fields, three.consumer(), {3, budget});
  EXPECT_EQ(whole.partialChunks, 0u) << what;
  for (const Collected* c : {&one, &three}) {
    EXPECT_GT(c->partialChunks, 2u) << what << ": the patches were not cut into row ranges";
    EXPECT_LE(c->maxPoints, std::max<size_t>(budget, size_t(grid.samplesV))) << what << ": a chunk exceeds the budget";
    EXPECT_TRUE(c->ordered) << what << ": row ranges out of order";
    expectSame(whole, *c, what);
  }
}

TEST(GridRowChunks, PlainSurfaceRows) {
  const Surface s = Surface::create(test::wavyNet({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 7, false));
  // Plain partials take the interleaved row path; 333 is not a multiple of the row (24 points).
  checkSurface(s, {40, 24, 2, 3}, fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dvv), 333,
               "plain 40x24");
  // A budget below one row: one row per chunk.
  checkSurface(s, {9, 50, 0, 2}, fieldBit(Field::Point), 7, "plain 9x50, budget under a row");
}

TEST(GridRowChunks, AlphaEBSurfaceWithNormals) {
  const Surface s = Surface::create(test::wavyNet({Construction::AlphaEB, 5, 0, -2.0, {}}, 7, true));
  checkSurface(s, {31, 17, 0, 2}, kSurfaceFields, 100, "alpha-EB 31x17");
}

TEST(GridRowChunks, KnotVectorSurface) {
  SurfaceModel m = test::wavyNet({Construction::BSpline, 0, 4, 0.0, {}}, 5, false);
  m.knotsU = m.knotsV = {0, 0, 0, 0, 0.4, 1, 1, 1, 1};
  const Surface s = Surface::create(std::move(m));
  checkSurface(s, {21, 13, 0, 0}, kSurfaceFields, 50, "knot-vector 21x13");
}

TEST(GridRowChunks, CurveSpansInSampleRanges) {
  CurveModel m;
  m.family = {Construction::AlphaEB, 5, 0, 0.5, {}};
  for (int i = 0; i < 9; ++i) m.points.push_back({double(i), std::sin(1.3 * i), 0.0});
  m.alpha.assign(9, 0.6);
  const Curve c = Curve::create(std::move(m));
  Collected whole, one, three;
  sampleCurveGrid(c, {1000, 1, 0, 0}, kCurveFields, whole.consumer(), {1, size_t{1} << 24});
  sampleCurveGrid(c, {1000, 1, 0, 0}, kCurveFields, one.consumer(), {1, 301});
  sampleCurveGrid(c, {1000, 1, 0, 0}, kCurveFields, three.consumer(), {3, 301});
  for (const Collected* x : {&one, &three}) {
    EXPECT_GT(x->partialChunks, 2u);
    EXPECT_LE(x->maxPoints, 301u);
    EXPECT_TRUE(x->ordered);
    expectSame(whole, *x, "alpha-EB curve S = 1000");
  }
}

// A consumer that throws in the middle of a patch stops the job cleanly (no worker outlives it).
TEST(GridRowChunks, ConsumerExceptionInsideAPatch) {
  const Surface s = Surface::create(test::wavyNet({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 5, false));
  int calls = 0;
  auto failing = [&](const GridChunk& c) {
    EXPECT_TRUE(c.partial());
    if (++calls == 3) throw std::runtime_error("disk full");
  };
  EXPECT_THROW(sampleSurfaceGrid(s, {64, 64, 0, 1}, fieldBit(Field::Point), failing, {2, 100}), std::runtime_error);
  EXPECT_EQ(calls, 3);
}

}  // namespace
}  // namespace shapespline
