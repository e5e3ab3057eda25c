// The parameter-update path (gpu_model.h): λ / α / μ changes rewrite only the small PARAMS buffer
// and re-run the α-EB vertex pass on the GPU; the net buffer (same VkBuffer handle) receives no
// byte. Results must then equal a CPU model rebuilt with the new parameters. Also: one control
// point update writes only the net entries that depend on it; GPU basis tables equal evalSpanBasis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>
#include <shapespline/gpu/evaluator.h>
#include "support/test_models.h"
#include "support/tolerances.h"
#include "support/vk_fixture.h"

namespace shapespline::test {
namespace {

SurfaceModel aebSurface() { return alphaEBTube(6, 5); }

double maxPointError(const Surface& cpu, gpu::SurfaceEvaluator& ev, gpu::GpuSurface& state) {
  std::vector<gpu::SurfaceSample> s;
  for (int i = cpu.patches().u.first; i <= cpu.patches().u.last; ++i)
    for (int j = cpu.patches().v.first; j <= cpu.patches().v.last; ++j)
      for (double u : {0.0, 0.3, 1.0})
        for (double v : {0.0, 0.55, 1.0}) s.push_back({i, j, u, v});
  const auto got = ev.evaluateList(state, s);
  double err = 0.0;
  for (size_t k = 0; k < s.size(); ++k) {
    const SurfacePoint e = cpu.evaluate(s[k].i, s[k].j, s[k].u, s[k].v);
    for (int a = 0; a < 3; ++a) {
      err = std::max(err, std::abs(e.point[a] - got[k].point[a]));
      err = std::max(err, std::abs(e.du[a] - got[k].du[a]) / 16.0);
    }
  }
  return err;
}

class GpuUpdateTest : public VulkanTest {};

TEST_F(GpuUpdateTest, LambdaAndAlphaNeverReuploadTheNet) {
  const Precision pr = ctx().supportsFloat64() ? Precision::Double : Precision::Float;
  const double tol = (pr == Precision::Double ? kFp64Rel : kFp32Rel) * 20.0;  // scale ~ 7, 1/α_min = 4
  SurfaceModel model = aebSurface();
  gpu::GpuSurface state(ctx_, Surface::create(model), pr);
  gpu::SurfaceEvaluator ev(ctx_, pr);
  const VkBuffer netHandle = state.netBuffer().handle();
  const gpu::UploadStats before = state.uploadStats();
  double worst = maxPointError(Surface::create(model), ev, state);
  EXPECT_LE(worst, tol);
  const uint64_t passes0 = state.uploadStats().vertexPasses;

  // λ change.
  state.setLambda(-4.0);
  model.family.lambda = -4.0;
  double e = maxPointError(Surface::create(model), ev, state);
  worst = std::max(worst, e);
  EXPECT_LE(e, tol) << "after setLambda";
  // One α and then all α.
  state.setAlpha(2, 3, 1.0);
  model.alpha[2 * model.cols + 3] = 1.0;
  e = maxPointError(Surface::create(model), ev, state);
  worst = std::max(worst, e);
  EXPECT_LE(e, tol) << "after setAlpha";
  std::vector<double> alphas(model.rows * model.cols);
  for (size_t k = 0; k < alphas.size(); ++k) alphas[k] = 0.25 + 0.75 * double(k % 4) / 3.0;
  state.setAlphas(alphas);
  model.alpha = alphas;
  e = maxPointError(Surface::create(model), ev, state);
  worst = std::max(worst, e);
  EXPECT_LE(e, tol * 4) << "after setAlphas";

  const gpu::UploadStats after = state.uploadStats();
  EXPECT_EQ(state.netBuffer().handle(), netHandle);
  EXPECT_EQ(after.netBytes, before.netBytes) << "a parameter change wrote into the net buffer";
  EXPECT_EQ(after.netWrites, before.netWrites);
  EXPECT_EQ(after.paramWrites, before.paramWrites + 3);
  EXPECT_EQ(after.vertexPasses, passes0 + 3) << "the vertex pass must run once per parameter change";
  const uint64_t paramBytesPerChange = (after.paramBytes - before.paramBytes) / 3;
  EXPECT_LT(paramBytesPerChange, before.netBytes) << "parameter block should be smaller than the net";
  std::printf("  update test: net %llu bytes uploaded once; each change uploads %llu parameter bytes; max error %.3g\n",
              (unsigned long long)before.netBytes, (unsigned long long)paramBytesPerChange, worst);

  // One control point: only its dependent net entries (closed v: wrapped copies) are written.
  const uint64_t netBytes0 = after.netBytes;
  const glm::dvec3 p(2.5, 0.2, -0.4);
  state.updateControlPoint(3, 1, p);
  model.points[3 * model.cols + 1] = p;
  e = maxPointError(Surface::create(model), ev, state);
  EXPECT_LE(e, tol * 4) << "after updateControlPoint";
  const uint64_t written = state.uploadStats().netBytes - netBytes0;
  EXPECT_GT(written, 0u);
  EXPECT_LE(written, 4 * 4 * (pr == Precision::Double ? 8u : 4u)) << "one interior point, at most 4 net entries";
}

TEST_F(GpuUpdateTest, CurveParametersUpdate) {
  const Precision pr = ctx().supportsFloat64() ? Precision::Double : Precision::Float;
  CurveModel m;
  m.family.construction = Construction::GUBP;
  m.family.order = 6;
  m.family.mu = {0.125, 0.25, 0.375, 0.5};
  m.closed = true;
  m.dimension = 2;
  for (int i = 0; i < 9; ++i) m.points.push_back({std::cos(i * 0.7), std::sin(i * 0.7) * (1 + 0.1 * i), 0.0});
  gpu::GpuCurve state(ctx_, Curve::create(m), pr);
  gpu::CurveEvaluator ev(ctx_, pr);
  const uint64_t net0 = state.uploadStats().netBytes;
  FamilySpec f = m.family;
  f.mu = {0.25, 0.125, 0.25, 0.75};
  state.setParameters(f);
  m.family = f;
  const Curve cpu = Curve::create(m);
  std::vector<gpu::CurveSample> s;
  for (int j = cpu.spans().first; j <= cpu.spans().last; ++j) s.push_back({j, 0.4});
  const auto got = ev.evaluateList(state, s);
  for (size_t k = 0; k < s.size(); ++k) {
    const CurvePoint e = cpu.evaluate(s[k].span, s[k].t);
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(e.point[a], got[k].point[a], (pr == Precision::Double ? kFp64Rel : kFp32Rel) * 8.0);
  }
  EXPECT_EQ(state.uploadStats().netBytes, net0);
}

TEST_F(GpuUpdateTest, BasisTablesMatchEvalSpanBasis) {
  double worst[2] = {0, 0};
  for (Precision pr : {Precision::Float, Precision::Double}) {
    if (pr == Precision::Double && !ctx().supportsFloat64()) continue;
    gpu::BasisTableEvaluator ev(ctx_, pr);
    const double tolRel = pr == Precision::Double ? 1e-13 : 4e-6;
    std::vector<SpanBasis> bases = {xuWangSpanBasis(4, 0.0), xuWangSpanBasis(6, -20.0), gbSpanBasis(5.0),
                                    ubpSpanBasis(10, 0.5), uniformBSplineSpanBasis(2)};
    const double mu[] = {0.25, 1.0, 1.5};
    bases.push_back(gubpSpanBasis(5, mu));
    for (const SpanBasis& b : bases) {
      for (int n : {1, 2, 13, 300}) {
        const auto table = ev.evaluate(b, n);
        ASSERT_EQ(table.size(), size_t(n) * 3 * b.count);
        for (int a = 0; a < n; ++a) {
          double v[3][kMaxBasisCount];
          evalSpanBasis(b, n > 1 ? double(a) / (n - 1) : 0.0, v[0], v[1], v[2]);
          for (int d = 0; d < 3; ++d)
            for (int r = 0; r < b.count; ++r) {
              const double got = table[size_t(a) * 3 * b.count + d * b.count + r];
              // second derivatives of order-10 pieces reach ~1e2: relative to max(1,|v|) * 10^d
              const double tol = tolRel * std::max(1.0, std::abs(v[d][r])) * std::pow(10.0, d);
              const double err = std::abs(got - v[d][r]);
              worst[pr == Precision::Double] = std::max(worst[pr == Precision::Double], err);
              ASSERT_LE(err, tol) << "m " << b.count << " n " << n << " a " << a << " d " << d << " r " << r;
            }
        }
      }
    }
  }
  std::printf("  basis tables: max error fp32 %.3g fp64 %.3g\n", worst[0], worst[1]);
}

}  // namespace
}  // namespace shapespline::test
