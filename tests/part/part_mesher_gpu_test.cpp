// The part mesher with its surface points from a Vulkan device: in fp64 the device's list kernel
// gives the CPU's points to rounding, so the mesh has the CPU's topology (every refinement decision
// the same) and its vertices agree to 1e-12 of the part's size.
#include <shapespline/core/model.h>
#include <shapespline/part/face_evaluator.h>
#include <shapespline/part/part_mesher.h>
#include <shapespline/part/part_model.h>
#include <shapespline/sampling/session.h>

#include <support/vk_fixture.h>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace shapespline::part {
namespace {

// A bicubic face over [0, 1]^2 waving in z, trimmed by a square with a round-ish hole.
Surface wavyFace() {
  SurfaceModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 4;
  m.orderV = 4;
  const int n = 4, rows = n + 3;
  std::vector<double> knots = {0, 0, 0};
  for (int i = 0; i <= n; ++i) knots.push_back(double(i) / n);
  knots.insert(knots.end(), {1, 1, 1});
  m.knotsU = m.knotsV = knots;
  m.rows = m.cols = rows;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < rows; ++j)
      m.points.push_back({double(i) / (rows - 1), double(j) / (rows - 1), 0.3 * std::sin(1.7 * i + 2.3 * j)});
  std::vector<glm::dvec2> hole;
  for (int k = 0; k < 12; ++k) {
    const double a = -2.0 * M_PI * k / 12;  // clockwise: a hole
    hole.push_back({0.5 + 0.2 * std::cos(a), 0.45 + 0.2 * std::sin(a)});
  }
  m.trim.loops = {{{0.05, 0.05}, {0.95, 0.05}, {0.95, 0.95}, {0.05, 0.95}}, hole};
  m.trim.tolerance = 1e-9;
  return Surface::create(std::move(m));
}

class PartMesherGpu : public test::VulkanTest {
 protected:
  PartMesh mesh(const Part& part, Precision precision) {
    sampling::Session session(ctx_);
    const sampling::DeviceRequest request{sampling::DeviceKind::Vulkan, precision, true};
    const sampling::Report report = session.plan(part.faces.front().surface, request);
    EXPECT_TRUE(report.gpu);
    EXPECT_EQ(report.computedPrecision, precision);
    SessionFaceEvaluator device(session, request, report.device);
    MeshOptions options;
    options.deflection = 1e-3;
    options.threads = 2;
    return meshPart(part, options, device);
  }
};

TEST_F(PartMesherGpu, Fp64HasTheCpuTopologyAndPoints) {
  const Part part = faceAsPart("wavy.json", wavyFace());
  CpuFaceEvaluator cpu;
  MeshOptions options;
  options.deflection = 1e-3;
  options.threads = 2;
  const PartMesh reference = meshPart(part, options, cpu);
  const PartMesh gpu = mesh(part, Precision::Double);
  ASSERT_EQ(gpu.mesh.triangles, reference.mesh.triangles);
  ASSERT_EQ(gpu.mesh.positions.size(), reference.mesh.positions.size());
  const double size = partDiagonal(part);
  for (size_t k = 0; k < gpu.mesh.positions.size(); ++k)
    ASSERT_LE(glm::length(gpu.mesh.positions[k] - reference.mesh.positions[k]), 1e-12 * size) << "vertex " << k;
  EXPECT_EQ(gpu.boundaryEdges, reference.boundaryEdges);
}

}  // namespace
}  // namespace shapespline::part
