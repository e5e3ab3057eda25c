// gpu::AdaptiveTessellator: for random cameras the GPU-made mesh is exactly buildTessTopology of the
// rates it chose (so crack-free: one vertex per shared point, no T-junction), its vertices are the
// CPU surface's, its screen-space distance to the exact surface stays below the tolerance, the
// hysteresis and culling rules hold, and bad options are refused by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <random>
#include <string>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/common.hpp>

#include <shapespline/core/surface.h>
#include <shapespline/core/tess_patches.h>
#include <shapespline/core/tess_topology.h>
#include <shapespline/gpu/adaptive_tessellator.h>
#include "support/test_models.h"
#include "support/tolerances.h"
#include "support/vk_fixture.h"
#include <shapespline/vk/pipeline_table.h>
#include <shapespline/vk/submit.h>

namespace shapespline::test {
namespace {

using gpu::tess_layout::TessVertex;

constexpr int kWidth = 640, kHeight = 400;

// A wavy α-EB sheet (open), curvature varying across it.
SurfaceModel waveSheet() {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.family.lambda = 0.25;
  m.rows = 9;
  m.cols = 11;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j)
      m.points.push_back({double(i), double(j), 1.2 * std::sin(0.9 * i) * std::cos(0.6 * j) + 0.05 * i * j});
  m.alpha.assign(size_t(m.rows) * m.cols, 0.6);
  for (size_t k = 0; k < m.alpha.size(); k += 5) m.alpha[k] = 1.0;
  return m;
}

// A torus (closed in u and v), α-EB.
SurfaceModel torus() {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 4;
  m.family.lambda = 0.5;
  m.rows = 6;
  m.cols = 8;
  m.closedU = m.closedV = true;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) {
      const double a = 2 * M_PI * i / m.rows, b = 2 * M_PI * j / m.cols;
      const double r = 3.0 + 1.2 * std::cos(b);
      m.points.push_back({r * std::cos(a), r * std::sin(a), 1.2 * std::sin(b)});
    }
  m.alpha.assign(size_t(m.rows) * m.cols, 0.7);
  m.alpha[9] = 1.0;
  return m;
}

// The wave's net as a cubic B-spline on non-uniform knots, clamped in u, unclamped in v, a double
// knot in each direction (empty intervals, which get no patch): its patches are the non-empty knot
// interval pairs (core/tess_patches.h).
SurfaceModel knotSheet() {
  SurfaceModel m = waveSheet();
  m.family = FamilySpec{};
  m.family.construction = Construction::BSpline;
  m.family.order = 4;
  m.orderV = 4;
  m.alpha.clear();
  m.knotsU = {0, 0, 0, 0, 0.1, 0.3, 0.3, 0.5, 0.8, 1, 1, 1, 1};
  m.knotsV = {0, 0.5, 0.7, 1, 1.6, 2, 2, 2.5, 3.5, 4, 4.2, 4.5, 5, 5.5, 6};
  return m;
}

// A plain family, closed in v (a tube).
SurfaceModel tube() {
  SurfaceModel m;
  m.family.construction = Construction::ExtendedBSpline;
  m.family.degree = 5;
  m.family.lambda = -0.5;
  m.rows = 6;
  m.cols = 7;
  m.closedV = true;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) {
      const double t = 2 * M_PI * j / m.cols, r = 1.0 + 0.3 * std::sin(1.7 * i + j);
      m.points.push_back({r * std::cos(t), r * std::sin(t), 0.8 * i});
    }
  return m;
}

struct Box {
  glm::dvec3 lo{1e300}, hi{-1e300};
  glm::dvec3 centre() const { return 0.5 * (lo + hi); }
  double diagonal() const { return glm::length(hi - lo); }
};

Box boxOf(const SurfaceModel& m) {
  Box b;
  for (const auto& p : m.points) {
    b.lo = glm::min(b.lo, p);
    b.hi = glm::max(b.hi, p);
  }
  return b;
}

// A perspective camera (Vulkan clip: y down, depth 0..1) at `eye` looking at `target`.
glm::dmat4 viewProj(const glm::dvec3& eye, const glm::dvec3& target, double zNear, double zFar) {
  glm::dmat4 proj = glm::perspectiveRH_ZO(glm::radians(40.0), double(kWidth) / kHeight, zNear, zFar);
  proj[1][1] *= -1.0;
  return proj * glm::lookAtRH(eye, target, glm::dvec3(0, 0, 1));
}

gpu::AdaptiveView adaptiveView(const glm::dmat4& vp) {
  gpu::AdaptiveView v;
  const glm::mat4 f(vp);
  std::memcpy(v.viewProj.data(), &f[0][0], sizeof(float) * 16);
  v.viewportWidth = float(kWidth);
  v.viewportHeight = float(kHeight);
  return v;
}

// Random cameras around the model: some far (the whole model small), some close (inside the box,
// with patches crossing the near plane and outside the frustum).
std::vector<glm::dmat4> randomCameras(const SurfaceModel& m, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Box box = boxOf(m);
  const double R = 0.5 * box.diagonal();
  std::vector<glm::dmat4> out;
  for (int k = 0; k < count; ++k) {
    const double az = 2 * M_PI * unit(rng), el = glm::radians(10.0 + 70.0 * unit(rng));
    const double dist = R * (0.6 + 2.5 * unit(rng));
    const glm::dvec3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const glm::dvec3 target = box.centre() + 0.4 * R * glm::dvec3(unit(rng) - 0.5, unit(rng) - 0.5, 0.0);
    out.push_back(viewProj(target + dist * dir, target, 0.05 * R, dist + 3 * R));
  }
  return out;
}

// Pixel position (x right, y down) and clip w of a model-space point.
glm::dvec3 toPixel(const glm::dmat4& vp, const glm::dvec3& p) {
  const glm::dvec4 c = vp * glm::dvec4(p, 1.0);
  return {(c.x / c.w * 0.5 + 0.5) * kWidth, (c.y / c.w * 0.5 + 0.5) * kHeight, c.w};
}

class AdaptiveTessellatorTest : public VulkanTest {
 protected:
  gpu::AdaptiveTessellator::Mesh run(gpu::AdaptiveTessellator& tess, const glm::dmat4& vp) {
    vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { tess.record(cmd, adaptiveView(vp)); });
    return tess.mesh();
  }
  void expectTopologySweep(const std::string& name, const SurfaceModel& model, const Surface& cpu,
                           gpu::GpuSurface& surf);
  void expectScreenErrorSweep(const std::string& name, const SurfaceModel& model, const Surface& cpu,
                              gpu::GpuSurface& surf);
};

// The frame's mesh is buildTessTopology of its rates: same numbering, same triangles; every
// interior edge is shared by exactly two triangles in opposite directions (no crack, no
// T-junction) and the shared sides of neighbouring patches are the same vertices.
void expectTopologyOfRates(const gpu::AdaptiveTessellator::Mesh& mesh, const TessTopology& topo,
                           const std::string& what) {
  ASSERT_EQ(mesh.vertices.size(), topo.vertexCount) << what;
  ASSERT_EQ(mesh.indices.size(), topo.indices.size()) << what;
  ASSERT_TRUE(mesh.indices == topo.indices) << what << ": the GPU triangles differ from the CPU topology";
  std::unordered_map<uint64_t, int> directed;
  directed.reserve(mesh.indices.size());
  auto key = [](uint32_t from, uint32_t to) { return (uint64_t(from) << 32) | to; };
  for (size_t k = 0; k < mesh.indices.size(); k += 3)
    for (int e = 0; e < 3; ++e) ++directed[key(mesh.indices[k + e], mesh.indices[k + (e + 1) % 3])];
  size_t open = 0;
  for (const auto& [edge, count] : directed) {
    ASSERT_EQ(count, 1) << what << ": directed edge used twice";
    if (!directed.count(key(uint32_t(edge), uint32_t(edge >> 32)))) ++open;
  }
  // Open edges only on open borders: their count is the border's segment count.
  const TessRates& r = topo.rates;
  size_t border = 0;
  if (!r.closedV)
    for (int a = 0; a < r.patchesU; ++a) border += size_t(r.edgeU[size_t(a) * r.boundariesV()]) + r.edgeU[size_t(a) * r.boundariesV() + r.patchesV];
  if (!r.closedU)
    for (int b = 0; b < r.patchesV; ++b) border += size_t(r.edgeV[b]) + r.edgeV[size_t(r.patchesU) * r.patchesV + b];
  EXPECT_EQ(open, border) << what << ": open edges that are not on the border (a crack or T-junction)";
  // Both patches of an edge list the same vertices along it.
  for (int a = 0; a < r.patchesU; ++a)
    for (int b = 0; b < r.patchesV; ++b) {
      if (a + 1 < r.patchesU || r.closedU) {
        EXPECT_EQ(topo.side(a, b, 1), topo.side((a + 1) % r.patchesU, b, 3)) << what;
      }
      if (b + 1 < r.patchesV || r.closedV) {
        EXPECT_EQ(topo.side(a, b, 2), topo.side(a, (b + 1) % r.patchesV, 0)) << what;
      }
    }
}

// Max |GPU - CPU| of the vertex positions (units of the net's box) and the worst |normal| - 1.
void expectVerticesOfSurface(const gpu::AdaptiveTessellator::Mesh& mesh, const TessTopology& topo, const Surface& cpu,
                             const std::string& what) {
  const TessPatches patches(cpu);
  const double scale = boxOf(cpu.toModel()).diagonal();
  double worst = 0.0, worstNormal = 0.0;
  for (uint32_t k = 0; k < topo.vertexCount; ++k) {
    const TessSample& s = topo.samples[k];
    const SurfacePoint e = patches.evaluate(cpu, s);
    const TessVertex& v = mesh.vertices[k];
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(e.point[c] - double(v.position[c])));
    const glm::dvec3 n(v.normal[0], v.normal[1], v.normal[2]);
    ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)) << what << " vertex " << k;
    worstNormal = std::max(worstNormal, std::abs(glm::length(n) - 1.0));
    EXPECT_FLOAT_EQ(v.uv[0], patches.uv(cpu, s)[0]) << what << " vertex " << k;
    EXPECT_FLOAT_EQ(v.uv[1], patches.uv(cpu, s)[1]) << what << " vertex " << k;
  }
  EXPECT_LE(worst / scale, kFp32Rel * 20) << what;
  EXPECT_LE(worstNormal, 1e-5) << what;
  // Normals of edge points and interior points against the CPU's §5.3 normal of the canonical
  // sample, where that is the regular rule and the partials are not nearly parallel (on these C¹
  // surfaces the mean over the patches of an edge is the same normal): fp32 within 2e-3, as the
  // fixed-rate tessellator's tests. Corners are left out (α = 1 vertices take a mean of limits).
  double worstDir = 0.0;
  int compared = 0;
  for (uint32_t k = topo.cornerCount; k < topo.vertexCount; ++k) {
    const TessSample& s = topo.samples[k];
    const SurfacePoint e = patches.evaluate(cpu, s);
    if (e.normalRule != NormalRule::Regular) continue;
    if (glm::length(glm::cross(e.du, e.dv)) < 0.05 * glm::length(e.du) * glm::length(e.dv)) continue;
    const TessVertex& v = mesh.vertices[k];
    worstDir = std::max(worstDir, glm::length(glm::dvec3(v.normal[0], v.normal[1], v.normal[2]) - e.normal));
    ++compared;
  }
  EXPECT_LE(worstDir, 2e-3) << what;
  EXPECT_GT(compared, int(topo.edgeVertexCount) / 2) << what;
}

// For random cameras the mesh is the topology of its rates with the surface's vertices, and its
// rates are not all one (the test would show nothing adaptive).
void AdaptiveTessellatorTest::expectTopologySweep(const std::string& name, const SurfaceModel& model, const Surface& cpu,
                                                  gpu::GpuSurface& surf) {
  gpu::AdaptiveOptions opt;
  opt.maxRate = 24;
  gpu::AdaptiveTessellator tess(ctx_, surf, opt);
  int k = 0;
  bool sawMixed = false;
  for (const glm::dmat4& vp : randomCameras(model, 4, 17)) {
    const std::string what = name + " camera " + std::to_string(k++);
    const auto mesh = run(tess, vp);
    const auto [lo, hi] = std::minmax_element(mesh.rates.rateU.begin(), mesh.rates.rateU.end());
    sawMixed = sawMixed || *lo != *hi;
    const TessTopology topo = buildTessTopology(mesh.rates);
    expectTopologyOfRates(mesh, topo, what);
    expectVerticesOfSurface(mesh, topo, cpu, what);
    const gpu::AdaptiveStats st = tess.stats();
    EXPECT_EQ(st.vertexCount, mesh.vertices.size()) << what;
    EXPECT_EQ(st.indexCount, mesh.indices.size()) << what;
  }
  EXPECT_TRUE(sawMixed) << name << ": every camera gave every patch one rate; the test shows nothing adaptive";
}

// The screen-space distance between the surface point of parameter x and the point of the mesh
// triangle with the same barycentric coordinates, sampled inside every triangle, for the samples
// that land in the viewport, in front of the camera, on patches whose rate was not clamped.
struct ErrorReport {
  double worst = 0.0;
  size_t samples = 0;
};

ErrorReport screenError(const gpu::AdaptiveTessellator::Mesh& mesh, const Surface& cpu, const glm::dmat4& vp,
                        double maxRate) {
  const TessTopology topo = buildTessTopology(mesh.rates);
  const TessRates& r = topo.rates;
  const TessPatches patches(cpu);
  static const double kBary[][3] = {{1 / 3.0, 1 / 3.0, 1 / 3.0}, {0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5},
                                    {0.6, 0.2, 0.2},             {0.2, 0.6, 0.2}, {0.2, 0.2, 0.6}};
  ErrorReport rep;
  for (int a = 0; a < r.patchesU; ++a)
    for (int b = 0; b < r.patchesV; ++b) {
      const size_t p = size_t(a) * r.patchesV + b;
      if (r.patchRateU(a, b) >= maxRate || r.patchRateV(a, b) >= maxRate) continue;  // clamped or near
      for (uint32_t t = topo.firstIndex[p]; t < topo.firstIndex[p] + topo.indexCount[p]; t += 3) {
        glm::dvec2 local[3];
        glm::dvec3 pix[3];
        for (int c = 0; c < 3; ++c) {
          const uint32_t k = topo.indices[t + c];
          const TessSample& s = topo.samples[k];
          // The vertex's canonical sample in this patch's local coordinates (wrapping seams).
          double u = s.a - a + s.u, v = s.b - b + s.v;
          if (r.closedU && u > 1.5) u -= r.patchesU;
          if (r.closedU && u < -0.5) u += r.patchesU;
          if (r.closedV && v > 1.5) v -= r.patchesV;
          if (r.closedV && v < -0.5) v += r.patchesV;
          local[c] = {u, v};
          const TessVertex& x = mesh.vertices[k];
          pix[c] = toPixel(vp, {x.position[0], x.position[1], x.position[2]});
        }
        for (const auto& w : kBary) {
          const glm::dvec2 uv = w[0] * local[0] + w[1] * local[1] + w[2] * local[2];
          const glm::dvec3 exact = toPixel(vp, cpu.evaluate(patches.u[a], patches.v[b], uv.x, uv.y).point);
          if (exact.z <= 0 || exact.x < 0 || exact.x > kWidth || exact.y < 0 || exact.y > kHeight) continue;
          const glm::dvec3 mesh3 = w[0] * pix[0] + w[1] * pix[1] + w[2] * pix[2];
          rep.worst = std::max(rep.worst, glm::length(glm::dvec2(exact) - glm::dvec2(mesh3)));
          ++rep.samples;
        }
      }
    }
  return rep;
}

// For random cameras and three tolerances, the screen-space error stays below the tolerance.
void AdaptiveTessellatorTest::expectScreenErrorSweep(const std::string& name, const SurfaceModel& model,
                                                     const Surface& cpu, gpu::GpuSurface& surf) {
  for (const float tol : {0.5f, 1.0f, 3.0f}) {
    gpu::AdaptiveOptions opt;
    opt.tolerancePx = tol;
    opt.maxRate = 48;
    opt.hysteresis = 0.0f;
    gpu::AdaptiveTessellator tess(ctx_, surf, opt);
    int k = 0;
    for (const glm::dmat4& vp : randomCameras(model, 5, 101 + unsigned(tol * 10))) {
      const auto mesh = run(tess, vp);
      const ErrorReport rep = screenError(mesh, cpu, vp, opt.maxRate);
      const std::string what = name + " tol " + std::to_string(tol) + " camera " + std::to_string(k++);
      EXPECT_LE(rep.worst, tol) << what << " over " << rep.samples << " samples";
      EXPECT_GT(rep.samples, 1000u) << what;
    }
  }
}

// Both sweeps in one test, so that they share each model's pipelines, which a process builds once
// (lavapipe with the validation layer, under the sanitizers: the sweeps took 43 s and 53 s as two
// tests in two processes, 50 s in one). The tube, a plain family, now takes the error sweep too.
TEST_F(AdaptiveTessellatorTest, MeshIsTheTopologyOfItsRatesOnTheSurfaceWithinTheTolerance) {
  const std::pair<const char*, SurfaceModel> models[] = {
      {"wave", waveSheet()}, {"torus", torus()}, {"tube", tube()}, {"knot sheet", knotSheet()},
      {"nurbs torus", nurbsTorus(2.0, 0.5)}};
  for (const auto& [name, model] : models) {
    const Surface cpu = Surface::create(model);
    gpu::GpuSurface surf(ctx_, cpu, Precision::Float);
    expectTopologySweep(name, model, cpu, surf);
    expectScreenErrorSweep(name, model, cpu, surf);
  }
}

// Hysteresis: rates rise at once to what the bound needs and fall only when the need drops below
// rate / (1 + h); with h = 0 they follow the need exactly.
TEST_F(AdaptiveTessellatorTest, HysteresisRaisesAtOnceAndLowersLate) {
  const SurfaceModel model = waveSheet();
  const Surface cpu = Surface::create(model);
  gpu::GpuSurface surf(ctx_, cpu, Precision::Float);
  const Box box = boxOf(model);
  const glm::dvec3 c = box.centre(), dir = glm::normalize(glm::dvec3(1, 0.7, 0.9));
  const double R = 0.5 * box.diagonal();
  auto at = [&](double dist) { return viewProj(c + dist * R * dir, c, 0.05 * R, (dist + 3) * R); };
  gpu::AdaptiveOptions exact;
  exact.hysteresis = 0.0f;
  gpu::AdaptiveTessellator follow(ctx_, surf, exact);
  gpu::AdaptiveOptions lagging = exact;
  lagging.hysteresis = 0.25f;
  gpu::AdaptiveTessellator lag(ctx_, surf, lagging);
  auto sum = [](const TessRates& r) {
    long s = 0;
    for (size_t p = 0; p < r.rateU.size(); ++p) s += r.rateU[p] + r.rateV[p];
    return s;
  };
  const auto nearRates = run(lag, at(1.6)).rates;
  EXPECT_EQ(nearRates.rateU, run(follow, at(1.6)).rates.rateU) << "the first frame has no history";
  // A little farther: the exact rates drop, the lagging ones stay between the need and before.
  const auto fartherNeed = run(follow, at(1.75)).rates;
  const auto fartherLag = run(lag, at(1.75)).rates;
  int held = 0;
  for (size_t p = 0; p < nearRates.rateU.size(); ++p) {
    EXPECT_GE(fartherLag.rateU[p], fartherNeed.rateU[p]);
    EXPECT_LE(fartherLag.rateU[p], nearRates.rateU[p]);
    EXPECT_LE(fartherLag.rateU[p], int(std::ceil(1.25 * fartherNeed.rateU[p])) + 1);
    held += fartherLag.rateU[p] > fartherNeed.rateU[p];
  }
  EXPECT_GT(held, 0) << "hysteresis held no rate";
  EXPECT_LT(sum(fartherNeed), sum(nearRates));
  // Closer again: both at least the need at once.
  const auto closerNeed = run(follow, at(1.2)).rates;
  const auto closerLag = run(lag, at(1.2)).rates;
  for (size_t p = 0; p < closerNeed.rateU.size(); ++p) {
    EXPECT_GE(closerLag.rateU[p], closerNeed.rateU[p]);
    EXPECT_GE(closerLag.rateV[p], closerNeed.rateV[p]);
  }
  // resetRates forgets the history.
  lag.resetRates();
  EXPECT_EQ(run(lag, at(1.75)).rates.rateU, fartherNeed.rateU);
}

// Looking at one corner from close by: patches entirely outside the frustum take rate 2 and are
// counted; every patch with a visible CPU sample is not culled.
TEST_F(AdaptiveTessellatorTest, CullsOnlyPatchesOutsideTheFrustum) {
  const SurfaceModel model = waveSheet();
  const Surface cpu = Surface::create(model);
  gpu::GpuSurface surf(ctx_, cpu, Precision::Float);
  gpu::AdaptiveTessellator tess(ctx_, surf, {});
  const glm::dmat4 vp = viewProj({-1.5, -1.5, 3.0}, {1.0, 1.0, 0.0}, 0.1, 40.0);
  const auto mesh = run(tess, vp);
  const gpu::AdaptiveStats st = tess.stats();
  EXPECT_GT(st.culledPatches, 0u);
  const PatchRange pr = cpu.patches();
  const TessRates& r = mesh.rates;
  uint32_t invisible = 0;
  for (int a = 0; a < r.patchesU; ++a)
    for (int b = 0; b < r.patchesV; ++b) {
      bool visible = false;
      for (int i = 0; i <= 16 && !visible; ++i)
        for (int j = 0; j <= 16 && !visible; ++j) {
          const glm::dvec4 c = vp * glm::dvec4(cpu.evaluate(a + pr.u.first, b + pr.v.first, i / 16.0, j / 16.0).point, 1.0);
          visible = c.w > 0 && std::abs(c.x) <= c.w && std::abs(c.y) <= c.w && c.z >= 0 && c.z <= c.w;
        }
      invisible += !visible;
      if (visible) {
        EXPECT_GT(r.patchRateU(a, b) + r.patchRateV(a, b), 4) << "visible patch " << a << "," << b << " culled";
      }
    }
  EXPECT_LE(st.culledPatches, invisible);
}

// fp64 evaluation (vertices are fp32 either way): the same topology rule and vertices.
TEST_F(AdaptiveTessellatorTest, Fp64SurfacesGiveTheSameMeshRules) {
  if (!ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  const SurfaceModel model = waveSheet();
  const Surface cpu = Surface::create(model);
  gpu::GpuSurface surf(ctx_, cpu, Precision::Double);
  gpu::AdaptiveOptions opt;
  opt.maxRate = 24;
  gpu::AdaptiveTessellator tess(ctx_, surf, opt);
  int k = 0;
  for (const glm::dmat4& vp : randomCameras(model, 2, 5)) {
    const auto mesh = run(tess, vp);
    const TessTopology topo = buildTessTopology(mesh.rates);
    expectTopologyOfRates(mesh, topo, "fp64 camera " + std::to_string(k));
    expectVerticesOfSurface(mesh, topo, cpu, "fp64 camera " + std::to_string(k++));
  }
}

// The first tessellator compiles its pipelines into the context's table; a second one of the same
// surface, with other options, compiles none and makes the mesh a first one with its options makes.
// (A context of its own, so that the table starts empty whatever ran before in this process.)
TEST_F(AdaptiveTessellatorTest, ASecondTessellatorReusesTheContextsPipelines) {
  vk::ContextOptions options;
  options.validation = true;
  options.persistentPipelineCache = false;
  const std::shared_ptr<vk::Context> own = vk::Context::create(options);
  ASSERT_EQ(own->pipelines().size(), 0u);
  const Surface cpu = Surface::create(waveSheet());
  gpu::GpuSurface surf(own, cpu, Precision::Float);
  const glm::dmat4 vp = randomCameras(waveSheet(), 1, 5).front();
  auto frame = [&](gpu::AdaptiveTessellator& tess) {
    vk::runOneShot(*own, [&](VkCommandBuffer cmd) { tess.record(cmd, adaptiveView(vp)); });
    return tess.mesh();
  };
  gpu::AdaptiveOptions coarse;
  coarse.tolerancePx = 3.0f;
  gpu::AdaptiveOptions fine;
  fine.tolerancePx = 0.5f;
  gpu::AdaptiveTessellator first(own, surf, coarse);
  const auto coarseMesh = frame(first);
  const size_t compiled = own->pipelines().size();
  EXPECT_GT(compiled, 0u) << "the tessellator's pipelines are not the context's";
  gpu::AdaptiveTessellator second(own, surf, fine);
  const auto fineMesh = frame(second);
  EXPECT_EQ(own->pipelines().size(), compiled) << "the second tessellator compiled its own pipelines";
  EXPECT_GT(fineMesh.indices.size(), coarseMesh.indices.size()) << "a finer tolerance, a finer mesh";
  gpu::AdaptiveTessellator again(own, surf, coarse);
  const auto againMesh = frame(again);
  EXPECT_TRUE(againMesh.indices == coarseMesh.indices);
  ASSERT_EQ(againMesh.vertices.size(), coarseMesh.vertices.size());
  EXPECT_EQ(std::memcmp(againMesh.vertices.data(), coarseMesh.vertices.data(),
                        coarseMesh.vertices.size() * sizeof(coarseMesh.vertices[0])), 0);
  EXPECT_EQ(own->pipelines().size(), compiled);
  for (const vk::ValidationMessage& m : own->validationMessages()) ADD_FAILURE() << m.id << ": " << m.text;
}

TEST_F(AdaptiveTessellatorTest, RefusesBadOptionsByName) {
  const Surface cpu = Surface::create(waveSheet());
  gpu::GpuSurface surf(ctx_, cpu, Precision::Float);
  auto refused = [&](gpu::AdaptiveOptions o, const std::string& field) {
    try {
      gpu::AdaptiveTessellator t(ctx_, surf, o);
      ADD_FAILURE() << field << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  gpu::AdaptiveOptions o;
  o.tolerancePx = 0.0f;
  refused(o, "tolerancePx");
  o = {};
  o.tolerancePx = NAN;
  refused(o, "tolerancePx");
  o = {};
  o.maxRate = 1;
  refused(o, "maxRate");
  o = {};
  o.probeRate = 1;
  refused(o, "probeRate");
  o = {};
  o.safety = 0.5f;
  refused(o, "safety");
  o = {};
  o.hysteresis = -1.0f;
  refused(o, "hysteresis");
  o = {};
  o.maxRate = 4096;  // 80 patches at 4096^2 exceed any storage-buffer range
  EXPECT_THROW(gpu::AdaptiveTessellator(ctx_, surf, o), std::length_error);
}

}  // namespace
}  // namespace shapespline::test
