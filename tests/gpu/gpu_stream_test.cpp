// Streaming of grid jobs (gpu/evaluator.h): a job forced into many chunks delivers exactly the bytes
// of a single-chunk run; at most two output slots are ever handed out (the ring), each within
// maxPlaneBytes; and a consumer that throws leaves no GPU work behind. (The peak memory of a long
// job: tests/memory/gpu_stream_rss_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <stdexcept>

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
  m.closedU = true;
  m.rows = 9;
  m.cols = 7;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> d(-0.3, 0.3), a(0.3, 1.0);
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) m.points.push_back({i + d(rng), j + d(rng), std::cos(i + 0.5 * j) + d(rng)});
  for (int i = 0; i < m.rows * m.cols; ++i) m.alpha.push_back(a(rng));
  return Surface::create(std::move(m));
}

// Every field plane of every chunk concatenated in item order, plus what the ring handed out.
struct Collected {
  std::vector<std::byte> bytes[kFieldCount];
  std::set<const void*> planes;
  size_t chunks = 0, maxChunkPlaneBytes = 0;
};

ChunkConsumer collector(Collected& out, size_t realBytes) {
  return [&out, realBytes](const GridChunk& c) {
    ++out.chunks;
    for (int f = 0; f < kFieldCount; ++f) {
      if (!c.planes[f]) continue;
      const size_t n = c.pointCount() * 3 * realBytes;
      const auto* p = static_cast<const std::byte*>(c.planes[f]);
      out.bytes[f].insert(out.bytes[f].end(), p, p + n);
      out.planes.insert(c.planes[f]);
      out.maxChunkPlaneBytes = std::max(out.maxChunkPlaneBytes, n);
    }
  };
}

// Parameter: the precision (skipped for fp64 without shaderFloat64).
class GpuStream : public VulkanTest, public ::testing::WithParamInterface<Precision> {
 protected:
  void SetUp() override {
    VulkanTest::SetUp();
    if (IsSkipped()) return;
    if (GetParam() == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  }
  size_t realBytes() const { return GetParam() == Precision::Double ? 8 : 4; }
};

TEST_P(GpuStream, ManyChunksAreByteIdenticalToOneChunk) {
  const Precision pr = GetParam();
  const size_t rs = realBytes();
  gpu::GpuSurface state(ctx_, alphaEBSurface(), pr);
  GridSpec grid;
  grid.samplesU = 13;
  grid.samplesV = 6;
  Collected one, many;
  gpu::SurfaceEvaluator single(ctx_, pr);
  single.evaluateGrid(state, grid, kSurfaceFields, collector(one, rs));
  gpu::EvaluatorOptions small;
  small.maxPlaneBytes = 3 * grid.pointsPerItem() * 3 * rs + 100;  // 3 patches per chunk
  gpu::SurfaceEvaluator chunked(ctx_, pr, small);
  chunked.evaluateGrid(state, grid, kSurfaceFields, collector(many, rs));
  EXPECT_EQ(one.chunks, 1u);
  EXPECT_GT(many.chunks, 10u);
  EXPECT_LE(many.maxChunkPlaneBytes, small.maxPlaneBytes);
  EXPECT_LE(many.planes.size(), 2u * 7u) << "more than two slots of planes were handed out";
  for (int f = 0; f < kFieldCount; ++f) {
    ASSERT_EQ(one.bytes[f].size(), many.bytes[f].size()) << "field " << f;
    EXPECT_TRUE(one.bytes[f].empty() || std::memcmp(one.bytes[f].data(), many.bytes[f].data(), one.bytes[f].size()) == 0)
        << "field " << f << " differs between the single-chunk and the chunked run";
  }
  // A sub-range of items (firstItem/itemCount) streams the same bytes as the slice of the whole.
  GridSpec part = grid;
  part.firstItem = 5;
  part.itemCount = 17;
  Collected slice;
  chunked.evaluateGrid(state, part, fieldBit(Field::Point), collector(slice, rs));
  const size_t itemBytes = grid.pointsPerItem() * 3 * rs;
  ASSERT_EQ(slice.bytes[0].size(), 17 * itemBytes);
  EXPECT_EQ(std::memcmp(slice.bytes[0].data(), one.bytes[0].data() + 5 * itemBytes, slice.bytes[0].size()), 0);
}

// The evaluator keeps its readback planes from one job to the next (gpu/plane_pool.h): a repeated
// job gets the same planes and the same bytes; a job whose single item exceeds the plane budget
// still runs (its planes are dropped afterwards), and the budget-sized job after it is unchanged.
TEST_P(GpuStream, SuccessiveJobsReuseTheirPlanes) {
  const Precision pr = GetParam();
  const size_t rs = realBytes();
  gpu::GpuSurface state(ctx_, alphaEBSurface(), pr);
  const GridSpec grid{9, 8, 0, 0};
  gpu::EvaluatorOptions small;
  small.maxPlaneBytes = 3 * grid.pointsPerItem() * 3 * rs + 100;  // 3 patches per chunk
  gpu::SurfaceEvaluator ev(ctx_, pr, small);
  Collected first, second, afterLarge;
  ev.evaluateGrid(state, grid, kSurfaceFields, collector(first, rs));
  ev.evaluateGrid(state, grid, kSurfaceFields, collector(second, rs));
  EXPECT_GT(first.chunks, 2u);
  EXPECT_EQ(first.planes, second.planes) << "the second job allocated new planes";
  GridSpec large;
  large.samplesU = large.samplesV = 64;  // one patch's plane is 4096 points, over the budget
  large.itemCount = 2;
  Collected big;
  ev.evaluateGrid(state, large, fieldBit(Field::Point), collector(big, rs));
  EXPECT_EQ(big.bytes[0].size(), 2 * large.pointsPerItem() * 3 * rs);
  ev.evaluateGrid(state, grid, kSurfaceFields, collector(afterLarge, rs));
  for (int f = 0; f < kFieldCount; ++f) {
    ASSERT_EQ(first.bytes[f].size(), second.bytes[f].size()) << "field " << f;
    ASSERT_EQ(first.bytes[f].size(), afterLarge.bytes[f].size()) << "field " << f;
    EXPECT_TRUE(first.bytes[f].empty() ||
                (std::memcmp(first.bytes[f].data(), second.bytes[f].data(), first.bytes[f].size()) == 0 &&
                 std::memcmp(first.bytes[f].data(), afterLarge.bytes[f].data(), first.bytes[f].size()) == 0))
        << "field " << f << " differs between successive jobs";
  }
}

TEST_P(GpuStream, ThrowingConsumerLeavesNothingInFlight) {
  const Precision pr = GetParam();
  gpu::GpuSurface state(ctx_, alphaEBSurface(), pr);
  gpu::EvaluatorOptions small;
  small.maxPlaneBytes = 4096;
  gpu::SurfaceEvaluator ev(ctx_, pr, small);
  GridSpec grid;
  grid.samplesU = grid.samplesV = 8;
  int calls = 0;
  EXPECT_THROW(ev.evaluateGrid(state, grid, kSurfaceFields,
                               [&](const GridChunk&) {
                                 if (++calls == 2) throw std::runtime_error("consumer stops");
                               }),
               std::runtime_error);
  EXPECT_EQ(calls, 2);
  // The evaluator and model stay usable.
  Collected again;
  ev.evaluateGrid(state, grid, fieldBit(Field::Point), collector(again, realBytes()));
  EXPECT_GT(again.chunks, 2u);
}

INSTANTIATE_TEST_SUITE_P(Precisions, GpuStream, ::testing::Values(Precision::Float, Precision::Double),
                         [](const auto& i) { return std::string(i.param == Precision::Double ? "fp64" : "fp32"); });

}  // namespace
}  // namespace shapespline::test
