// Closest points with the search on a Vulkan device (part/gpu_closest_points.h) against the CPU's
// (part/closest_points.h), which closest_points_test.cpp holds to a brute-force reference. In fp64
// the device takes the same steps in the same arithmetic but for contraction and the order it visits
// pieces in, so every foot agrees to 1e-9 of the diagonal and the range; in fp32 the distance agrees
// within kFloatDistance of the diagonal (docs/math.md "Closest points" gives the bound).
#include <shapespline/part/closest_points.h>
#include <shapespline/part/gpu_closest_points.h>
#include <shapespline/part/part_model.h>

#include <support/temp_files.h>
#include <support/vk_fixture.h>

#include "cube_part.h"
#include "projection_surfaces.h"
#include "wavy_face.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace shapespline::part {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr int kGpuPoints = 1000;
#else
constexpr int kGpuPoints = 10000;
#endif
// fp32: the tables and the queries are rounded to fp32 relative to the tree's centre (at most half
// the diagonal away), and Horner's sums of a bicubic add a few roundings more: 2^-24 of the diagonal
// each. 64 of them bound the distance's error with room for the Newton step's own rounding.
constexpr double kFloatDistance = 64.0 * 0x1p-24;

class ClosestPointsGpu : public test::VulkanTest {
 protected:
  // The GPU's feet and the CPU's for the same queries.
  void compare(const ProjectionTree& tree, const std::vector<glm::dvec3>& queries, Precision precision, bool signedDistance,
               const std::string& name) {
    const ClosestPoints cpu(tree);
    std::vector<FootPoint> expected(queries.size()), got(queries.size());
    cpu.of(queries, expected, signedDistance, 0);
    GpuClosestPoints gpu(cpu, ctx_, precision);
    gpu.of(queries, got, signedDistance, 0);
    // llvmpipe's loop limit sends the longest searches back to the CPU (gpu/closest_point_search.cpp).
    EXPECT_LE(gpu.redone(), queries.size() / 2) << name;
    const double diag = tree.diagonal();
    const bool fp64 = precision == Precision::Double;
    const double distanceBound = fp64 ? 1e-12 * diag : kFloatDistance * diag;
    int differ = 0, elsewhere = 0, sign = 0, offSurface = 0;
    for (size_t k = 0; k < queries.size(); ++k) {
      const FootPoint &e = expected[k], &g = got[k];
      if (std::abs(g.distance - e.distance) > distanceBound && ++differ <= 3)
        ADD_FAILURE() << name << ": q " << k << " GPU " << g.distance << " (face " << g.face << " at " << g.u << ", " << g.v
                      << (g.boundary ? ", boundary" : "") << ") CPU " << e.distance << " (face " << e.face << " at " << e.u
                      << ", " << e.v << (e.boundary ? ", boundary" : "") << ")";
      // The foot is where the distance says it is, and the surface's point at its parameters.
      EXPECT_NEAR(glm::length(g.point - queries[k]), g.distance, 1e-12 * diag);
      if (!tree.faces().empty()) {
        const Surface* face = nullptr;
        for (const ProjectionFace& f : tree.faces())
          if (f.id == g.face) face = f.surface;
        if (face && glm::length(face->evaluateAt(g.u, g.v).point - g.point) > distanceBound && ++offSurface <= 3)
          ADD_FAILURE() << name << ": q " << k << " GPU foot " << g.u << ", " << g.v << " is not the surface's point there";
      }
      if (signedDistance && std::abs(e.signedDistance) > distanceBound && (g.signedDistance > 0) != (e.signedDistance > 0))
        ++sign;
      // fp64: the same place. Off the surface the distance is flat to its rounding near the foot,
      // so where Newton's last steps are not trusted (docs/math.md) either path's parameters are
      // good to a few 1e-9 of the patch, the feet to 1e-8 of the diagonal and the normal, turned
      // by the curvature over that, to 1e-7; at a tie (a point over an edge two faces share) the
      // face may differ but the point does not.
      const bool samePlace = glm::length(g.point - e.point) <= 1e-8 * diag;
      const bool sameFoot = g.face != e.face || glm::length(g.normal - e.normal) <= 1e-7;
      if (fp64 && (!samePlace || !sameFoot) && ++elsewhere <= 3)
        ADD_FAILURE() << name << ": q " << k << " GPU " << g.distance << " (face " << g.face << " at " << g.u << ", " << g.v
                      << (g.boundary ? ", boundary" : "") << ") CPU " << e.distance << " (face " << e.face << " at " << e.u
                      << ", " << e.v << (e.boundary ? ", boundary" : "") << ")";
    }
    EXPECT_EQ(differ, 0) << name << ": distances off the CPU's";
    EXPECT_EQ(elsewhere, 0) << name << ": feet at another face, parameters or normal";
    EXPECT_EQ(sign, 0) << name << ": signs off the CPU's";
    EXPECT_EQ(offSurface, 0) << name << ": feet off the surface";
  }

  void compareSurface(const Surface& s, Precision precision, const std::string& name) {
    const ProjectionTree tree = ProjectionTree::ofFaces({{&s, 0, false}});
    Queries q = queriesFor(s, tree.diagonal(), kGpuPoints, 11);
    compare(tree, q.on, precision, false, name + " (on)");
    compare(tree, q.off, precision, false, name + " (off)");
  }
};

TEST_F(ClosestPointsGpu, Fp64FreeFormSurfacesMatchTheCpu) {
  compareSurface(wavyNurbs(), Precision::Double, "wavy NURBS");
  compareSurface(halfCylinder(), Precision::Double, "half cylinder");
  compareSurface(xuWangSurface(), Precision::Double, "Xu-Wang");
}

TEST_F(ClosestPointsGpu, Fp32FreeFormSurfacesAreWithinTheFloatBound) {
  compareSurface(wavyNurbs(), Precision::Float, "wavy NURBS");
  compareSurface(halfCylinder(), Precision::Float, "half cylinder");
  compareSurface(xuWangSurface(), Precision::Float, "Xu-Wang");
}

// Trim loops: feet over the hole and beyond the border lie on the loops, on both paths.
TEST_F(ClosestPointsGpu, TrimmedFaceMatchesTheCpu) {
  const Surface s = wavyFace({{{0.05, 0.05}, {0.95, 0.05}, {0.95, 0.95}, {0.05, 0.95}},
                              {{0.3, 0.3}, {0.7, 0.3}, {0.7, 0.7}, {0.3, 0.7}}});
  const ProjectionTree tree = ProjectionTree::ofFaces({{&s, 7, false}});
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> x(-0.1, 1.1), z(-0.6, 0.6);
  std::vector<glm::dvec3> queries;
  for (int k = 0; k < kGpuPoints; ++k) queries.push_back({x(rng), x(rng), z(rng)});
  compare(tree, queries, Precision::Double, false, "trimmed face fp64");
  compare(tree, queries, Precision::Float, false, "trimmed face fp32");
}

// A part: the cube's faces (ids and the sign at edges and corners).
TEST_F(ClosestPointsGpu, CubeMatchesTheCpuWithSigns) {
  const std::filesystem::path dir = test::processTempFile("closest_gpu", "cube");
  writeCube(dir, 2.0);
  const Part part = loadPart(dir / "part.json");
  const ProjectionTree tree = ProjectionTree::ofPart(part);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> x(-1.0, 3.0);
  std::vector<glm::dvec3> queries;
  for (int k = 0; k < kGpuPoints / 4; ++k) queries.push_back({x(rng), x(rng), x(rng)});
  compare(tree, queries, Precision::Double, true, "cube fp64");
  compare(tree, queries, Precision::Float, true, "cube fp32");
}

TEST_F(ClosestPointsGpu, CurvesAreRefused) {
  CurveModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 3;
  m.dimension = 3;
  m.knots = {0, 0, 0, 1, 1, 1};
  m.points = {{0, 0, 0}, {1, 1, 0}, {2, 0, 0}};
  const Curve c = Curve::create(std::move(m));
  const ProjectionTree tree = ProjectionTree::ofCurve(c);
  const ClosestPoints cpu(tree);
  EXPECT_THROW(GpuClosestPoints(cpu, ctx_, Precision::Float), std::invalid_argument);
}

}  // namespace
}  // namespace shapespline::part
