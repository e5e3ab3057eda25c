// The part mesher with its surface points from a Vulkan device: in fp64 the device's list kernel
// gives the CPU's points to rounding, so the mesh has the CPU's topology (every refinement decision
// the same) and its vertices agree to 1e-12 of the part's size.
#include <shapespline/core/model.h>
#include <shapespline/part/face_evaluator.h>
#include <shapespline/part/part_mesher.h>
#include <shapespline/part/part_model.h>
#include <shapespline/sampling/session.h>

#include <support/vk_fixture.h>

#include "wavy_face.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace shapespline::part {
namespace {

// The wavy face trimmed by a square with a round-ish hole.
Surface wavyFaceWithARoundHole() {
  std::vector<glm::dvec2> hole;
  for (int k = 0; k < 12; ++k) {
    const double a = -2.0 * M_PI * k / 12;  // clockwise: a hole
    hole.push_back({0.5 + 0.2 * std::cos(a), 0.45 + 0.2 * std::sin(a)});
  }
  return wavyFace({{{0.05, 0.05}, {0.95, 0.05}, {0.95, 0.95}, {0.05, 0.95}}, hole});
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
  const Part part = faceAsPart("wavy.json", wavyFaceWithARoundHole());
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
