// SurfaceTessellator and its topology (gpu/tessellator.h, core/tess_topology.h):
//  * topology: every interior mesh edge is shared by exactly two triangles of opposite orientation
//    and every border edge lies on an open boundary — no cracks, no T-junctions — for uniform,
//    per-patch and per-edge rates, open and closed directions; neighbours see the same edge vertex
//    list;
//  * GPU: vertices equal the CPU fp64 surface at their canonical samples, shared-edge vertices are
//    bitwise identical from both sides, normals are finite and unit, and at α = 1 vertices agree
//    with Surface::limitNormal (mean over the patches sharing the vertex, the documented rule);
//  * updates: λ, α and a control point show at the next record() without re-uploading the net;
//  * caller-owned vertex/index buffers; the index copy happens once per configuration.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <set>

#include <glm/geometric.hpp>
#include <glm/common.hpp>

#include <shapespline/core/surface.h>
#include <shapespline/core/tess_patches.h>
#include <shapespline/gpu/tessellator.h>
#include "support/tolerances.h"
#include "support/degenerate_nets.h"
#include "support/test_models.h"
#include "support/vk_fixture.h"
#include <shapespline/shaders/tess_layout.h>
#include <shapespline/vk/submit.h>

namespace shapespline::test {
namespace {

using shapespline::TessRates;
using shapespline::TessTopology;
using gpu::tess_layout::TessVertex;

// Half-edge check: each directed edge at most once; an undirected edge with one triangle must lie
// on an open border (both ends on a border side of the patch grid).
void expectWatertight(const TessTopology& t, const std::string& what) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (size_t k = 0; k < t.indices.size(); k += 3)
    for (int e = 0; e < 3; ++e) {
      const auto key = std::make_pair(t.indices[k + e], t.indices[k + (e + 1) % 3]);
      ASSERT_EQ(++directed[key], 1) << what << ": directed edge " << key.first << "->" << key.second << " used twice";
    }
  std::set<uint32_t> border;
  const TessRates& r = t.rates;
  for (int a = 0; a < r.patchesU; ++a)
    for (int b = 0; b < r.patchesV; ++b) {
      std::vector<int> sides;
      if (!r.closedV && b == 0) sides.push_back(0);
      if (!r.closedV && b == r.patchesV - 1) sides.push_back(2);
      if (!r.closedU && a == 0) sides.push_back(3);
      if (!r.closedU && a == r.patchesU - 1) sides.push_back(1);
      for (int s : sides) border.insert(t.side(a, b, s).begin(), t.side(a, b, s).end());
    }
  int open = 0;
  for (const auto& [e, n] : directed) {
    if (directed.count({e.second, e.first})) continue;
    ++open;
    EXPECT_TRUE(border.count(e.first) && border.count(e.second))
        << what << ": edge " << e.first << "-" << e.second << " has one triangle but is not on an open border";
  }
  if (r.closedU && r.closedV) {
    EXPECT_EQ(open, 0) << what;
  }
  // Every vertex is used.
  std::vector<char> used(t.vertexCount, 0);
  for (uint32_t i : t.indices) used[i] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << what << ": unreferenced vertices";
}

// Neighbouring patches list the same vertices on their shared side.
void expectSharedSides(const TessTopology& t, const std::string& what) {
  const TessRates& r = t.rates;
  for (int a = 0; a < r.patchesU; ++a)
    for (int b = 0; b < r.patchesV; ++b) {
      if (a + 1 < r.patchesU || r.closedU) {
        EXPECT_EQ(t.side(a, b, 1), t.side((a + 1) % r.patchesU, b, 3)) << what << " patch " << a << "," << b << " side u=1";
      }
      if (b + 1 < r.patchesV || r.closedV) {
        EXPECT_EQ(t.side(a, b, 2), t.side(a, (b + 1) % r.patchesV, 0)) << what << " patch " << a << "," << b << " side v=1";
      }
    }
}

TessRates mixedRates(int pu, int pv, bool cu, bool cv) {
  TessRates r;
  r.patchesU = pu;
  r.patchesV = pv;
  r.closedU = cu;
  r.closedV = cv;
  r.rateU.clear();
  r.rateV.clear();
  for (int a = 0; a < pu; ++a)
    for (int b = 0; b < pv; ++b) {
      r.rateU.push_back(1 + (a * 3 + b * 5) % 7);
      r.rateV.push_back(1 + (a * 2 + b * 3) % 5);
    }
  return r;
}

TEST(TessTopologyTest, WatertightForUniformPerPatchAndPerEdgeRates) {
  for (bool cu : {false, true})
    for (bool cv : {false, true}) {
      const std::string tag = std::string("closed ") + (cu ? "u" : "-") + (cv ? "v" : "-");
      for (int rate : {1, 2, 5}) {
        const TessTopology t = buildTessTopology(TessRates::uniform(3, 4, cu, cv, rate));
        expectWatertight(t, tag + " uniform " + std::to_string(rate));
        expectSharedSides(t, tag + " uniform");
      }
      const TessTopology m = buildTessTopology(mixedRates(4, 3, cu, cv));
      expectWatertight(m, tag + " mixed");
      expectSharedSides(m, tag + " mixed");
      // Caller-chosen edge rates (here: 1 + a deterministic pattern, independent of the patches).
      TessRates e = mixedRates(4, 3, cu, cv);
      e.edgeU.resize(size_t(4) * e.boundariesV());
      e.edgeV.resize(size_t(e.boundariesU()) * 3);
      for (size_t k = 0; k < e.edgeU.size(); ++k) e.edgeU[k] = 1 + int(k * 7 % 9);
      for (size_t k = 0; k < e.edgeV.size(); ++k) e.edgeV[k] = 1 + int(k * 5 % 6);
      const TessTopology te = buildTessTopology(e);
      expectWatertight(te, tag + " edge rates");
      expectSharedSides(te, tag + " edge rates");
      for (int a = 0; a < 4; ++a)
        EXPECT_EQ(int(te.side(a, 0, 0).size()), e.edgeU[size_t(a) * e.boundariesV()] + 1) << tag;
    }
}

TEST(TessTopologyTest, DefaultEdgeRateIsTheMaxOfTheNeighbours) {
  TessRates r = TessRates::uniform(2, 1, false, false, 3);
  r.rateV = {3, 8};
  const TessTopology t = buildTessTopology(r);
  EXPECT_EQ(t.side(0, 0, 1).size(), 9u);  // shared u-boundary: max(3, 8) segments
  EXPECT_EQ(t.side(0, 0, 3).size(), 4u);
  EXPECT_EQ(t.side(1, 0, 1).size(), 9u);
  // Uniform rate n on an open single patch: (n+1)^2 vertices, 2 n^2 triangles.
  const TessTopology u = buildTessTopology(TessRates::uniform(1, 1, false, false, 6));
  EXPECT_EQ(u.vertexCount, 49u);
  EXPECT_EQ(u.indices.size(), 3u * 72u);
  EXPECT_THROW(buildTessTopology(TessRates::uniform(2, 2, false, false, 0)), std::invalid_argument);
}

// ---- GPU -----------------------------------------------------------------------------------------

SurfaceModel testSurface() {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.family.lambda = 0.5;
  m.rows = 5;
  m.cols = 6;
  m.closedV = true;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) {
      const double t = j * 2.0 * M_PI / m.cols;
      const double r = 1.0 + 0.3 * std::sin(1.7 * i + j);
      m.points.push_back({r * std::cos(t), r * std::sin(t), 0.8 * i});
    }
  m.alpha.assign(size_t(m.rows) * m.cols, 0.6);
  m.alpha[size_t(2) * m.cols + 3] = 1.0;  // interior α = 1 vertex (4 patches)
  m.alpha[size_t(0) * m.cols + 1] = 1.0;  // on the open boundary (2 patches)
  m.alpha[size_t(4) * m.cols + 4] = 1.0;
  return m;
}

double scaleOf(const SurfaceModel& m) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : m.points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return glm::length(hi - lo);
}

std::vector<TessVertex> download(const vk::Buffer& b, uint32_t count, VkDeviceSize offset = 0) {
  std::vector<TessVertex> v(count);
  b.downloadSpan(std::span<TessVertex>(v), offset);
  return v;
}

class TessellatorTest : public VulkanTest {
 protected:
  Precision precision() { return Precision::Float; }

  // Max |GPU - CPU| over the canonical samples, in units of the net's scale.
  double positionError(const gpu::SurfaceTessellator& tess, const Surface& cpu, const std::vector<TessVertex>& v) {
    const TessTopology& t = tess.topology();
    const PatchRange r = cpu.patches();
    double worst = 0.0;
    for (uint32_t k = 0; k < t.vertexCount; ++k) {
      const TessSample& s = t.samples[k];
      const SurfacePoint e = cpu.evaluate(s.a + r.u.first, s.b + r.v.first, s.u, s.v);
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(e.point[c] - double(v[k].position[c])));
    }
    return worst / scaleOf(cpu.toModel());
  }
};

TEST_F(TessellatorTest, MatchesCpuIsWatertightAndHasLimitNormalsAtAlphaOne) {
  const SurfaceModel model = testSurface();
  const Surface cpu = Surface::create(model);
  gpu::GpuSurface surf(ctx_, cpu, precision());
  TessRates rates = mixedRates(int(cpu.patches().u.last - cpu.patches().u.first + 1),
                               int(cpu.patches().v.last - cpu.patches().v.first + 1), false, true);
  gpu::SurfaceTessellator tess(ctx_, surf, rates);
  expectWatertight(tess.topology(), "gpu mixed");
  vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd); });
  const auto v = download(tess.vertexBuffer(), tess.vertexCount());
  EXPECT_LE(positionError(tess, cpu, v), kFp32Rel * 20);

  // Finite, unit normals everywhere; uv finite.
  for (uint32_t k = 0; k < tess.vertexCount(); ++k) {
    const glm::dvec3 n(v[k].normal[0], v[k].normal[1], v[k].normal[2]);
    ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) && std::isfinite(v[k].uv[0]) &&
                std::isfinite(v[k].uv[1]))
        << "vertex " << k;
    ASSERT_NEAR(glm::length(n), 1.0, 1e-5) << "vertex " << k;
  }

  // Shared edges: both patches reference the same vertices, so their positions compare bitwise;
  // and the normals there agree with the CPU normal of either patch (C² surface).
  const TessTopology& t = tess.topology();
  int compared = 0;
  for (int a = 0; a < rates.patchesU; ++a)
    for (int b = 0; b < rates.patchesV; ++b) {
      if (a + 1 >= rates.patchesU) continue;
      const auto& mine = t.side(a, b, 1);
      const auto& theirs = t.side(a + 1, b, 3);
      ASSERT_EQ(mine.size(), theirs.size());
      for (size_t q = 0; q < mine.size(); ++q) {
        EXPECT_EQ(std::memcmp(v[mine[q]].position, v[theirs[q]].position, 12), 0)
            << "patch " << a << "," << b << " edge point " << q;
        ++compared;
      }
    }
  EXPECT_GT(compared, 20);

  // α = 1 vertices: mean of the core's per-patch diagonal limits over the patches sharing the vertex.
  const PatchRange r = cpu.patches();
  for (int vi = 0; vi < model.rows; ++vi)
    for (int vj = 0; vj < model.cols; ++vj) {
      if (model.alpha[size_t(vi) * model.cols + vj] != 1.0) continue;
      glm::dvec3 sum(0.0);
      int patches = 0;
      for (int di = 0; di <= 1; ++di)
        for (int dj = 0; dj <= 1; ++dj) {
          const int pi = vi - di, pj = (vj - dj + model.cols) % model.cols;
          if (pi < r.u.first || pi > r.u.last) continue;
          sum += cpu.limitNormal(pi, pj, di, dj);
          ++patches;
        }
      const glm::dvec3 expected = glm::normalize(sum);
      // The corner vertex of the patch grid: corner (vi, vj) is vertex vi * boundariesV + vj.
      const uint32_t k = uint32_t(vi * t.rates.boundariesV() + vj);
      const glm::dvec3 got(v[k].normal[0], v[k].normal[1], v[k].normal[2]);
      EXPECT_GT(glm::dot(got, expected), 1.0 - 1e-6)
          << "alpha = 1 vertex (" << vi << "," << vj << ") over " << patches << " patches: got (" << got.x << ","
          << got.y << "," << got.z << ") expected (" << expected.x << "," << expected.y << "," << expected.z << ")";
      if (patches == 1) continue;
      // Each patch's own limit normal is on the same side as the shared normal.
      for (int di = 0; di <= 1; ++di)
        for (int dj = 0; dj <= 1; ++dj) {
          const int pi = vi - di, pj = (vj - dj + model.cols) % model.cols;
          if (pi < r.u.first || pi > r.u.last) continue;
          EXPECT_GT(glm::dot(got, cpu.limitNormal(pi, pj, di, dj)), 0.0);
        }
    }
}

TEST_F(TessellatorTest, LambdaAlphaAndControlPointUpdatesShowAtTheNextRecord) {
  SurfaceModel model = testSurface();
  gpu::GpuSurface surf(ctx_, Surface::create(model), precision());
  gpu::SurfaceTessellator tess(ctx_, surf, gpu::SurfaceTessellator::uniformRates(surf, 6));
  const uint64_t netWrites = surf.uploadStats().netWrites;
  auto check = [&](const char* what) {
    vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd); });
    const auto v = download(tess.vertexBuffer(), tess.vertexCount());
    EXPECT_LE(positionError(tess, Surface::create(model), v), kFp32Rel * 20) << what;
  };
  check("initial");
  surf.setLambda(-2.0);
  model.family.lambda = -2.0;
  check("after setLambda(-2)");
  EXPECT_EQ(surf.uploadStats().netWrites, netWrites) << "a lambda change re-uploaded the net";
  surf.setAlpha(1, 2, 0.3);
  model.alpha[size_t(1) * model.cols + 2] = 0.3;
  check("after setAlpha");
  EXPECT_EQ(surf.uploadStats().netWrites, netWrites);
  surf.updateControlPoint(3, 4, {0.5, -1.5, 2.0});
  model.points[size_t(3) * model.cols + 4] = {0.5, -1.5, 2.0};
  check("after updateControlPoint");
}

TEST_F(TessellatorTest, WritesIntoCallerBuffersAndCopiesIndicesOncePerConfiguration) {
  const SurfaceModel model = testSurface();
  gpu::GpuSurface surf(ctx_, Surface::create(model), precision());
  gpu::SurfaceTessellator tess(ctx_, surf, gpu::SurfaceTessellator::uniformRates(surf, 4));
  const VkDeviceSize voff = std::max<VkDeviceSize>(256, ctx().limits().minStorageBufferOffsetAlignment);
  vk::Buffer vb = vk::Buffer::create(ctx(), voff + tess.vertexBytes(),
                                     gpu::kTessVertexBufferUsage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  vk::Buffer ib = vk::Buffer::create(ctx(), 64 + tess.indexBytes(),
                                     gpu::kTessIndexBufferUsage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  const gpu::TessTargets targets{vb.handle(), voff, ib.handle(), 64};
  vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd, targets); });
  std::vector<uint32_t> idx(tess.indexCount());
  ib.downloadSpan(std::span<uint32_t>(idx), 64);
  EXPECT_EQ(idx, tess.topology().indices);
  const auto own = [&] {
    vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd); });
    return download(tess.vertexBuffer(), tess.vertexCount());
  }();
  const auto got = download(vb, tess.vertexCount(), voff);
  EXPECT_EQ(std::memcmp(own.data(), got.data(), got.size() * sizeof(TessVertex)), 0);
  // Overwrite the caller's indices: a second record() of the same configuration does not copy again.
  std::vector<uint32_t> zeros(tess.indexCount(), 0u);
  ib.uploadSpan(std::span<const uint32_t>(zeros), 64);
  vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd, targets); });
  ib.downloadSpan(std::span<uint32_t>(idx), 64);
  EXPECT_EQ(idx, zeros);
  // A new configuration copies again.
  tess.setRates(gpu::SurfaceTessellator::uniformRates(surf, 3));
  vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd, targets); });
  idx.resize(tess.indexCount());
  ib.downloadSpan(std::span<uint32_t>(idx), 64);
  EXPECT_EQ(idx, tess.topology().indices);
}

// Every uniform construction tessellates (plain tensor surfaces share the α-EB path's topology).
TEST_F(TessellatorTest, PlainFamiliesMatchCpu) {
  SurfaceModel m = testSurface();
  m.family.construction = Construction::ExtendedBSpline;
  m.alpha.clear();
  const Surface cpu = Surface::create(m);
  gpu::GpuSurface surf(ctx_, cpu, precision());
  gpu::SurfaceTessellator tess(ctx_, surf, gpu::SurfaceTessellator::uniformRates(surf, 5));
  vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd); });
  EXPECT_LE(positionError(tess, cpu, download(tess.vertexBuffer(), tess.vertexCount())), kFp32Rel * 20);
}

// Interior vertices (one patch each, no normal averaging) against the CPU §5.3 normal of their
// canonical sample. Regular normals: fp32 within 2e-3 where the derivatives are not nearly
// parallel (the cross of two fp32 derivatives of relative error ~kFp32Rel, over sin of their
// angle); fallback normals (shifted / base / fixed axis): fp32 5e-3 (a shifted evaluation δ = 2^-12
// from a pole has derivatives of order δ, a few hundred ulps of the net), fp64 1e-6 in both cases
// (the vertices themselves are fp32). Returns how many fallback normals were compared.
int expectInteriorNormals(const gpu::SurfaceTessellator& tess, const Surface& cpu, const std::vector<TessVertex>& v,
                          Precision pr) {
  const TessTopology& t = tess.topology();
  const TessPatches patches(cpu);
  const bool fp64 = pr == Precision::Double;
  double worstRegular = 0.0, worstFallback = 0.0;
  int fallbacks = 0;
  for (uint32_t k = t.cornerCount + t.edgeVertexCount; k < t.vertexCount; ++k) {
    const TessSample& s = t.samples[k];
    const SurfacePoint e = patches.evaluate(cpu, s);
    const glm::dvec3 got(v[k].normal[0], v[k].normal[1], v[k].normal[2]);
    const double err = glm::length(got - e.normal);
    if (e.normalRule == NormalRule::Regular) {
      const double sinA = glm::length(glm::cross(e.du, e.dv)) / (glm::length(e.du) * glm::length(e.dv));
      if (sinA < 0.05) continue;
      worstRegular = std::max(worstRegular, err);
      EXPECT_LE(err, fp64 ? 1e-6 : 2e-3) << "vertex " << k << " patch " << s.a << "," << s.b << " uv " << s.u << ","
                                         << s.v;
    } else {
      ++fallbacks;
      worstFallback = std::max(worstFallback, err);
      EXPECT_LE(err, fp64 ? 1e-6 : 5e-3) << "fallback vertex " << k << " patch " << s.a << "," << s.b << " uv "
                                         << s.u << "," << s.v;
    }
  }
  std::printf("  interior normals (%s): max error regular %.3g, fallback %.3g over %d vertices\n",
              fp64 ? "fp64" : "fp32", worstRegular, worstFallback, fallbacks);
  return fallbacks;
}

void expectUnitNormals(const std::vector<TessVertex>& v) {
  for (size_t k = 0; k < v.size(); ++k) {
    const glm::dvec3 n(v[k].normal[0], v[k].normal[1], v[k].normal[2]);
    ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)) << "vertex " << k;
    ASSERT_NEAR(glm::length(n), 1.0, 1e-5) << "vertex " << k;
  }
}

// (precision, packed stores): the packed-store variants (uint64 pairs, where the device has
// shaderInt64) and the plain vec4 stores every other device runs.
struct TessConfig {
  Precision precision;
  bool packedStores;
};

class TessellatorPrecisionTest : public VulkanTest, public ::testing::WithParamInterface<TessConfig> {
 protected:
  gpu::TessellatorOptions options() const {
    gpu::TessellatorOptions o;
    o.packedStores = GetParam().packedStores;
    return o;
  }
};

// Uniform rates take the grid pass's uniform mode, mixed rates its per-patch records and the list
// pass; both agree with the CPU in positions and interior normals, in fp32 and fp64.
TEST_P(TessellatorPrecisionTest, UniformAndMixedRatesMatchCpu) {
  const Precision pr = GetParam().precision;
  if (pr == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  const Surface cpu = Surface::create(testSurface());
  gpu::GpuSurface surf(ctx_, cpu, pr);
  const double posTol = pr == Precision::Double ? kFp32Rel : kFp32Rel * 20;  // fp32 vertices either way
  for (bool mixed : {false, true}) {
    SCOPED_TRACE(mixed ? "mixed rates" : "uniform rates");
    const TessRates rates = mixed ? mixedRates(int(surf.patchesU()), int(surf.patchesV()), false, true)
                                  : gpu::SurfaceTessellator::uniformRates(surf, 7);
    gpu::SurfaceTessellator tess(ctx_, surf, rates, options());
    vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd); });
    const auto v = download(tess.vertexBuffer(), tess.vertexCount());
    const TessTopology& t = tess.topology();
    double worst = 0.0;
    for (uint32_t k = 0; k < t.vertexCount; ++k) {
      const TessSample& s = t.samples[k];
      const SurfacePoint e = cpu.evaluate(s.a + cpu.patches().u.first, s.b + cpu.patches().v.first, s.u, s.v);
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(e.point[c] - double(v[k].position[c])));
      EXPECT_EQ(v[k].uv[0], float(s.a + cpu.patches().u.first) + float(s.u)) << "vertex " << k;
    }
    EXPECT_LE(worst / scaleOf(cpu.toModel()), posTol);
    expectUnitNormals(v);
    expectInteriorNormals(tess, cpu, v, pr);
  }
}

// collapsedRowsNet (a point patch row and a pole row): whole grid rows need the fallback normal,
// which the grid pass then redoes for every sample of the row.
TEST_P(TessellatorPrecisionTest, DegenerateRowsTakeTheFallbackNormals) {
  const Precision pr = GetParam().precision;
  if (pr == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  const Surface cpu = Surface::create(collapsedRowsNet());
  gpu::GpuSurface surf(ctx_, cpu, pr);
  gpu::SurfaceTessellator tess(ctx_, surf, gpu::SurfaceTessellator::uniformRates(surf, 6), options());
  vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd); });
  const auto v = download(tess.vertexBuffer(), tess.vertexCount());
  expectUnitNormals(v);
  EXPECT_GT(expectInteriorNormals(tess, cpu, v, pr), 20);
}

// A bicubic on non-uniform knots, unclamped in v, with a double interior knot in each direction
// (empty intervals, which have no tessellation patch).
SurfaceModel nonUniformKnotSurface() {
  FamilySpec f;
  f.construction = Construction::BSpline;
  f.order = 4;
  SurfaceModel m = wavyNet(f, 7, false);
  m.knotsU = {0, 0, 0, 0, 0.2, 0.5, 0.5, 1, 1, 1, 1};
  m.knotsV = {0, 0.1, 0.3, 0.35, 0.6, 0.6, 0.9, 1.2, 1.3, 1.5, 1.6};
  return m;
}

// Knot-vector surfaces (the grid pass on knot patches) and a rational one (the NURBS torus, whose
// double knots leave empty intervals too; its weights a fourth channel of the grid pass): positions,
// uv (the knot parameters) and interior normals against the CPU, every vertex of the torus on the torus.
TEST_P(TessellatorPrecisionTest, KnotVectorAndRationalSurfacesMatchCpu) {
  const Precision pr = GetParam().precision;
  if (pr == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  constexpr double R = 2.0, r = 0.5;
  for (bool torus : {false, true}) {
    SCOPED_TRACE(torus ? "NURBS torus" : "non-uniform knots");
    const Surface cpu = Surface::create(torus ? nurbsTorus(R, r) : nonUniformKnotSurface());
    const TessPatches patches(cpu);
    gpu::GpuSurface surf(ctx_, cpu, pr);
    ASSERT_EQ(surf.gridItemsU(), patches.u.size());
    ASSERT_EQ(surf.gridItemsU(), torus ? 4u : 3u);
    ASSERT_EQ(surf.gridItemsV(), torus ? 4u : 3u);
    ASSERT_LT(surf.gridItemsV(), surf.patchesV());  // the knot range has empty intervals
    const double posTol = pr == Precision::Double ? kFp32Rel : kFp32Rel * 20;  // fp32 vertices either way
    const auto [ulo, uhi] = cpu.parameterRangeU();
    const auto [vlo, vhi] = cpu.parameterRangeV();
    const double uvTol = 2 * double(std::numeric_limits<float>::epsilon()) *
                         std::max({std::abs(ulo), std::abs(uhi), std::abs(vlo), std::abs(vhi)});
    for (bool mixed : {false, true}) {
      SCOPED_TRACE(mixed ? "mixed rates" : "uniform rates");
      const TessRates rates = mixed ? mixedRates(int(surf.gridItemsU()), int(surf.gridItemsV()), false, false)
                                    : gpu::SurfaceTessellator::uniformRates(surf, 7);
      gpu::SurfaceTessellator tess(ctx_, surf, rates, options());
      vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd); });
      const auto v = download(tess.vertexBuffer(), tess.vertexCount());
      const TessTopology& t = tess.topology();
      double worst = 0.0, worstTorus = 0.0;
      for (uint32_t k = 0; k < t.vertexCount; ++k) {
        const TessSample& s = t.samples[k];
        const SurfacePoint e = patches.evaluate(cpu, s);
        const glm::dvec3 got(v[k].position[0], v[k].position[1], v[k].position[2]);
        worst = std::max(worst, glm::length(e.point - got));
        // The grid pass forms t_i + u h_i in the evaluation precision: fp32 within 2 ulps of the
        // parameter range's size (1 in t_i, 1 in u h_i), not always the rounded fp64 value.
        const auto [U, V] = cpu.parameterOf(patches.u[s.a], patches.v[s.b], s.u, s.v);
        EXPECT_LE(std::abs(double(v[k].uv[0]) - U), uvTol) << "vertex " << k;
        EXPECT_LE(std::abs(double(v[k].uv[1]) - V), uvTol) << "vertex " << k;
        if (torus) worstTorus = std::max(worstTorus, std::abs(std::hypot(std::hypot(got.x, got.y) - R, got.z) - r));
      }
      EXPECT_LE(worst / scaleOf(cpu.toModel()), posTol);
      // The fp32 bound (fp32 vertices either way): 1e-6 of the torus's size.
      if (torus) {
        EXPECT_LE(worstTorus / (R + r), 1e-6);
      }
      expectUnitNormals(v);
      expectInteriorNormals(tess, cpu, v, pr);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Precisions, TessellatorPrecisionTest,
                         ::testing::Values(TessConfig{Precision::Float, true}, TessConfig{Precision::Float, false},
                                           TessConfig{Precision::Double, true}),
                         [](const auto& info) {
                           return std::string(info.param.precision == Precision::Double ? "fp64" : "fp32") +
                                  (info.param.packedStores ? "_packed" : "_plain");
                         });

}  // namespace
}  // namespace shapespline::test
