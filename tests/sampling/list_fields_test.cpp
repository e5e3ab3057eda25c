// Session::evaluate(..., ListFields): on the CPU the lean list kernel, the same bits as the full
// list's fields, nets scaled by a power of two included; on the GPU the list kernels with only those
// fields written, within fp32 of the CPU.
#include <gtest/gtest.h>

#include <shapespline/core/list_eval.h>
#include <shapespline/sampling/session.h>

#include "support/test_models.h"
#include "support/tolerances.h"
#include "support/vk_fixture.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

std::vector<SurfaceQuery> torusQueries() {
  std::vector<SurfaceQuery> q;
  for (int a = 0; a <= 12; ++a)
    for (int b = 0; b <= 12; ++b) q.push_back({true, 0, 0, a / 12.0, b / 12.0});
  q.push_back({false, 2, 4, 0.25, 1.0});  // knot intervals 2, 4, 6, 8 are the non-empty ones
  q.push_back({false, 4, 2, 1.0, 0.0});
  return q;
}

// The NURBS torus with its net times `scale`.
Surface scaledTorus(double scale) {
  SurfaceModel m = nurbsTorus(2.0, 0.5);
  for (auto& p : m.points) p *= scale;
  return Surface::create(m);
}

TEST(ListFieldsSession, CpuListsHaveTheFullListsBitsAtEveryScale) {
  for (double scale : {1.0, 1e250}) {  // 1e250: beyond 2^200, evaluated as 2^k * net and scaled back
    SCOPED_TRACE("net scale " + std::to_string(scale));
    const Surface s = scaledTorus(scale);
    const std::vector<SurfaceQuery> q = torusQueries();
    sampling::Session session;
    const sampling::DeviceRequest cpu{sampling::DeviceKind::Cpu, Precision::Double};
    const auto full = session.evaluate(s, cpu, q);
    const auto lean = session.evaluate(s, cpu, q, ListFields::FirstDerivatives);
    const auto point = session.evaluate(s, cpu, q, ListFields::Point);
    EXPECT_EQ(lean.report.netScaleExponent, full.report.netScaleExponent);
    if (scale > 1.0) {
      EXPECT_NE(full.report.netScaleExponent, 0);
    }
    ASSERT_EQ(lean.points.size(), q.size());
    for (size_t k = 0; k < q.size(); ++k) {
      EXPECT_TRUE(sameBits(lean.points[k].point, full.points[k].point)) << "query " << k;
      EXPECT_TRUE(sameBits(lean.points[k].du, full.points[k].du)) << "query " << k;
      EXPECT_TRUE(sameBits(lean.points[k].dv, full.points[k].dv)) << "query " << k;
      EXPECT_TRUE(sameBits(point.points[k].point, full.points[k].point)) << "query " << k;
    }
  }
  const Curve c = Curve::create(nurbsCircle(3.0));
  std::vector<CurveQuery> cq;
  for (int k = 0; k <= 40; ++k) cq.push_back({true, 0, 0.0, k / 40.0});
  sampling::Session session;
  const sampling::DeviceRequest cpu{sampling::DeviceKind::Cpu, Precision::Double};
  const auto full = session.evaluate(c, cpu, cq);
  const auto lean = session.evaluate(c, cpu, cq, ListFields::FirstDerivatives);
  for (size_t k = 0; k < cq.size(); ++k) {
    EXPECT_TRUE(sameBits(lean.points[k].point, full.points[k].point)) << "curve query " << k;
    EXPECT_TRUE(sameBits(lean.points[k].d1, full.points[k].d1)) << "curve query " << k;
  }
}

TEST(ListFieldsSession, AQueryOutsideTheModelIsNamed) {
  const Surface s = Surface::create(nurbsTorus(2.0, 0.5));
  const std::vector<SurfaceQuery> q = {{true, 0, 0, 0.5, 0.5}, {true, 0, 0, 0.5, -0.5}};
  sampling::Session session;
  try {
    session.evaluate(s, {sampling::DeviceKind::Cpu, Precision::Double}, q, ListFields::Point);
    FAIL() << "expected QueryRangeError";
  } catch (const sampling::QueryRangeError& e) {
    EXPECT_EQ(e.index(), 1u);
  }
}

class ListFieldsGpu : public VulkanTest {};

TEST_F(ListFieldsGpu, GpuListsWriteTheAskedFieldsWithinFp32) {
  const Surface s = Surface::create(nurbsTorus(2.0, 0.5));
  const std::vector<SurfaceQuery> q = torusQueries();
  std::vector<SurfaceFirst> expected(q.size());
  evaluateList(s, q, ListFields::FirstDerivatives, expected);
  sampling::Session session(ctx_);
  const auto got = session.evaluate(s, {sampling::DeviceKind::Vulkan, Precision::Float, true}, q,
                                    ListFields::FirstDerivatives);
  ASSERT_TRUE(got.report.gpu);
  double derivScale = 0.0;
  for (const auto& e : expected) derivScale = std::max({derivScale, glm::length(e.du), glm::length(e.dv)});
  const double tol = 4.0 * kFp32Rel * 5.0, tolD = 32.0 * kFp32Rel * derivScale;  // the torus spans 5 units
  for (size_t k = 0; k < q.size(); ++k) {
    EXPECT_LE(glm::length(got.points[k].point - expected[k].point), tol) << "query " << k;
    EXPECT_LE(glm::length(got.points[k].du - expected[k].du), tolD) << "query " << k;
    EXPECT_LE(glm::length(got.points[k].dv - expected[k].dv), tolD) << "query " << k;
  }
  const auto points = session.evaluate(s, {sampling::DeviceKind::Vulkan, Precision::Float, true}, q, ListFields::Point);
  for (size_t k = 0; k < q.size(); ++k) EXPECT_TRUE(sameBits(points.points[k].du, glm::dvec3(0.0))) << "query " << k;
}

// Two lists through `resident` on its one upload: each with `want`'s bits (point and partials).
void expectTwoListsOf(sampling::Session::ResidentSurface& resident, const std::vector<SurfaceQuery>& q,
                      const std::vector<SurfaceFirst>& want) {
  for (int list = 0; list < 2; ++list) {
    const std::vector<SurfaceFirst> got = resident.evaluate(q, ListFields::FirstDerivatives);
    ASSERT_EQ(got.size(), q.size());
    for (size_t k = 0; k < q.size(); ++k) {
      EXPECT_TRUE(sameBits(got[k].point, want[k].point)) << "list " << list << " query " << k;
      EXPECT_TRUE(sameBits(got[k].du, want[k].du)) << "list " << list << " query " << k;
      EXPECT_TRUE(sameBits(got[k].dv, want[k].dv)) << "list " << list << " query " << k;
    }
  }
}

// A resident surface gives evaluate()'s bits, list after list, on the CPU (nets scaled too) and on
// the device, and reports the plan evaluate() makes.
TEST(ListFieldsSession, AResidentSurfaceGivesEvaluatesBitsOnTheCpu) {
  for (double scale : {1.0, 1e250}) {
    SCOPED_TRACE("net scale " + std::to_string(scale));
    const Surface s = scaledTorus(scale);
    const std::vector<SurfaceQuery> q = torusQueries();
    sampling::Session session;
    const sampling::DeviceRequest cpu{sampling::DeviceKind::Cpu, Precision::Double};
    const auto want = session.evaluate(s, cpu, q, ListFields::FirstDerivatives);
    const auto resident = session.resident(s, cpu);
    EXPECT_FALSE(resident->report().gpu);
    EXPECT_EQ(resident->report().netScaleExponent, want.report.netScaleExponent);
    expectTwoListsOf(*resident, q, want.points);
    EXPECT_TRUE(resident->evaluate({}, ListFields::FirstDerivatives).empty());
  }
}

TEST_F(ListFieldsGpu, AResidentSurfaceGivesEvaluatesBitsOnTheDevice) {
  const Surface s = Surface::create(nurbsTorus(2.0, 0.5));
  const std::vector<SurfaceQuery> q = torusQueries();
  sampling::Session session(ctx_);
  const sampling::DeviceRequest vulkan{sampling::DeviceKind::Vulkan, Precision::Float, true};
  const auto want = session.evaluate(s, vulkan, q, ListFields::FirstDerivatives);
  const auto resident = session.resident(s, vulkan);
  ASSERT_TRUE(resident->report().gpu);
  expectTwoListsOf(*resident, q, want.points);  // each the bits of a list with its own upload
}

}  // namespace
}  // namespace shapespline::test
