// part.json's coedges (docs/cad.md "Coedges"), read back by io::readPartManifest: every trim-loop
// point is tied to the edge it lies on and that edge's parameter there. Checked on the test parts
// (STEP and IGES): the coedges cover each loop once, in order; in a closed shell every edge has two
// coedges (a seam two in one face); each loop point, evaluated on the imported face, lies on the
// edge's OCCT 3-D curve at the coedge's parameter; the two coedges of an edge end at the same points.
#include "test_parts.h"

#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/part_import.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/part_manifest.h>

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRep_Tool.hxx>
#include <Geom_Curve.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Circ.hxx>
#include <gp_Pln.hxx>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <map>
#include <unistd.h>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// Loop points are p-curve points, mapped to the model exactly (10^-9 of the face's size); the
// p-curve lies within the edge's tolerance of its 3-D curve. Where two edges meet, the shared point
// is the previous edge's end: the next edge's start lies within its tolerance of it too, and a
// closed loop's dropped last point within trim.tolerance (in parameters) of point 0. Hence the edge's
// tolerance plus a few trim tolerances times the face's size over its parameter span.
constexpr double kTrimToleranceMultiple = 4.0;

fs::path scratch() {
  static const fs::path root = [] {
    fs::path p = fs::temp_directory_path() / ("shapespline_coedge_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
  }();
  return root;
}

double boxDiagonal(const std::vector<glm::dvec3>& points) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const glm::dvec3& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

glm::dvec3 vec(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }

// One coedge's ends in 3-D, evaluated on its face's model.
struct CoedgeEnds {
  int face;
  glm::dvec3 first, last;
  double tolerance;
};

class Coedges : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

TEST_P(Coedges, TieEveryLoopPointToItsEdge) {
  const auto& [name, format] = GetParam();
  TopoDS_Shape shape;
  for (const TestPart& p : allTestParts())
    if (p.name == name) shape = p.shape;
  ASSERT_FALSE(shape.IsNull());
  const fs::path file = scratch() / (name + "." + format);
  (format == "step" ? writeStep : writeIges)(shape, file);
  const fs::path dir = scratch() / (name + "_" + format);
  cad::importPart(file, dir);
  const io::PartManifest manifest = io::readPartManifest(dir / "part.json");

  // OCCT's side: the same file read again, its edges in the ids part.json uses.
  const cad::PartShape part = cad::readPart(file, std::uint64_t{1} << 30);
  TopTools_IndexedMapOfShape faces, edges;
  TopExp::MapShapes(part.shape, TopAbs_FACE, faces);
  TopExp::MapShapes(part.shape, TopAbs_EDGE, edges);
  ASSERT_EQ(static_cast<int>(manifest.edges.size()), edges.Extent());
  std::map<int, bool> degenerate;
  for (const io::PartEdgeEntry& e : manifest.edges) degenerate[e.id] = e.degenerate;

  std::map<int, std::vector<CoedgeEnds>> byEdge;  // non-degenerate edges' coedges over the whole part
  int points = 0, decreasing = 0;
  double worst = 0.0, worstShare = 0.0;  // the largest distance, and distance / allowed
  ASSERT_EQ(static_cast<int>(manifest.faces.size()), faces.Extent());
  for (const io::PartFaceEntry& face : manifest.faces) {
    SCOPED_TRACE("face " + std::to_string(face.id) + " " + face.surface);
    ASSERT_TRUE(face.model.has_value());
    const SurfaceModel model = std::get<SurfaceModel>(io::loadModelFile(*face.model));
    const Surface surface = Surface::create(model);
    const auto [a0, a1] = surface.parameterRangeU();
    const auto [b0, b1] = surface.parameterRangeV();
    const double trimSlack = kTrimToleranceMultiple * model.trim.tolerance / std::max(a1 - a0, b1 - b0) *
                             boxDiagonal(model.points);
    const TopoDS_Face occtFace = TopoDS::Face(faces(face.id));
    ASSERT_EQ(face.coedges.size(), model.trim.loops.size());
    std::map<int, int> inThisFace;
    for (size_t l = 0; l < model.trim.loops.size(); ++l) {
      SCOPED_TRACE("loop " + std::to_string(l));
      const std::vector<glm::dvec2>& loop = model.trim.loops[l];
      const std::vector<io::PartCoedge>& coedges = face.coedges[l];
      const int n = static_cast<int>(loop.size());
      ASSERT_FALSE(coedges.empty());
      // Every point once, in order: each coedge starts where the previous ended, the first at 0,
      // the last ends at point n = 0 (the test parts' loops all close).
      int next = 0;
      for (const io::PartCoedge& c : coedges) {
        ASSERT_EQ(c.start, next);
        ASSERT_GE(c.t.size(), 2u);
        next = c.start + static_cast<int>(c.t.size()) - 1;
      }
      ASSERT_EQ(next, n);

      for (const io::PartCoedge& c : coedges) {
        SCOPED_TRACE("edge " + std::to_string(c.edge));
        ASSERT_TRUE(degenerate.count(c.edge));
        const TopoDS_Edge& edge = TopoDS::Edge(edges(c.edge));
        ++inThisFace[c.edge];
        const bool down = c.t.back() < c.t.front();
        decreasing += down;
        for (size_t j = 1; j < c.t.size(); ++j) ASSERT_EQ(c.t[j] < c.t[j - 1], down) << "t not monotonic at " << j;
        const double tolerance = BRep_Tool::Tolerance(edge) + trimSlack;
        double first = 0.0, last = 0.0;
        const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, first, last);
        ASSERT_EQ(degenerate[c.edge], curve.IsNull());
        const glm::dvec3 pole = degenerate[c.edge] ? vec(BRep_Tool::Pnt(TopExp::FirstVertex(edge))) : glm::dvec3(0.0);
        std::vector<glm::dvec3> onFace(c.t.size());
        for (size_t j = 0; j < c.t.size(); ++j) {
          const glm::dvec2 q = loop[(c.start + j) % n];
          onFace[j] = surface.evaluateAt(q.x, q.y).point;
          const glm::dvec3 onEdge = curve.IsNull() ? pole : vec(curve->Value(c.t[j]));
          const double d = glm::length(onFace[j] - onEdge);
          worst = std::max(worst, d);
          worstShare = std::max(worstShare, d / tolerance);
          ASSERT_LE(d, tolerance) << "point " << j << " t " << c.t[j];
          ++points;
        }
        if (!degenerate[c.edge]) byEdge[c.edge].push_back({face.id, onFace.front(), onFace.back(), tolerance});
      }
    }
    // An edge used twice by one face is its seam.
    for (const auto& [id, count] : inThisFace)
      if (!degenerate[id] && count > 1) {
        EXPECT_EQ(count, 2) << "edge " << id;
        EXPECT_TRUE(BRep_Tool::IsClosed(TopoDS::Edge(edges(id)), occtFace)) << "edge " << id << " twice, not a seam";
      }
  }
  EXPECT_GT(points, 0);
  EXPECT_GT(decreasing, 0);  // the parts' loops use edges both ways

  // A closed shell uses every edge twice; the solids written as STEP are closed.
  int shells = 0, closedShells = 0;
  for (TopExp_Explorer shell(part.shape, TopAbs_SHELL); shell.More(); shell.Next(), ++shells)
    closedShells += BRep_Tool::IsClosed(shell.Current());
  const bool closed = shells > 0 && closedShells == shells;
  if (format == "step" && name != "free_form") {
    EXPECT_TRUE(closed);
  }
  std::cout << name << " " << format << ": " << points << " loop points on " << byEdge.size() << " edges ("
            << (closed ? "closed" : "open") << "), " << decreasing << " used backwards; largest distance " << worst
            << ", " << worstShare << " of the allowed\n";
  int edgesUsed = 0;
  for (int id = 1; id <= edges.Extent(); ++id) {
    if (degenerate[id]) continue;
    const auto it = byEdge.find(id);
    const size_t count = it == byEdge.end() ? 0 : it->second.size();
    if (closed) {
      EXPECT_EQ(count, 2u) << "edge " << id;
    } else {
      EXPECT_LE(count, 2u) << "edge " << id;
    }
    if (count == 0) continue;
    ++edgesUsed;
    if (count != 2) continue;
    // Both coedges end at the same 3-D points (the other way round where the faces use the edge in
    // opposite directions).
    const CoedgeEnds& a = it->second[0];
    const CoedgeEnds& b = it->second[1];
    const double tolerance = a.tolerance + b.tolerance;
    const bool same = glm::length(a.first - b.first) <= tolerance && glm::length(a.last - b.last) <= tolerance;
    const bool opposite = glm::length(a.first - b.last) <= tolerance && glm::length(a.last - b.first) <= tolerance;
    EXPECT_TRUE(same || opposite) << "edge " << id << " in faces " << a.face << " and " << b.face;
  }
  EXPECT_GT(edgesUsed, 0);
}

// The loop reversal: a plane face whose outer wire runs clockwise and whose hole (a circle) runs
// counter-clockwise, as a file may give them; the importer turns both round. The coedges turn with
// them: still every point once from point 0, each point on its edge at its parameter.
TEST(CoedgesOfReversedLoops, TurnWithTheLoop) {
  const TopoDS_Wire outer = BRepBuilderAPI_MakePolygon(gp_Pnt(0, 0, 0), gp_Pnt(0, 10, 0), gp_Pnt(10, 10, 0),
                                                       gp_Pnt(10, 0, 0), true)
                                .Wire();  // clockwise seen from +z
  const TopoDS_Edge circle = BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp_Pnt(4, 5, 0), gp::DZ()), 2.0));
  const TopoDS_Wire hole = BRepBuilderAPI_MakeWire(circle).Wire();  // counter-clockwise
  BRepBuilderAPI_MakeFace make(gp_Pln(gp::XOY()), outer, true);
  make.Add(hole);
  ASSERT_TRUE(make.IsDone());
  const TopoDS_Face face = make.Face();

  const cad::ConvertedFace converted = cad::convertFace(face, 1e-5);
  const Surface surface = Surface::create(converted.model);
  const std::vector<std::vector<glm::dvec2>>& loops = converted.model.trim.loops;
  ASSERT_EQ(loops.size(), 2u);
  ASSERT_EQ(converted.coedges.size(), 2u);
  ASSERT_EQ(converted.coedges[0].size(), 4u);  // the square's sides
  ASSERT_EQ(converted.coedges[1].size(), 1u);  // the circle
  // The wires as built run the wrong way for the model: each edge is used against the wire's order.
  for (size_t l = 0; l < 2; ++l) {
    SCOPED_TRACE("loop " + std::to_string(l));
    const int n = static_cast<int>(loops[l].size());
    int next = 0;
    for (const cad::TrimCoedge& c : converted.coedges[l]) {
      ASSERT_EQ(c.start, next);
      next = c.start + static_cast<int>(c.t.size()) - 1;
      double first = 0.0, last = 0.0;
      const Handle(Geom_Curve) curve = BRep_Tool::Curve(c.edge, first, last);
      for (size_t j = 0; j < c.t.size(); ++j) {
        const glm::dvec2 q = loops[l][(c.start + j) % n];
        const double d = glm::length(surface.evaluateAt(q.x, q.y).point - vec(curve->Value(c.t[j])));
        ASSERT_LE(d, BRep_Tool::Tolerance(c.edge) + kTrimToleranceMultiple * 1e-5 * 10.0) << "point " << j;
      }
    }
    EXPECT_EQ(next, n);
  }
  // The circle's run goes against the edge's parameter: the wire used it forward, the loop reversed.
  const cad::TrimCoedge& around = converted.coedges[1][0];
  EXPECT_LT(around.t.back(), around.t.front());
}

std::string caseName(const ::testing::TestParamInfo<Coedges::ParamType>& info) {
  return std::get<0>(info.param) + "_" + std::get<1>(info.param);
}

INSTANTIATE_TEST_SUITE_P(Parts, Coedges,
                         ::testing::Combine(::testing::Values("filleted_box", "drilled_plate", "cylinder", "sphere",
                                                              "torus", "free_form"),
                                            ::testing::Values("step", "iges")),
                         caseName);

}  // namespace
}  // namespace shapespline::test
