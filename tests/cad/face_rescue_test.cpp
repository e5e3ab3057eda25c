// Faces that real parts carry and that the separable parameter map alone would lose (issue 54
// item 0): p-curves a hair outside the B-spline's knot domain (clamped within twice the edge's
// tolerance) and a face whose parameter map fails (trims projected onto the B-spline). Each face is
// made here with OCCT, converted, written, and sampled trimmed by the CLI.
#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/trim_loops.h>
#include <shapespline/cad/trim_points.h>
#include <shapespline/io/model_json.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gp_Ax3.hxx>

#include <cli/cli_runner.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

struct TrimmedRecord {
  double u, v, x, y, z;
};

// A flat 10 x 10 square as a degree-1 B-spline on [0, 1]^2: |dS/du| = 10.
Handle(Geom_BSplineSurface) flatSquare() {
  TColgp_Array2OfPnt poles(1, 2, 1, 2);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) poles(i + 1, j + 1) = gp_Pnt(10.0 * i, 10.0 * j, 0.0);
  TColStd_Array1OfReal knots(1, 2);
  knots(1) = 0.0, knots(2) = 1.0;
  TColStd_Array1OfInteger mults(1, 2);
  mults(1) = mults(2) = 2;
  return new Geom_BSplineSurface(poles, knots, knots, mults, mults, 1, 1);
}

// The square's face with the p-curve of its u = 1 edge moved to u = 1 + overshoot, and that edge's
// tolerance set to `edgeTolerance` (as a file whose trims overshoot the surface would carry).
TopoDS_Face overshootingFace(double overshoot, double edgeTolerance) {
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(flatSquare(), 0.0, 1.0, 0.0, 1.0, 1e-7);
  BRep_Builder builder;
  int moved = 0;
  for (TopExp_Explorer edges(face, TopAbs_EDGE); edges.More(); edges.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(edges.Current());
    double first = 0.0, last = 0.0;
    const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, face, first, last);
    if (std::abs(pcurve->Value(0.5 * (first + last)).X() - 1.0) > 1e-12) continue;
    const Handle(Geom2d_Geometry) shifted = pcurve->Translated(gp_Vec2d(overshoot, 0.0));
    builder.UpdateEdge(edge, Handle(Geom2d_Curve)::DownCast(shifted), face, edgeTolerance);
    builder.UpdateEdge(edge, edgeTolerance);
    ++moved;
  }
  EXPECT_EQ(moved, 1);
  return face;
}

// The face samples as a trimmed model (`sample FACE --grid N --trim`, CPU): the kept records.
std::vector<TrimmedRecord> sampleTrimmed(const SurfaceModel& model, const ScratchDir& dir, const std::string& name, int grid) {
  const fs::path file = dir / (name + ".json"), out = dir / (name + ".f64");
  std::ofstream(file) << io::toJson(model).dump(1) << "\n";
  const CliResult r = runCli("sample " + quote(file.string()) + " --grid " + std::to_string(grid) + " --trim --device cpu -o " +
                                 quote(out.string()),
                             dir.path());
  EXPECT_EQ(r.rc, 0) << r.err;
  const std::string bytes = readText(out);
  std::vector<TrimmedRecord> records(bytes.size() / sizeof(TrimmedRecord));
  std::memcpy(records.data(), bytes.data(), records.size() * sizeof(TrimmedRecord));
  return records;
}

TEST(FaceRescue, TrimPointsAHairOutsideTheDomainAreClamped) {
  // 0.0015 beyond u = 1 (150 trim tolerances): 0.015 from the face in 3-D, within 2 x 0.01.
  const cad::ConvertedFace converted = cad::convertFace(overshootingFace(0.0015, 0.01), 1e-5);
  EXPECT_GT(converted.clampedTrimPoints, 0);
  EXPECT_TRUE(converted.mapFailure.empty());
  for (const auto& loop : converted.model.trim.loops)
    for (const glm::dvec2& q : loop) {
      ASSERT_GE(q.x, 0.0);
      ASSERT_LE(q.x, 1.0);
    }
  // The clamped loop is the whole square: every sample of the grid is kept, on OCCT's surface.
  ScratchDir dir("face_rescue_clamp");
  const std::vector<TrimmedRecord> kept = sampleTrimmed(converted.model, dir, "clamped", 24);
  EXPECT_EQ(kept.size(), 24u * 24u);
  for (const TrimmedRecord& k : kept) {
    const gp_Pnt p = converted.bspline->Value(k.u, k.v);
    ASSERT_LE(p.Distance(gp_Pnt(k.x, k.y, k.z)), 1e-12 * 15.0) << k.u << ", " << k.v;
  }
}

TEST(FaceRescue, TrimPointsFurtherOutAreStillRefusedWithTheReason) {
  // 0.005 beyond: 0.05 from the face, more than 2 x 0.01.
  try {
    cad::convertFace(overshootingFace(0.005, 0.01), 1e-5);
    FAIL() << "converted";
  } catch (const cad::ConversionError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("knot domain [0, 1] x [0, 1]"), std::string::npos) << what;
    EXPECT_NE(what.find("the edge's tolerance 0.01"), std::string::npos) << what;
  }
}

// A face over a whole period of a cylinder trimmed to start at pi/2 (as a real STEP part carries
// it). GeomConvert would make the whole period a periodic B-spline whose parameters start about 2
// degrees further on, so the face's loops crossed the B-spline's ends and its trims had to be
// projected; cut a hair short of the period, the conversion keeps the seam where the face has it
// and the separable map holds. The projection (the map's fallback) is checked on the same face:
// its trim points are on the face's boundary too.
TEST(FaceRescue, AWholePeriodKeepsItsSeamAndTheProjectionAgrees) {
  const double radius = 5.0, height = 12.0;
  Handle(Geom_CylindricalSurface) cylinder = new Geom_CylindricalSurface(gp_Ax3(gp::XOY()), radius);
  Handle(Geom_RectangularTrimmedSurface) trimmed =
      new Geom_RectangularTrimmedSurface(cylinder, M_PI / 2, M_PI / 2 + 2 * M_PI, -height, height);
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(trimmed, M_PI / 2, M_PI / 2 + 2 * M_PI, -3.0, 4.0, 1e-7);
  const cad::ConvertedFace converted = cad::convertFace(face, 1e-5);
  EXPECT_TRUE(converted.mapFailure.empty()) << converted.mapFailure;
  // The B-spline starts at the seam: angle pi/2, the point (0, r).
  double u0, u1, v0, v1;
  converted.bspline->Bounds(u0, u1, v0, v1);
  EXPECT_LE(converted.bspline->Value(u0, 0.0).Distance(gp_Pnt(0.0, radius, 0.0)), 1e-9 * radius);

  const double tolerance = 1e-5 * std::max(u1 - u0, v1 - v0);
  cad::TrimPoints projection(converted.source, converted.bspline, nullptr, tolerance);
  const cad::FaceTrim projected = cad::faceTrimLoops(face, projection, tolerance);
  EXPECT_LE(projection.largestGap(), 1e-9 * height);
  const double size = 2.0 * height;
  const double hair = 1e-9 * 2.0 * M_PI * radius;  // the seam's side cut short (host/cad/conversion.cpp)
  for (const auto* trim : {&converted.model.trim, &projected.trim}) {
    SCOPED_TRACE(trim == &projected.trim ? "projected" : "mapped");
    ASSERT_EQ(trim->loops.size(), 1u);
    // Every trim point lies on the face's boundary: on the cylinder, at z = -3 or 4 or on the
    // seam at angle pi/2; none jumps across the B-spline's ends (a step of most of the period).
    const auto& loop = trim->loops.front();
    for (size_t k = 0; k < loop.size(); ++k) {
      const glm::dvec2 q = loop[k];
      const gp_Pnt p = converted.bspline->Value(q.x, q.y);
      ASSERT_NEAR(std::hypot(p.X(), p.Y()), radius, 1e-9 * size);
      const double toSeam = std::hypot(p.X(), p.Y() - radius);
      const double toBoundary = std::min({std::abs(p.Z() + 3.0), std::abs(p.Z() - 4.0), toSeam});
      ASSERT_LE(toBoundary, 1e-9 * size + hair) << p.X() << ", " << p.Y() << ", " << p.Z();
      // A jump: the next point far in U (across the B-spline's ends) at the same place in space.
      // The projection may put a point of the seam on either side (it cannot tell them apart), so
      // only the mapped loop is free of jumps; that is why a whole period is not left to it.
      if (trim == &projected.trim) continue;
      const glm::dvec2 next = loop[(k + 1) % loop.size()];
      ASSERT_FALSE(std::abs(next.x - q.x) > 0.5 * (u1 - u0) &&
                   converted.bspline->Value(next.x, next.y).Distance(p) < 1e-3 * size)
          << "a jump at point " << k << " (" << q.x << ", " << q.y << ") to (" << next.x << ", " << next.y << ")";
    }
  }
  // Sampled trimmed: every kept point is on the face (between its heights, within the trim
  // tolerance mapped to 3-D, here far below the slack), and the face's heights are all reached.
  ScratchDir dir("face_rescue_whole_period");
  const std::vector<TrimmedRecord> kept = sampleTrimmed(converted.model, dir, "whole_period", 48);
  ASSERT_FALSE(kept.empty());
  const double slack = 1e-3;
  for (const TrimmedRecord& k : kept) {
    ASSERT_NEAR(std::hypot(k.x, k.y), radius, 1e-9 * size);
    ASSERT_GE(k.z, -3.0 - slack);
    ASSERT_LE(k.z, 4.0 + slack);
  }
  double lowest = 1e300, highest = -1e300;
  for (const TrimmedRecord& k : kept) lowest = std::min(lowest, k.z), highest = std::max(highest, k.z);
  EXPECT_LT(lowest, -3.0 + 7.0 / 8);
  EXPECT_GT(highest, 4.0 - 7.0 / 8);
}

}  // namespace
}  // namespace shapespline::test
