// `shapespline import` against Open CASCADE (issue 32): parts made here with OCCT, written to STEP
// and IGES, imported, and every face's model evaluated by shapespline against OCCT's own
// evaluation of the B-spline it converted the face to (Geom_BSplineSurface::D1), and against the
// face's original surface through the parameter map; trimming loops against the part's geometry.
#include "test_parts.h"

#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/parameter_map.h>
#include <shapespline/cad/part_import.h>
#include <shapespline/cad/trim_loops.h>
#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/model_json.h>

#include <TopExp.hxx>
#include <TopLoc_Location.hxx>
#include <gp_Trsf.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <random>
#include <unistd.h>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Points: 1e-12 of the face's size (fp64 evaluation of the same B-spline). Derivatives: the same
// relative bound on size / parameter span, the scale of a first derivative.
constexpr double kRelativeTolerance = 1e-12;
constexpr int kSamplesPerFace = 10000;

fs::path scratchRoot() {
  static const fs::path root = [] {
    fs::path p = fs::temp_directory_path() / ("shapespline_cad_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
  }();
  return root;
}

// The test parts, written once per process: NAME.step and NAME.iges.
const fs::path& partFiles() {
  static const fs::path dir = [] {
    fs::path d = scratchRoot() / "parts";
    fs::create_directories(d);
    for (const TestPart& p : allTestParts()) {
      writeStep(p.shape, d / (p.name + ".step"));
      writeIges(p.shape, d / (p.name + ".iges"));
    }
    return d;
  }();
  return dir;
}

json readJson(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

double boxDiagonal(const std::vector<glm::dvec3>& points) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const glm::dvec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

glm::dvec3 vec(const gp_XYZ& p) { return {p.X(), p.Y(), p.Z()}; }

struct Imported {
  fs::path part, dir;
  json manifest;
  cad::PartShape shape;  // the same file read again, for OCCT's side
  TopTools_IndexedMapOfShape faces, edges;
};

Imported importOnce(const std::string& name, const std::string& format) {
  Imported r;
  r.part = partFiles() / (name + "." + format);
  r.dir = scratchRoot() / (name + "_" + format);
  cad::importPart(r.part, r.dir);
  r.manifest = readJson(r.dir / "part.json");
  r.shape = cad::readPart(r.part, std::uint64_t{1} << 30);
  TopExp::MapShapes(r.shape.shape, TopAbs_FACE, r.faces);
  TopExp::MapShapes(r.shape.shape, TopAbs_EDGE, r.edges);
  return r;
}

class ImportPart : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

TEST_P(ImportPart, EveryFaceEvaluatesAsOcctDoes) {
  const auto& [name, format] = GetParam();
  const Imported imp = importOnce(name, format);
  const json& faces = imp.manifest.at("faces");
  ASSERT_EQ(static_cast<int>(faces.size()), imp.faces.Extent());
  ASSERT_GT(faces.size(), 0u);
  std::mt19937_64 random(20261204);
  for (const json& entry : faces) {
    const int id = entry.at("id").get<int>();
    SCOPED_TRACE("face " + std::to_string(id) + " " + entry.value("surface", std::string()));
    ASSERT_FALSE(entry.at("model").is_null()) << entry.dump();
    const SurfaceModel model = std::get<SurfaceModel>(io::loadModelFile(imp.dir / entry.at("model").get<std::string>()));
    const Surface surface = Surface::create(model);
    const cad::ConvertedFace ref = cad::convertFace(TopoDS::Face(imp.faces(id)), 1e-5);
    double a0, a1, b0, b1;
    ref.bspline->Bounds(a0, a1, b0, b1);
    const double size = boxDiagonal(model.points);
    const double pointTolerance = kRelativeTolerance * size;
    const double duTolerance = pointTolerance / (a1 - a0), dvTolerance = pointTolerance / (b1 - b0);
    std::uniform_real_distribution<double> U(a0, a1), V(b0, b1);
    double worstPoint = 0.0, worstDu = 0.0, worstDv = 0.0;
    for (int k = 0; k < kSamplesPerFace; ++k) {
      const double u = U(random), v = V(random);
      gp_Pnt p;
      gp_Vec du, dv;
      ref.bspline->D1(u, v, p, du, dv);
      const SurfacePoint ours = surface.evaluateAt(u, v);
      worstPoint = std::max(worstPoint, glm::length(ours.point - vec(p.XYZ())));
      worstDu = std::max(worstDu, glm::length(ours.du - vec(du.XYZ())));
      worstDv = std::max(worstDv, glm::length(ours.dv - vec(dv.XYZ())));
    }
    EXPECT_LE(worstPoint, pointTolerance);
    EXPECT_LE(worstDu, duTolerance);
    EXPECT_LE(worstDv, dvTolerance);

    // The face's own surface (a cylinder's angle, a sphere's latitude) through the parameter map.
    const cad::ParameterMap map(ref.source, ref.bounds, ref.bspline);
    std::uniform_real_distribution<double> Us(ref.bounds[0], ref.bounds[1]), Vs(ref.bounds[2], ref.bounds[3]);
    double worstSource = 0.0;
    for (int k = 0; k < 200; ++k) {
      const double u = Us(random), v = Vs(random);
      const glm::dvec2 q = map(u, v);
      worstSource = std::max(worstSource, glm::length(surface.evaluateAt(q.x, q.y).point - vec(ref.source->Value(u, v).XYZ())));
    }
    EXPECT_LE(worstSource, 1e-9 * size);

    // Trimming loops: the outer one counter-clockwise, holes clockwise.
    ASSERT_FALSE(model.trim.empty());
    EXPECT_EQ(entry.at("loops").get<size_t>(), model.trim.loops.size());
    EXPECT_GT(cad::signedArea(model.trim.loops[0]), 0.0);
    for (size_t l = 1; l < model.trim.loops.size(); ++l) EXPECT_LT(cad::signedArea(model.trim.loops[l]), 0.0) << "loop " << l;
  }
}

TEST_P(ImportPart, EveryEdgeEvaluatesAsOcctDoes) {
  const auto& [name, format] = GetParam();
  const Imported imp = importOnce(name, format);
  std::mt19937_64 random(7);
  int curves = 0;
  for (const json& entry : imp.manifest.at("edges")) {
    const int id = entry.at("id").get<int>();
    SCOPED_TRACE("edge " + std::to_string(id));
    if (entry.value("degenerate", false)) continue;
    ASSERT_FALSE(entry.at("model").is_null()) << entry.dump();
    const CurveModel model = std::get<CurveModel>(io::loadModelFile(imp.dir / entry.at("model").get<std::string>()));
    const Curve curve = Curve::create(model);
    const cad::ConvertedEdge ref = cad::convertEdge(TopoDS::Edge(imp.edges(id)));
    const double size = std::max(boxDiagonal(model.points), 1e-300);
    std::uniform_real_distribution<double> U(ref.bspline->FirstParameter(), ref.bspline->LastParameter());
    for (int k = 0; k < 200; ++k) {
      const double u = U(random);
      gp_Pnt p;
      gp_Vec d1;
      ref.bspline->D1(u, p, d1);
      const CurvePoint ours = curve.evaluateAt(u);
      ASSERT_LE(glm::length(ours.point - vec(p.XYZ())), kRelativeTolerance * size) << "u " << u;
      ASSERT_LE(glm::length(ours.d1 - vec(d1.XYZ())),
                kRelativeTolerance * size / (ref.bspline->LastParameter() - ref.bspline->FirstParameter()))
          << "u " << u;
    }
    ++curves;
  }
  EXPECT_GT(curves, 0);
}

// The drilled plate's top and bottom faces: three loops each. Every point of the two inner loops,
// evaluated on the imported surface, lies on a hole's circle; every point of the outer loop on the
// plate's rectangle. (The loop points are exact points of the edges' curves on the face, so the
// bound is the evaluation's, not the polyline tolerance.)
TEST(ImportTrim, DrilledPlateHolesAreTheInnerLoops) {
  for (const char* format : {"step", "iges"}) {
    SCOPED_TRACE(format);
    const Imported imp = importOnce("drilled_plate", format);
    int drilledFaces = 0;
    for (const json& entry : imp.manifest.at("faces")) {
      if (entry.at("loops").get<int>() != 3) continue;
      ++drilledFaces;
      const SurfaceModel model = std::get<SurfaceModel>(io::loadModelFile(imp.dir / entry.at("model").get<std::string>()));
      const Surface surface = Surface::create(model);
      const double tolerance = 1e-9 * 100.0;
      for (const glm::dvec2& q : model.trim.loops[0]) {
        const glm::dvec3 p = surface.evaluateAt(q.x, q.y).point;
        const double toRectangle = std::min({std::abs(p.x), std::abs(p.x - 100.0), std::abs(p.y), std::abs(p.y - 60.0)});
        ASSERT_LE(toRectangle, tolerance) << p.x << ", " << p.y;
      }
      for (size_t l = 1; l < 3; ++l) {
        double nearestHoleX = 0.0;
        for (const glm::dvec2& q : model.trim.loops[l]) {
          const glm::dvec3 p = surface.evaluateAt(q.x, q.y).point;
          double best = 1e300;
          for (const Hole& h : drilledPlateHoles()) {
            const double d = std::abs(std::hypot(p.x - h.x, p.y - h.y) - h.radius);
            if (d < best) best = d, nearestHoleX = h.x;
          }
          ASSERT_LE(best, tolerance) << "loop " << l << ": " << p.x << ", " << p.y;
        }
        EXPECT_TRUE(nearestHoleX == 30.0 || nearestHoleX == 70.0);
      }
    }
    EXPECT_EQ(drilledFaces, 2);
  }
}

// A placed part (an assembly's instance): the cylinder turned 90 degrees about x and moved by
// (10, 20, 30). STEP carries the placement; import applies it, so the side face's points lie at
// radius 5 about the moved axis (through (10, 20, 30), along -y), between y = 20 - 12 and 20.
TEST(ImportPlacement, PlacementsAreApplied) {
  gp_Trsf turn, move;
  turn.SetRotation(gp::OX(), M_PI / 2);
  move.SetTranslation(gp_Vec(10.0, 20.0, 30.0));
  const TopoDS_Shape placed = cylinder().Moved(TopLoc_Location(move * turn));
  const fs::path dir = scratchRoot() / "placed";
  fs::create_directories(dir);
  writeStep(placed, dir / "placed.step");
  cad::importPart(dir / "placed.step", dir / "out");
  const json manifest = readJson(dir / "out" / "part.json");
  int sides = 0;
  for (const json& entry : manifest.at("faces")) {
    if (entry.at("surface") != "Geom_CylindricalSurface") continue;
    ++sides;
    const SurfaceModel model = std::get<SurfaceModel>(io::loadModelFile(dir / "out" / entry.at("model").get<std::string>()));
    const Surface surface = Surface::create(model);
    const auto [a0, a1] = surface.parameterRangeU();
    const auto [b0, b1] = surface.parameterRangeV();
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 10; ++j) {
        const glm::dvec3 p = surface.evaluateAt(a0 + (a1 - a0) * i / 10, b0 + (b1 - b0) * j / 10).point;
        ASSERT_NEAR(std::hypot(p.x - 10.0, p.z - 30.0), 5.0, 1e-12 * 20.0) << p.x << ", " << p.y << ", " << p.z;
        ASSERT_GE(p.y, 20.0 - 12.0 - 1e-12 * 20.0);
        ASSERT_LE(p.y, 20.0 + 1e-12 * 20.0);
      }
  }
  EXPECT_EQ(sides, 1);
}

std::string caseName(const ::testing::TestParamInfo<ImportPart::ParamType>& info) {
  return std::get<0>(info.param) + "_" + std::get<1>(info.param);
}

INSTANTIATE_TEST_SUITE_P(Parts, ImportPart,
                         ::testing::Combine(::testing::Values("filleted_box", "drilled_plate", "cylinder", "sphere",
                                                              "torus", "free_form"),
                                            ::testing::Values("step", "iges")),
                         caseName);

}  // namespace
}  // namespace shapespline::test
