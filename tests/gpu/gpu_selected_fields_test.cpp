// The GPU list kernels asked for the point, or the point and first derivatives, alone (what
// Session::evaluate(..., ListFields) runs on the GPU; tests/sampling/list_fields_test.cpp goes
// through the session): those fields within the fp32/fp64 tolerances of the CPU lean kernel
// (core/list_eval.h), the others not written (0), on every parameterization (local spans, α-EB,
// knot vectors plain and rational).
#include <gtest/gtest.h>

#include <shapespline/core/list_eval.h>
#include <shapespline/gpu/curve_evaluator.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/gpu/surface_evaluator.h>

#include "support/test_models.h"
#include "support/tolerances.h"
#include "support/vk_fixture.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace shapespline::test {
namespace {

class GpuListFields : public VulkanTest, public ::testing::WithParamInterface<Precision> {
 protected:
  bool skipFp64() { return GetParam() == Precision::Double && !ctx().supportsFloat64(); }
  double rel() const { return GetParam() == Precision::Double ? kFp64Rel : kFp32Rel; }
};

double netDiagonal(const std::vector<glm::dvec3>& points) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

// Global (U, V) drawn over the surface's range, and every patch corner's.
std::vector<SurfaceQuery> listQueries(const Surface& s) {
  std::mt19937 rng(3);
  const auto [u0, u1] = s.parameterRangeU();
  const auto [v0, v1] = s.parameterRangeV();
  std::uniform_real_distribution<double> U(u0, u1), V(v0, v1);
  std::vector<SurfaceQuery> q = {{true, 0, 0, u0, v0}, {true, 0, 0, u1, v1}};
  for (int k = 0; k < 96; ++k) q.push_back({true, 0, 0, U(rng), V(rng)});
  return q;
}

TEST_P(GpuListFields, SurfacesWriteOnlyTheAskedFieldsWithinTolerance) {
  if (skipFp64()) GTEST_SKIP() << "no shaderFloat64";
  const Precision pr = GetParam();
  const std::pair<std::string, SurfaceModel> models[] = {
      {"extended B-spline", wavyNet({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 6, false)},
      {"alpha-EB", wavyNet({Construction::AlphaEB, 5, 0, -2.0, {}}, 6, true)},
      {"knot-vector B-spline", wavyNet({Construction::BSpline, 0, 4, 0.0, {}}, 6, false)},
      {"NURBS torus", nurbsTorus(2.0, 0.5)},
  };
  for (const auto& [name, model] : models) {
    SCOPED_TRACE(name);
    const Surface cpu = Surface::create(model);
    const std::vector<SurfaceQuery> queries = listQueries(cpu);
    std::vector<SurfaceFirst> expected(queries.size());
    evaluateList(cpu, queries, ListFields::FirstDerivatives, expected);
    double derivScale = 0.0;
    for (const auto& e : expected) derivScale = std::max({derivScale, glm::length(e.du), glm::length(e.dv)});
    const double tol = 4.0 * rel() * netDiagonal(model.points), tolD = 32.0 * rel() * derivScale;
    gpu::SurfaceEvaluator ev(ctx_, pr);
    gpu::GpuSurface state(ctx_, cpu, pr);
    std::vector<std::pair<double, double>> uv;
    for (const auto& q : queries) uv.emplace_back(q.u, q.v);
    const FieldMask first = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv);
    for (FieldMask mask : {fieldBit(Field::Point), first}) {
      const auto got = ev.evaluateListAt(state, uv, mask);
      ASSERT_EQ(got.size(), queries.size());
      for (size_t k = 0; k < got.size(); ++k) {
        const std::string at = "query " + std::to_string(k);
        EXPECT_LE(glm::length(got[k].point - expected[k].point), tol) << at;
        EXPECT_TRUE(sameBits(got[k].duu, glm::dvec3(0.0)) && sameBits(got[k].normal, glm::dvec3(0.0)))
            << at << ": second derivatives and normal were not asked for";
        if (mask == fieldBit(Field::Point)) {
          EXPECT_TRUE(sameBits(got[k].du, glm::dvec3(0.0))) << at << ": du was not asked for";
          continue;
        }
        EXPECT_LE(glm::length(got[k].du - expected[k].du), tolD) << at;
        EXPECT_LE(glm::length(got[k].dv - expected[k].dv), tolD) << at;
      }
    }
    EXPECT_THROW(ev.evaluateListAt(state, uv, 0), std::invalid_argument);
    EXPECT_THROW(ev.evaluateListAt(state, uv, fieldBit(Field::D1)), std::invalid_argument);
  }
}

TEST_P(GpuListFields, CurvesWriteOnlyTheAskedFieldsWithinTolerance) {
  if (skipFp64()) GTEST_SKIP() << "no shaderFloat64";
  const Precision pr = GetParam();
  gpu::CurveEvaluator ev(ctx_, pr);
  CurveModel plain;
  plain.family = {Construction::ExtendedBSpline, 5, 0, -3.0, {}};
  plain.dimension = 3;
  for (int i = 0; i < 9; ++i) plain.points.emplace_back(i, std::sin(1.3 * i), 0.2 * i);
  for (const CurveModel& model : {plain, nurbsCircle(2.0)}) {
    const Curve cpu = Curve::create(model);
    const auto [lo, hi] = cpu.parameterRange();
    std::vector<CurveQuery> queries;
    for (int k = 0; k <= 64; ++k) queries.push_back({true, 0, 0.0, lo + (hi - lo) * k / 64});
    std::vector<CurveFirst> expected(queries.size());
    evaluateList(cpu, queries, ListFields::FirstDerivatives, expected);
    double derivScale = 0.0;
    for (const auto& e : expected) derivScale = std::max(derivScale, glm::length(e.d1));
    const double tol = 4.0 * rel() * netDiagonal(model.points), tolD = 32.0 * rel() * derivScale;
    gpu::GpuCurve state(ctx_, cpu, pr);
    std::vector<double> us;
    for (const auto& q : queries) us.push_back(q.u);
    const auto got = ev.evaluateListAt(state, us, fieldBit(Field::Point) | fieldBit(Field::D1));
    for (size_t k = 0; k < queries.size(); ++k) {
      EXPECT_LE(glm::length(got[k].point - expected[k].point), tol) << "query " << k;
      EXPECT_LE(glm::length(got[k].d1 - expected[k].d1), tolD) << "query " << k;
      EXPECT_TRUE(sameBits(got[k].d2, glm::dvec3(0.0))) << "query " << k << ": d2 was not asked for";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Precisions, GpuListFields, ::testing::Values(Precision::Float, Precision::Double),
                         [](const auto& i) { return std::string(i.param == Precision::Double ? "fp64" : "fp32"); });

}  // namespace
}  // namespace shapespline::test
