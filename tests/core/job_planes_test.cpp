// The CPU sampler writing the caller's arrays (SamplerOptions::jobPlanes, what Python's sample()
// gives it): the same bits, at the same places, as a run over chunk buffers copied out by point
// index, for plain rows, α-EB with normals, knot-vector and rational surfaces and curves, with items
// cut into row ranges, a shard's item range and 1-3 threads; the slice consumer and the consumer
// see chunks over the arrays; planes for other fields than the sampled ones are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <shapespline/core/grid_sampler.h>

#include "support/test_models.h"

namespace shapespline {
namespace {

using Planes = std::vector<std::vector<double>>;  // per field: 3 values per job point

// Runs `sample` both ways and compares every field's values bit for bit.
template <class Sample>
void expectSamePlanes(Sample sample, FieldMask fields, size_t points, int threads, size_t chunkPoints,
                      const std::string& what) {
  Planes copied(kFieldCount), direct(kFieldCount);
  std::array<double*, kFieldCount> jobPlanes{};
  for (int f = 0; f < kFieldCount; ++f) {
    if (!(fields & fieldBit(Field(f)))) continue;
    copied[size_t(f)].assign(points * 3, std::nan(""));
    direct[size_t(f)].assign(points * 3, std::nan(""));
    jobPlanes[size_t(f)] = direct[size_t(f)].data();
  }
  size_t firstJobItem = SIZE_MAX, ppi = 0;
  SamplerOptions a{threads, chunkPoints};
  sample(a, [&](const GridChunk& c) {
    if (firstJobItem == SIZE_MAX) firstJobItem = c.firstItem, ppi = c.pointsPerItem;
    const size_t at = (c.firstItem - firstJobItem) * ppi + c.firstItemPoint();
    for (int f = 0; f < kFieldCount; ++f)
      if (c.has(Field(f)))
        std::memcpy(&copied[size_t(f)][at * 3], c.planes[size_t(f)], c.pointCount() * 3 * sizeof(double));
  });
  SamplerOptions b{threads, chunkPoints};
  b.jobPlanes = jobPlanes;
  size_t slices = 0, chunks = 0;
  std::mutex mutex;
  b.slice = [&](const GridChunk& c, size_t first, size_t count) {
    const size_t at = (c.firstItem - firstJobItem) * ppi + c.firstItemPoint() + first;
    for (int f = 0; f < kFieldCount; ++f)
      if (c.has(Field(f))) {
        EXPECT_EQ(static_cast<const double*>(c.planes[size_t(f)]) + first * 3, jobPlanes[size_t(f)] + at * 3) << what;
      }
    std::lock_guard lock(mutex);
    slices += count;
  };
  sample(b, [&](const GridChunk& c) {
    ++chunks;
    const size_t at = (c.firstItem - firstJobItem) * ppi + c.firstItemPoint();
    EXPECT_EQ(c.planes[size_t(Field::Point)], jobPlanes[size_t(Field::Point)] + at * 3) << what;
  });
  EXPECT_EQ(slices, points) << what;
  EXPECT_GT(chunks, 0u) << what;
  for (int f = 0; f < kFieldCount; ++f) {
    if (copied[size_t(f)].empty()) continue;  // not sampled (and memcmp takes no null pointer)
    EXPECT_EQ(0, std::memcmp(copied[size_t(f)].data(), direct[size_t(f)].data(), copied[size_t(f)].size() * sizeof(double)))
        << what << " field " << f;
  }
}

void checkSurface(const Surface& s, const GridSpec& grid, FieldMask fields, int threads, size_t chunkPoints,
                  const std::string& what) {
  const size_t items = grid.itemCount ? grid.itemCount : surfaceGridItems(s).size() - grid.firstItem;
  expectSamePlanes([&](const SamplerOptions& o, const ChunkConsumer& c) { sampleSurfaceGrid(s, grid, fields, c, o); },
                   fields, items * grid.pointsPerItem(), threads, chunkPoints, what);
}

TEST(JobPlanes, EveryPathWritesTheCallersArraysAsTheChunkBuffersHoldThem) {
  const Surface plain = Surface::create(test::wavyNet({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 7, false));
  const Surface aeb = Surface::create(test::wavyNet({Construction::AlphaEB, 5, 0, -2.0, {}}, 7, true));
  SurfaceModel k = test::wavyNet({Construction::BSpline, 0, 4, 0.0, {}}, 6, false);
  k.knotsU = k.knotsV = {0, 0, 0, 0, 0.3, 0.3, 1, 1, 1, 1};
  const Surface knots = Surface::create(k);
  k.weights.assign(36, 1.0);
  for (size_t w = 0; w < 36; ++w) k.weights[w] = 0.5 + 0.05 * double(w);
  const Surface nurbs = Surface::create(k);
  for (int threads : {1, 2, 3}) {
    const std::string t = " threads " + std::to_string(threads);
    checkSurface(plain, {9, 13, 0, 0}, fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv), threads, 1000,
                 "plain" + t);
    checkSurface(plain, {40, 23, 3, 5}, kSurfaceFields, threads, 333, "plain in row ranges, items 3..7" + t);
    checkSurface(aeb, {11, 9, 0, 0}, kSurfaceFields, threads, 200, "alpha-EB" + t);
    checkSurface(knots, {7, 6, 0, 0}, kSurfaceFields, threads, 100, "knot vector" + t);
    checkSurface(nurbs, {7, 8, 1, 0}, kSurfaceFields, threads, 100, "rational" + t);
  }
  CurveModel m;
  m.family = {Construction::AlphaEB, 5, 0, 0.5, {}};
  m.dimension = 3;
  for (int i = 0; i < 9; ++i) m.points.push_back({double(i), std::sin(1.3 * i), 0.2 * i});
  m.alpha.assign(9, 0.6);
  const Curve curve = Curve::create(std::move(m));
  const FieldMask all = fieldBit(Field::Point) | fieldBit(Field::D1) | fieldBit(Field::D2);
  expectSamePlanes([&](const SamplerOptions& o, const ChunkConsumer& c) { sampleCurveGrid(curve, {301, 1, 0, 0}, all, c, o); },
                   all, curveGridItems(curve).size() * 301, 2, 100, "alpha-EB curve");
}

TEST(JobPlanes, PlanesForOtherFieldsThanTheSampledOnesAreRefused) {
  const Surface s = Surface::create(test::wavyNet({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 5, false));
  std::vector<double> plane(1 << 12);
  SamplerOptions o;
  o.jobPlanes[size_t(Field::Point)] = plane.data();
  EXPECT_THROW(sampleSurfaceGrid(s, {3, 3, 0, 1}, fieldBit(Field::Point) | fieldBit(Field::Du), [](const GridChunk&) {}, o),
               std::invalid_argument);
}

}  // namespace
}  // namespace shapespline
