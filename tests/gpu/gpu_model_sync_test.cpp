// One model per evaluation (gpu_model.h): after every setter the GPU mirror evaluates like the core
// Curve/Surface it holds, and that held object equals a fresh Curve/Surface::create of the changed
// model exactly. An invalid λ or α through a setter throws core's ModelError naming the field and
// leaves the held object, the buffers and the upload counters as they were.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>
#include <shapespline/gpu/evaluator.h>
#include "support/test_models.h"
#include "support/tolerances.h"
#include "support/vk_fixture.h"

namespace shapespline::test {
namespace {

double boxDiagonal(const std::vector<glm::dvec3>& pts) {
  glm::dvec3 lo(pts[0]), hi(pts[0]);
  for (const auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

double minAlpha(const std::vector<double>& alpha) {
  return alpha.empty() ? 1.0 : *std::min_element(alpha.begin(), alpha.end());
}

bool sameBits(const glm::dvec3& a, const glm::dvec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expectSamePoints(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (size_t k = 0; k < a.size(); ++k)
    EXPECT_TRUE(sameBits(a[k], b[k])) << what << "[" << k << "] differs";
}

void expectSameBasis(const SpanBasis& a, const SpanBasis& b) {
  ASSERT_EQ(a.count, b.count);
  ASSERT_EQ(a.degree, b.degree);
  for (int r = 0; r < a.count; ++r)
    for (int d = 0; d <= a.degree; ++d) EXPECT_EQ(a.coef[r][d], b.coef[r][d]) << "coef[" << r << "][" << d << "]";
}

// The held curve against a fresh Curve::create of its model: every precomputed table and the
// evaluation at a few global parameters, bit for bit.
void expectSameCurve(const Curve& held, const Curve& fresh) {
  EXPECT_EQ(held.parameterization(), fresh.parameterization());
  EXPECT_EQ(held.model().alpha, fresh.model().alpha);
  EXPECT_EQ(held.model().family.lambda, fresh.model().family.lambda);
  expectSameBasis(held.basis(), fresh.basis());
  expectSamePoints(held.spanPoints(), fresh.spanPoints(), "spanPoints");
  expectSamePoints(held.alphaNodes(), fresh.alphaNodes(), "alphaNodes");
  expectSamePoints(held.alphaV(), fresh.alphaV(), "alphaV");
  const auto [lo, hi] = fresh.parameterRange();
  for (int k = 0; k <= 8; ++k) {
    const double u = lo + (hi - lo) * k / 8.0;
    EXPECT_TRUE(sameBits(held.evaluateAt(u).point, fresh.evaluateAt(u).point)) << "u " << u;
  }
}

void expectSameSurface(const Surface& held, const Surface& fresh) {
  EXPECT_EQ(held.parameterization(), fresh.parameterization());
  EXPECT_EQ(held.model().alpha, fresh.model().alpha);
  EXPECT_EQ(held.model().family.lambda, fresh.model().family.lambda);
  expectSameBasis(held.basisU(), fresh.basisU());
  expectSameBasis(held.basisV(), fresh.basisV());
  expectSamePoints(held.patchNet(), fresh.patchNet(), "patchNet");
  expectSamePoints(held.alphaNodes(), fresh.alphaNodes(), "alphaNodes");
  expectSamePoints(held.alphaV(), fresh.alphaV(), "alphaV");
  const auto [ulo, uhi] = fresh.parameterRangeU();
  const auto [vlo, vhi] = fresh.parameterRangeV();
  for (int a = 0; a <= 4; ++a)
    for (int b = 0; b <= 4; ++b) {
      const double U = ulo + (uhi - ulo) * a / 4.0, V = vlo + (vhi - vlo) * b / 4.0;
      EXPECT_TRUE(sameBits(held.evaluateAt(U, V).point, fresh.evaluateAt(U, V).point)) << "(" << U << ", " << V << ")";
    }
}

class GpuModelSyncTest : public VulkanTest {
 protected:
  Precision precision() { return ctx().supportsFloat64() ? Precision::Double : Precision::Float; }
  double rel() { return precision() == Precision::Double ? kFp64Rel : kFp32Rel; }

  // GPU list evaluation at global parameters (through the shared span lookup) against the held
  // curve. Tolerance: rel * scale / α_min for points (support/tolerances.h), 16x that for d1 as in
  // gpu_update_test.cpp.
  void expectGpuMatchesHeld(gpu::GpuCurve& state, const std::string& after) {
    const Curve& cpu = state.curve();
    const double tol = rel() * boxDiagonal(cpu.model().points) / minAlpha(cpu.model().alpha);
    const auto [lo, hi] = cpu.parameterRange();
    std::vector<double> u;
    for (int k = 0; k <= 40; ++k) u.push_back(lo + (hi - lo) * k / 40.0);
    if (!curveEval_) curveEval_ = std::make_unique<gpu::CurveEvaluator>(ctx_, precision());
    const auto got = curveEval_->evaluateListAt(state, u);
    for (size_t k = 0; k < u.size(); ++k) {
      const CurvePoint e = cpu.evaluateAt(u[k]);
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(got[k].point[a], e.point[a], tol) << after << ": u " << u[k];
        EXPECT_NEAR(got[k].d1[a], e.d1[a], 16 * tol) << after << ": u " << u[k];
      }
    }
  }

  void expectGpuMatchesHeld(gpu::GpuSurface& state, const std::string& after) {
    const Surface& cpu = state.surface();
    const double tol = rel() * boxDiagonal(cpu.controlPoints()) / minAlpha(cpu.model().alpha);
    const auto [ulo, uhi] = cpu.parameterRangeU();
    const auto [vlo, vhi] = cpu.parameterRangeV();
    std::vector<std::pair<double, double>> uv;
    for (int a = 0; a <= 8; ++a)  // every joint and patch middle of the 4 x 4 patches
      for (int b = 0; b <= 8; ++b) uv.push_back({ulo + (uhi - ulo) * a / 8.0, vlo + (vhi - vlo) * b / 8.0});
    if (!surfaceEval_) surfaceEval_ = std::make_unique<gpu::SurfaceEvaluator>(ctx_, precision());
    const auto got = surfaceEval_->evaluateListAt(state, uv);
    for (size_t k = 0; k < uv.size(); ++k) {
      const SurfacePoint e = cpu.evaluateAt(uv[k].first, uv[k].second);
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(got[k].point[a], e.point[a], tol) << after << ": (U, V) " << uv[k].first << ", " << uv[k].second;
        EXPECT_NEAR(got[k].du[a], e.du[a], 16 * tol) << after << ": (U, V) " << uv[k].first << ", " << uv[k].second;
      }
    }
  }

 private:
  std::unique_ptr<gpu::CurveEvaluator> curveEval_;
  std::unique_ptr<gpu::SurfaceEvaluator> surfaceEval_;
};

SurfaceModel aebSurface() { return alphaEBTube(5, 4); }

CurveModel aebCurve() {
  CurveModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 4;
  m.family.lambda = 0.0;
  m.dimension = 2;
  for (int i = 0; i < 7; ++i) m.points.push_back({double(i), std::sin(0.9 * i), 0.0});
  m.alpha.assign(m.points.size(), 0.75);
  return m;
}

// modelBufferBytes, which the sampling layer compares with maxStorageBufferRange before a mirror
// exists, is what the mirrors then create, for every parameterization and both precisions.
TEST_F(GpuModelSyncTest, BufferSizesAreKnownBeforeTheBuffers) {
  auto expectSizes = [](const gpu::GpuModel& mirror, const gpu::ModelBufferBytes& predicted, const std::string& what) {
    EXPECT_EQ(mirror.netBuffer().size(), predicted.net) << what;
    EXPECT_EQ(mirror.paramBuffer().size(), predicted.params) << what;
    EXPECT_EQ(mirror.vertexBuffer().size(), predicted.verts) << what;
  };
  FamilySpec xuWang;
  xuWang.construction = Construction::ExtendedBSpline;
  xuWang.degree = 5;
  xuWang.lambda = 0.5;
  const std::vector<std::pair<std::string, SurfaceModel>> surfaces = {
      {"alpha_eb", aebSurface()}, {"nurbs torus", nurbsTorus(3.0, 1.0)}, {"xu-wang", wavyNet(xuWang, 7, false)}};
  CurveModel plain = aebCurve();
  plain.family = xuWang;
  plain.alpha.clear();
  const std::vector<std::pair<std::string, CurveModel>> curves = {
      {"alpha_eb", aebCurve()}, {"nurbs circle", nurbsCircle(2.0)}, {"xu-wang", plain}};
  std::vector<Precision> precisions = {Precision::Float};
  if (ctx().supportsFloat64()) precisions.push_back(Precision::Double);
  for (Precision p : precisions) {
    for (const auto& [name, m] : surfaces) {
      const Surface s = Surface::create(m);
      expectSizes(gpu::GpuSurface(ctx_, s, p), gpu::modelBufferBytes(s, p), "surface " + name);
    }
    for (const auto& [name, m] : curves) {
      const Curve c = Curve::create(m);
      expectSizes(gpu::GpuCurve(ctx_, c, p), gpu::modelBufferBytes(c, p), "curve " + name);
    }
  }
}

// The α-EB vertex pass runs one invocation per vertex; past maxComputeWorkGroupCount[0] groups
// of them the dispatch folds into y, and every vertex must still be computed (a 2048² net has
// 4.2 million vertices: 65,536 groups of 64, one more than lavapipe's x limit; the last 64 V were
// left unwritten). An α-EB curve just past that count, its last spans against the CPU.
TEST_F(GpuModelSyncTest, VertexPassCoversEveryVertexPastTheGroupLimit) {
  const uint64_t groupsX = ctx().limits().maxComputeWorkGroupCount[0];
  const uint64_t n = groupsX * 64 + 60;  // 64: KernelSet's workgroup size
  const Precision p = Precision::Float;
  if (n * 2 * 4 * 4 > ctx().limits().maxStorageBufferRange || n > (uint64_t{1} << 23)) {
    GTEST_SKIP() << "maxComputeWorkGroupCount[0] " << groupsX << ": too many vertices for this test";
  }
  CurveModel m = aebCurve();
  m.points.resize(n);
  for (size_t i = 0; i < n; ++i) m.points[i] = {double(i % 1000), std::sin(0.37 * double(i)), 0.0};
  m.alpha.assign(n, 0.75);
  const Curve cpu = Curve::create(m);
  gpu::GpuCurve mirror(ctx_, cpu, p);
  gpu::CurveEvaluator evaluator(ctx_, p);
  std::vector<gpu::CurveSample> samples;
  for (int s = cpu.spans().last - 70; s <= cpu.spans().last; ++s) samples.push_back({s, 0.5});
  const auto got = evaluator.evaluateList(mirror, samples);
  const double tol = kFp32Rel * boxDiagonal(m.points) / 0.75;  // support/tolerances.h, over α
  for (size_t k = 0; k < samples.size(); ++k) {
    const CurvePoint e = cpu.evaluate(samples[k].span, samples[k].t);
    for (int a = 0; a < 2; ++a) EXPECT_NEAR(got[k].point[a], e.point[a], tol) << "span " << samples[k].span;
  }
}

TEST_F(GpuModelSyncTest, SurfaceSettersKeepCoreAndGpuEqual) {
  SurfaceModel model = aebSurface();
  gpu::GpuSurface state(ctx_, Surface::create(model), precision());
  expectGpuMatchesHeld(state, "construction");

  const std::vector<std::pair<std::string, std::function<void()>>> steps = {
      {"setLambda", [&] { state.setLambda(-3.0), model.family.lambda = -3.0; }},
      {"setParameters", [&] {
         FamilySpec f = model.family;
         f.lambda = 0.5;
         state.setParameters(f), model.family = f;
       }},
      {"setAlpha", [&] { state.setAlpha(2, 3, 1.0), model.alpha[2 * model.cols + 3] = 1.0; }},
      {"setAlphas", [&] {
         std::vector<double> a(model.alpha.size());
         for (size_t k = 0; k < a.size(); ++k) a[k] = 0.25 + 0.75 * double(k % 4) / 3.0;
         state.setAlphas(a), model.alpha = a;
       }},
      {"updateControlPoint", [&] {
         const glm::dvec3 p(2.5, 0.2, -0.4);
         state.updateControlPoint(0, 3, p), model.points[3] = p;  // open u edge, closed v wrap
       }},
  };
  for (const auto& [name, step] : steps) {
    step();
    expectSameSurface(state.surface(), Surface::create(model));
    expectGpuMatchesHeld(state, "after " + name);
  }
}

TEST_F(GpuModelSyncTest, CurveSettersKeepCoreAndGpuEqual) {
  CurveModel model = aebCurve();
  gpu::GpuCurve state(ctx_, Curve::create(model), precision());
  expectGpuMatchesHeld(state, "construction");
  const std::vector<std::pair<std::string, std::function<void()>>> steps = {
      {"setLambda", [&] { state.setLambda(-2.0), model.family.lambda = -2.0; }},
      {"setAlpha", [&] { state.setAlpha(3, 0.25), model.alpha[3] = 0.25; }},
      {"setAlphas", [&] {
         std::vector<double> a(model.alpha.size(), 0.5);
         a[0] = 1.0;
         state.setAlphas(a), model.alpha = a;
       }},
      {"updateControlPoint", [&] {
         const glm::dvec3 p(0.0, -0.5, 0.0);
         state.updateControlPoint(0, p), model.points[0] = p;  // also moves the phantom P_{-1}
       }},
  };
  for (const auto& [name, step] : steps) {
    step();
    expectSameCurve(state.curve(), Curve::create(model));
    expectGpuMatchesHeld(state, "after " + name);
  }
}

TEST_F(GpuModelSyncTest, KnotVectorControlPointWritesOneEntry) {
  CurveModel model;
  model.family.construction = Construction::BSpline;
  model.family.order = 4;
  model.dimension = 2;
  for (int i = 0; i < 6; ++i) model.points.push_back({double(i), std::cos(0.8 * i), 0.0});
  model.knots = {0, 0, 0, 0, 0.3, 0.3, 1, 1, 1, 1};  // a double interior knot: an empty interval
  gpu::GpuCurve state(ctx_, Curve::create(model), precision());
  const uint64_t writes0 = state.uploadStats().netWrites;
  const glm::dvec3 p(2.0, 1.5, 0.0);
  state.updateControlPoint(2, p);
  model.points[2] = p;
  EXPECT_EQ(state.uploadStats().netWrites, writes0 + 1) << "a knot-vector net entry is the point itself";
  expectSameCurve(state.curve(), Curve::create(model));
  expectGpuMatchesHeld(state, "after updateControlPoint");
}

// A rejected value: core's ModelError with the field, and no byte or object changed.
template <class State, class Core>
void expectRejected(State& state, const Core& (State::*held)() const, const std::function<void()>& set,
                    const std::string& field, const std::function<void(const Core&, const Core&)>& same) {
  const Core before = (state.*held)();
  const gpu::UploadStats stats = state.uploadStats();
  try {
    set();
    ADD_FAILURE() << "no ModelError for " << field;
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), field);
  }
  same((state.*held)(), before);
  EXPECT_EQ(state.uploadStats().netBytes, stats.netBytes);
  EXPECT_EQ(state.uploadStats().paramBytes, stats.paramBytes);
  EXPECT_EQ(state.verticesDirty(), false) << "a rejected value must not queue a vertex pass";
}

TEST_F(GpuModelSyncTest, InvalidValuesThrowAndChangeNothing) {
  gpu::GpuSurface surface(ctx_, Surface::create(aebSurface()), precision());
  expectGpuMatchesHeld(surface, "construction");  // runs the vertex pass: clean from here on
  const std::function<void(const Surface&, const Surface&)> sameSurface = expectSameSurface;
  expectRejected(surface, &gpu::GpuSurface::surface, [&] { surface.setLambda(2.0); }, "lambda", sameSurface);
  expectRejected(surface, &gpu::GpuSurface::surface, [&] { surface.setAlpha(2, 3, 0.0); }, "alpha[2][3]",
                 sameSurface);
  expectGpuMatchesHeld(surface, "after the rejected values");

  gpu::GpuCurve curve(ctx_, Curve::create(aebCurve()), precision());
  expectGpuMatchesHeld(curve, "construction");
  const std::function<void(const Curve&, const Curve&)> sameCurve = expectSameCurve;
  expectRejected(curve, &gpu::GpuCurve::curve, [&] { curve.setLambda(std::nan("")); }, "lambda", sameCurve);
  std::vector<double> alphas(aebCurve().alpha.size(), 0.5);
  alphas[4] = 1.5;
  expectRejected(curve, &gpu::GpuCurve::curve, [&] { curve.setAlphas(alphas); }, "alpha[4]", sameCurve);
  expectGpuMatchesHeld(curve, "after the rejected values");
}

}  // namespace
}  // namespace shapespline::test
