// The part mesher on parts written here, without Open CASCADE: a unit cube of six planar faces (its
// welding, orientation and watertightness exactly) and a wavy trimmed bicubic face (the deflection,
// measured by projecting the mesh back onto the surface). tests/cad/ meshes real OCCT parts.
#include <shapespline/core/list_eval.h>
#include <shapespline/core/model.h>
#include <shapespline/core/trim_classifier.h>
#include <shapespline/part/face_triangulation.h>
#include <shapespline/part/part_mesher.h>
#include <shapespline/part/part_model.h>
#include <shapespline/part/shaded_mesh.h>

#include <support/temp_files.h>

#include "cube_part.h"
#include "wavy_face.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <set>

namespace shapespline::part {
namespace {

using nlohmann::json;

// Every mesh edge used by exactly two triangles, once each way: closed, manifold, consistently wound.
void expectClosedAndOriented(const io::TriangleMesh& mesh) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[size_t(k)], t[size_t((k + 1) % 3)]}];
  for (const auto& [edge, n] : directed) {
    EXPECT_EQ(n, 1) << "edge " << edge.first << "-" << edge.second << " is wound the same way twice";
    EXPECT_TRUE(directed.count({edge.second, edge.first})) << "edge " << edge.first << "-" << edge.second << " is open";
  }
}

double signedVolume(const io::TriangleMesh& mesh) {
  double six = 0.0;
  for (const auto& t : mesh.triangles)
    six += glm::dot(mesh.positions[t[0]], glm::cross(mesh.positions[t[1]], mesh.positions[t[2]]));
  return six / 6.0;
}

TEST(PartMesher, CubeIsTwelveTrianglesOnEightSharedVertices) {
  const std::filesystem::path dir = test::processTempFile("part", "cube");
  writeCube(dir, 2.0);
  const Part part = loadPart(dir / "part.json");
  ASSERT_EQ(part.faces.size(), 6u);
  CpuFaceEvaluator cpu;
  MeshOptions options;
  options.deflection = 1e-3;
  const PartMesh mesh = meshPart(part, options, cpu);
  EXPECT_EQ(mesh.mesh.positions.size(), 8u);
  EXPECT_EQ(mesh.mesh.triangles.size(), 12u);
  EXPECT_EQ(mesh.boundaryEdges, 0);
  EXPECT_EQ(mesh.nonManifoldEdges, 0);
  EXPECT_EQ(mesh.edges, 12);
  expectClosedAndOriented(mesh.mesh);
  EXPECT_NEAR(signedVolume(mesh.mesh), 8.0, 1e-12);  // positive: every face wound outwards
  std::map<int, int> perFace;
  for (int f : mesh.mesh.faceIds) ++perFace[f];
  EXPECT_EQ(perFace.size(), 6u);
  for (const auto& [f, n] : perFace) EXPECT_EQ(n, 2) << "face " << f;
}

// The picture's mesh of the cube: each face on 4 vertices of its own with the face's own normal
// (the welded mean would be a corner's diagonal), and the 12 cube edges as lines.
TEST(PartMesher, ShadedCubeKeepsEachFacesNormalAndDrawsItsTwelveEdges) {
  const std::filesystem::path dir = test::processTempFile("part", "shaded_cube");
  writeCube(dir, 2.0);
  const Part part = loadPart(dir / "part.json");
  CpuFaceEvaluator cpu;
  MeshOptions options;
  options.deflection = 1e-3;
  EXPECT_THROW(shadedMesh(meshPart(part, options, cpu)), std::invalid_argument);
  options.cornerNormals = true;
  const PartMesh mesh = meshPart(part, options, cpu);
  const ShadedMesh shaded = shadedMesh(mesh);
  ASSERT_EQ(shaded.positions.size(), 24u);
  ASSERT_EQ(shaded.triangles.size(), 36u);
  EXPECT_EQ(shaded.faceIds, mesh.mesh.faceIds);
  for (size_t t = 0; t < 12; ++t) {
    const glm::vec3 a = shaded.positions[shaded.triangles[3 * t]], b = shaded.positions[shaded.triangles[3 * t + 1]],
                    c = shaded.positions[shaded.triangles[3 * t + 2]];
    const glm::vec3 outward = glm::normalize(glm::cross(b - a, c - a));
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(glm::dot(shaded.normals[shaded.triangles[3 * t + j]], outward), 1.0f, 1e-6f);
  }
  ASSERT_EQ(shaded.edgeLines.size(), 24u);
  // Each line is a whole cube edge: two coordinates shared, the third 2 apart.
  for (size_t l = 0; l < 12; ++l) {
    const glm::vec3 d = glm::abs(shaded.positions[shaded.edgeLines[2 * l]] - shaded.positions[shaded.edgeLines[2 * l + 1]]);
    EXPECT_FLOAT_EQ(d.x + d.y + d.z, 2.0f);
    EXPECT_FLOAT_EQ(std::max({d.x, d.y, d.z}), 2.0f);
  }
}

TEST(PartMesher, RefusesAFaceWithoutCoedges) {
  const std::filesystem::path dir = test::processTempFile("part", "old");
  writeCube(dir, 1.0);
  json manifest = json::parse(std::ifstream(dir / "part.json"));
  manifest["faces"][2].erase("coedges");
  writeJson(dir / "part.json", manifest);
  CpuFaceEvaluator cpu;
  MeshOptions options;
  options.deflection = 1e-3;
  try {
    meshPart(loadPart(dir / "part.json"), options, cpu);
    FAIL() << "a face without coedges was meshed";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "faces[2].coedges");
  }
}

// The foot of p on the surface: the nearest of a grid, then Newton on |S(u,v) - p|^2 (the test's
// own projection: a wavy face of 4 x 4 bicubic spans has one minimum near its grid's best).
struct Foot {
  double distance;
  glm::dvec2 uv;
};
Foot footOnSurface(const Surface& s, glm::dvec3 p) {
  constexpr int n = 48;
  double best = INFINITY;
  glm::dvec2 uv(0.0);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double d = glm::length(s.evaluateAt(double(i) / n, double(j) / n).point - p);
      if (d < best) best = d, uv = {double(i) / n, double(j) / n};
    }
  for (int it = 0; it < 30; ++it) {
    const SurfacePoint q = s.evaluateAt(uv.x, uv.y);
    const glm::dvec3 r = q.point - p;
    const double a = glm::dot(q.du, q.du) + glm::dot(r, q.duu), b = glm::dot(q.du, q.dv) + glm::dot(r, q.duv),
                 c = glm::dot(q.dv, q.dv) + glm::dot(r, q.dvv);
    const double gu = glm::dot(r, q.du), gv = glm::dot(r, q.dv), det = a * c - b * b;
    if (det == 0.0) break;
    uv = glm::clamp(uv - glm::dvec2(c * gu - b * gv, a * gv - b * gu) / det, 0.0, 1.0);
  }
  return {std::min(best, glm::length(s.evaluateAt(uv.x, uv.y).point - p)), uv};
}

TEST(PartMesher, TrimmedFaceIsWithinTheDeflection) {
  const std::vector<std::vector<glm::dvec2>> loops = {{{0.05, 0.05}, {0.95, 0.05}, {0.95, 0.95}, {0.05, 0.95}},
                                                     {{0.4, 0.4}, {0.4, 0.6}, {0.6, 0.6}, {0.6, 0.4}}};
  Part part = faceAsPart("wavy.json", wavyFace(loops));
  const Surface& surface = part.faces.front().surface;
  CpuFaceEvaluator cpu;
  for (double deflection : {1e-2, 1e-3}) {
    MeshOptions options;
    options.deflection = deflection;
    const PartMesh mesh = meshPart(part, options, cpu);
    SCOPED_TRACE("deflection " + std::to_string(deflection) + ", " + std::to_string(mesh.mesh.triangles.size()) +
                 " triangles");
    EXPECT_EQ(mesh.nonManifoldEdges, 0);
    EXPECT_GT(mesh.boundaryEdges, 8);  // the two loops, cut to the deflection
    // No two vertices at one point: the refinement converges instead of piling points up (as it
    // did on the slivers three loop vertices along a straight side make).
    std::set<std::array<double, 3>> places;
    for (const glm::dvec3& p : mesh.mesh.positions)
      places.insert({std::round(p.x * 1e11), std::round(p.y * 1e11), std::round(p.z * 1e11)});
    EXPECT_EQ(places.size(), mesh.mesh.positions.size());
    double worst = 0.0;
    const TrimClassifier inside(surface.model().trim);
    const size_t step = std::max<size_t>(1, mesh.mesh.triangles.size() / 300);
    for (size_t k = 0; k < mesh.mesh.triangles.size(); k += step) {
      const auto& t = mesh.mesh.triangles[k];
      const glm::dvec3 a = mesh.mesh.positions[t[0]], b = mesh.mesh.positions[t[1]], c = mesh.mesh.positions[t[2]];
      EXPECT_GT(glm::length(glm::cross(b - a, c - a)), 0.0) << "triangle " << k << " has no area";
      for (glm::dvec3 q : {(a + b + c) / 3.0, (a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0})
        worst = std::max(worst, footOnSurface(surface, q).distance);
      // Inside the loops only: the centroid's foot is inside, or (a boundary chord leaves the
      // surface by up to the deflection) within the deflection of a loop, in parameters as in space
      // on this face whose speed is about 1 to 2.
      const glm::dvec2 foot = footOnSurface(surface, (a + b + c) / 3.0).uv;
      double nearest = INFINITY;
      for (const auto& loop : surface.model().trim.loops)
        for (size_t j = 0; j < loop.size(); ++j)
          nearest = std::min(nearest, distanceToSegment(foot, loop[j], loop[(j + 1) % loop.size()]));
      EXPECT_TRUE(inside.inside(foot) || nearest <= deflection)
          << "triangle " << k << " at (" << foot.x << ", " << foot.y << "), " << nearest << " from a loop";
    }
    EXPECT_LE(worst, deflection);
    EXPECT_GT(worst, deflection / 20) << "the mesh is far finer than asked";
  }
}

// A bicubic face over [0, 1]^2, a quarter of a bowl, whose side u = 0 is drawn to (nearly) a
// point: its first row of control points on a circle of radius `apexRadius` (0: one point).
Surface apexFace(double apexRadius) {
  SurfaceModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 4;
  m.orderV = 4;
  m.knotsU = m.knotsV = {0, 0, 0, 0, 1, 1, 1, 1};
  m.rows = m.cols = 4;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const double r = i == 0 ? apexRadius : i / 3.0, a = 1.5 * j / 3.0;
      m.points.push_back({r * std::cos(a), r * std::sin(a), 0.4 * r * r});
    }
  m.trim.loops = {{{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}}};
  m.trim.tolerance = 1e-9;
  return Surface::create(std::move(m));
}

// A bicubic face whose whole side u = 0 is one point (a cone's apex drawn as a B-spline, its edge
// not marked degenerate): the points the refinement puts at the apex are the apex's one vertex,
// and no triangle is left without area.
TEST(PartMesher, ASideDrawnToAPointLeavesNoTriangleWithoutArea) {
  const Part part = faceAsPart("apex.json", apexFace(0.0));
  CpuFaceEvaluator cpu;
  MeshOptions options;
  options.deflection = 1e-4;
  const PartMesh mesh = meshPart(part, options, cpu);
  ASSERT_GT(mesh.mesh.triangles.size(), 50u);
  EXPECT_EQ(mesh.nonManifoldEdges, 0);
  size_t atApex = 0;
  for (const glm::dvec3& p : mesh.mesh.positions) atApex += glm::length(p) <= 1e-12;
  EXPECT_EQ(atApex, 1u);
  for (const auto& t : mesh.mesh.triangles) {
    const glm::dvec3 a = mesh.mesh.positions[t[0]], b = mesh.mesh.positions[t[1]], c = mesh.mesh.positions[t[2]];
    ASSERT_GT(glm::length(glm::cross(b - a, c - a)), 0.0);
  }
}

// The same face with its apex row spread over 1e-7 (a side drawn nearly to a point, as real parts
// have): refinement near the spot does not fold the mesh. No two triangles that share an edge face
// opposite ways, and no triangle is without area.
TEST(PartMesher, ASideDrawnNearlyToAPointFoldsNothing) {
  const Part part = faceAsPart("near_apex.json", apexFace(1e-7));
  CpuFaceEvaluator cpu;
  MeshOptions options;
  options.deflection = 1e-4;
  const PartMesh mesh = meshPart(part, options, cpu);
  EXPECT_EQ(mesh.nonManifoldEdges, 0);
  const auto& p = mesh.mesh.positions;
  std::map<std::pair<uint32_t, uint32_t>, glm::dvec3> normalBeside;  // by directed edge
  for (const auto& t : mesh.mesh.triangles) {
    const glm::dvec3 n = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
    ASSERT_GT(glm::length(n), 0.0);
    for (int k = 0; k < 3; ++k) normalBeside[{t[size_t(k)], t[size_t((k + 1) % 3)]}] = glm::normalize(n);
  }
  size_t folds = 0;
  for (const auto& [edge, n] : normalBeside) {
    const auto other = normalBeside.find({edge.second, edge.first});
    folds += other != normalBeside.end() && glm::dot(n, other->second) < -0.5;
  }
  EXPECT_EQ(folds, 0u);
}

TEST(PartMesher, CrossingLoopsAndTheBudgetAreRefused) {
  CpuFaceEvaluator cpu;
  MeshOptions options;
  options.deflection = 1e-3;
  Part crossing = faceAsPart("bow.json", wavyFace({{{0.1, 0.1}, {0.9, 0.7}, {0.9, 0.1}, {0.1, 0.9}}}));
  EXPECT_THROW(meshPart(crossing, options, cpu), ModelError);
  Part fine = faceAsPart("wavy.json", wavyFace({{{0.1, 0.1}, {0.9, 0.1}, {0.9, 0.9}, {0.1, 0.9}}}));
  options.deflection = 1e-6;
  options.maxTriangles = 1000;
  EXPECT_THROW(meshPart(fine, options, cpu), TriangleBudgetExceeded);
}

}  // namespace
}  // namespace shapespline::part
