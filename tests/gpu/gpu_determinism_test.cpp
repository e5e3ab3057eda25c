// Determinism on one device (issue 7): the same GPU job gives byte-identical output planes when run
// twice, and when split into different chunk sizes (EvaluatorOptions::maxPlaneBytes).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include <shapespline/core/surface.h>
#include <shapespline/gpu/evaluator.h>
#include "support/vk_fixture.h"

namespace shapespline::test {
namespace {

SurfaceModel wavySurface() {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.family.lambda = -4.0;
  m.rows = 7;
  m.cols = 6;
  m.closedV = true;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j)
      m.points.push_back({std::cos(j * 1.047) * (2 + 0.3 * i), std::sin(j * 1.047) * (2 + 0.2 * i), i + 0.1 * j});
  for (int k = 0; k < m.rows * m.cols; ++k) m.alpha.push_back(k % 5 == 0 ? 1.0 : 0.3 + 0.1 * (k % 4));
  return m;
}

// Each field's bytes, chunks concatenated in order (so the result does not depend on the chunking).
std::vector<unsigned char> runJob(std::shared_ptr<vk::Context> ctx, const Surface& surface, Precision precision,
                                  size_t maxPlaneBytes, size_t& chunks) {
  gpu::EvaluatorOptions options;
  options.maxPlaneBytes = maxPlaneBytes;
  gpu::SurfaceEvaluator evaluator(ctx, precision, options);
  gpu::GpuSurface state(ctx, surface, precision);
  GridSpec grid;
  grid.samplesU = 9;
  grid.samplesV = 7;
  FieldMask fields = 0;
  for (Field f : {Field::Point, Field::Du, Field::Dv, Field::Duu, Field::Duv, Field::Dvv, Field::Normal})
    fields |= fieldBit(f);
  std::vector<unsigned char> perField[kFieldCount];
  chunks = 0;
  const size_t scalar = precision == Precision::Double ? sizeof(double) : sizeof(float);
  evaluator.evaluateGrid(state, grid, fields, [&](const GridChunk& c) {
    ++chunks;
    for (int f = 0; f < kFieldCount; ++f) {
      if (!c.planes[f]) continue;
      const auto* p = static_cast<const unsigned char*>(c.planes[f]);
      perField[f].insert(perField[f].end(), p, p + c.pointCount() * 3 * scalar);
    }
  });
  std::vector<unsigned char> bytes;
  for (const auto& f : perField) bytes.insert(bytes.end(), f.begin(), f.end());
  return bytes;
}

class GpuDeterminism : public VulkanTest {};

TEST_F(GpuDeterminism, SameJobTwiceAndOtherChunkSizesGiveIdenticalBytes) {
  const Surface surface = Surface::create(wavySurface());
  std::vector<Precision> precisions{Precision::Float};
  if (ctx().supportsFloat64()) precisions.push_back(Precision::Double);
  for (Precision precision : precisions) {
    size_t chunksA = 0, chunksB = 0, chunksC = 0;
    const auto a = runJob(ctx_, surface, precision, size_t(64) << 20, chunksA);
    const auto b = runJob(ctx_, surface, precision, size_t(64) << 20, chunksB);
    // About three patches per chunk: many chunks, boundaries in other places.
    const size_t small = 3 * 9 * 7 * 3 * (precision == Precision::Double ? 8 : 4);
    const auto c = runJob(ctx_, surface, precision, small, chunksC);
    ASSERT_FALSE(a.empty());
    EXPECT_GT(chunksC, chunksA) << "the small plane limit should split the job";
    ASSERT_EQ(a.size(), b.size());
    ASSERT_EQ(a.size(), c.size());
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size())) << "run twice, precision " << int(precision);
    EXPECT_EQ(0, std::memcmp(a.data(), c.data(), a.size())) << "other chunk size, precision " << int(precision);
  }
}

}  // namespace
}  // namespace shapespline::test
