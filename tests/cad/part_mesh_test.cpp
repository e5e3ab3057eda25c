// The part mesher (host/part) on the parts tests/cad makes with Open CASCADE (issue 54): imported,
// meshed at a deflection of 1e-3 and 1e-4 of the part's diagonal, and checked against OCCT: closed
// shells closed, manifold and wound outwards (the enclosed volume is OCCT's within area x
// deflection), every triangle's centroid and edge midpoints within the deflection of the face's
// own OCCT surface (projected with GeomAPI_ProjectPointOnSurf), and at most 1.5 x the triangles of
// BRepMesh_IncrementalMesh at the same deflection and angle. Open3D checks the PLY the CLI writes.
// The part headers first: they bring the Vulkan headers, whose vk::Handle must not meet OCCT's
// macro `Handle`.
#include <shapespline/part/part_mesher.h>
#include <shapespline/part/part_model.h>

#include "test_parts.h"

#include <cli/cli_runner.h>

#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/part_import.h>

#include <BRepGProp.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <sstream>
#include <unistd.h>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

fs::path scratch() {
  static const fs::path root = [] {
    fs::path p = fs::temp_directory_path() / ("shapespline_part_mesh_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
  }();
  return root;
}

// NAME imported from STEP: its folder.
fs::path imported(const TestPart& part) {
  const fs::path step = scratch() / (part.name + ".step"), dir = scratch() / part.name;
  if (!fs::exists(dir / "part.json")) {
    writeStep(part.shape, step);
    cad::importPart(step, dir);
  }
  return dir;
}

// Triangles of OCCT's own mesher at the same absolute deflection and angle (InParallel).
size_t brepMeshTriangles(const TopoDS_Shape& shape, double deflection, double angle) {
  const TopoDS_Shape copy = shape;  // BRepMesh stores its triangulation in the shape's faces
  BRepMesh_IncrementalMesh mesher(copy, deflection, false, angle, true);
  size_t triangles = 0;
  for (TopExp_Explorer f(copy, TopAbs_FACE); f.More(); f.Next()) {
    TopLoc_Location location;
    const Handle(Poly_Triangulation) t = BRep_Tool::Triangulation(TopoDS::Face(f.Current()), location);
    if (!t.IsNull()) triangles += static_cast<size_t>(t->NbTriangles());
  }
  return triangles;
}

bool closedShell(const std::string& name) { return name != "free_form"; }

class PartMesh : public ::testing::TestWithParam<double> {};

TEST_P(PartMesh, ClosedOrientedAndWithinTheDeflectionOfOcct) {
  const double relative = GetParam();
  for (const TestPart& test : allTestParts()) {
    SCOPED_TRACE(test.name);
    const part::Part part = part::loadPart(imported(test) / "part.json");
    // OCCT's side: the part as read back from the STEP file (its faces in the order of the ids).
    const TopoDS_Shape shape = cad::readPart(scratch() / (test.name + ".step"), std::uint64_t{1} << 30).shape;
    const double diagonal = part::partDiagonal(part);
    part::MeshOptions options;
    options.deflection = relative * diagonal;
    options.angle = 0.5;
    part::CpuFaceEvaluator cpu;
    const part::PartMesh mesh = part::meshPart(part, options, cpu);
    const io::TriangleMesh& m = mesh.mesh;
    ASSERT_FALSE(m.triangles.empty());

    // Closed: every edge once each way; outward: the volume is OCCT's.
    if (closedShell(test.name)) {
      EXPECT_EQ(mesh.boundaryEdges, 0);
      EXPECT_EQ(mesh.nonManifoldEdges, 0);
      std::map<std::pair<uint32_t, uint32_t>, int> directed;
      for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++directed[{t[size_t(k)], t[size_t((k + 1) % 3)]}];
      int unpaired = 0, doubled = 0;
      for (const auto& [e, n] : directed) {
        doubled += n > 1;
        unpaired += !directed.count({e.second, e.first});
      }
      EXPECT_EQ(unpaired, 0);
      EXPECT_EQ(doubled, 0);
      double volume = 0.0, area = 0.0;
      for (const auto& t : m.triangles) {
        volume += glm::dot(m.positions[t[0]], glm::cross(m.positions[t[1]], m.positions[t[2]])) / 6.0;
        area += 0.5 * glm::length(glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
      }
      GProp_GProps props;
      BRepGProp::VolumeProperties(shape, props);
      EXPECT_NEAR(volume, props.Mass(), area * options.deflection);
    }

    // Within the deflection: centroids and edge midpoints projected onto the face's OCCT surface.
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(shape, TopAbs_FACE, faces);
    double worst = 0.0;
    int zeroArea = 0;
    const size_t step = std::max<size_t>(1, m.triangles.size() / 400);
    for (size_t k = 0; k < m.triangles.size(); ++k) {
      const auto& t = m.triangles[k];
      const glm::dvec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
      zeroArea += !(glm::length(glm::cross(b - a, c - a)) > 0.0);
      if (k % step) continue;
      const Handle(Geom_Surface) surface = BRep_Tool::Surface(TopoDS::Face(faces(m.faceIds[k])));
      for (const glm::dvec3 q : {(a + b + c) / 3.0, (a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0}) {
        GeomAPI_ProjectPointOnSurf projection(gp_Pnt(q.x, q.y, q.z), surface);
        ASSERT_GT(projection.NbPoints(), 0);
        worst = std::max(worst, projection.LowerDistance());
      }
    }
    EXPECT_EQ(zeroArea, 0);
    EXPECT_LE(worst, options.deflection * (1 + 1e-9));

    // As many triangles as BRepMesh's at the same deflection and angle, within half again.
    const size_t occt = brepMeshTriangles(shape, options.deflection, options.angle);
    EXPECT_LE(double(m.triangles.size()), 1.5 * double(occt));
    std::printf("[ part mesh ] %-10s rel %.0e: %zu triangles (BRepMesh %zu, ratio %.2f), deviation %.3g of D\n",
                test.name.c_str(), relative, m.triangles.size(), occt, double(m.triangles.size()) / double(occt),
                worst / options.deflection);
  }
}

INSTANTIATE_TEST_SUITE_P(Deflections, PartMesh, ::testing::Values(1e-3, 1e-4));

// `sample part.json -o part.ply` as a user runs it, on Vulkan (the CPU with a notice where there is
// none) and on the CPU (also `auto`'s choice for meshes): Open3D finds each closed part's mesh
// watertight, orientable and edge-manifold, and the two devices give the same triangles.
TEST(PartMeshCli, Open3dFindsEveryClosedPartWatertightOnEveryDevice) {
  if (const std::string why = open3dMissing(); !why.empty()) GTEST_FAIL() << why;
  std::string files;
  for (const TestPart& test : allTestParts()) {
    if (!closedShell(test.name)) continue;
    const fs::path dir = imported(test);
    for (const std::string device : {"vulkan", "cpu"}) {
      const fs::path out = scratch() / (test.name + "_" + device + ".ply");
      const CliResult r = runCli("sample " + quote((dir / "part.json").string()) + " --device " + device + " -o " +
                                     quote(out.string()),
                                 scratch());
      ASSERT_EQ(r.rc, 0) << r.err;
      EXPECT_NE(r.err.find(" 0 open edges"), std::string::npos) << r.err;
    }
    files += " " + quote((scratch() / (test.name + "_vulkan.ply")).string()) + " " +
             quote((scratch() / (test.name + "_cpu.ply")).string());
  }
  const ToolResult checks = runTool(std::string(kSystemPython) + " -c \"import sys, numpy as np, open3d as o3d\n"
                                    "for a, b in zip(sys.argv[1::2], sys.argv[2::2]):\n"
                                    "  m, c = o3d.io.read_triangle_mesh(a), o3d.io.read_triangle_mesh(b)\n"
                                    "  same = np.array_equal(np.asarray(m.triangles), np.asarray(c.triangles))\n"
                                    "  print(len(m.triangles) > 0, m.is_watertight(), m.is_orientable(), "
                                    "m.is_edge_manifold(), same)\n\"" +
                                    files);
  ASSERT_EQ(checks.rc, 0) << checks.out;
  size_t parts = 0;
  std::istringstream lines(checks.out);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("True") == std::string::npos && line.find("False") == std::string::npos) continue;  // Open3D's notes
    ++parts;
    EXPECT_EQ(line, "True True True True True") << "non-empty, watertight, orientable, edge-manifold, same on both "
                                                   "devices: " << checks.out;
  }
  EXPECT_EQ(parts, allTestParts().size() - 1) << checks.out;
}

}  // namespace
}  // namespace shapespline::test
