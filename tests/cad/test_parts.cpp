#include "test_parts.h"

#include <shapespline/cad/occt_part.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Writer.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gp_Ax2.hxx>

#include <cmath>
#include <stdexcept>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

namespace shapespline::test {
namespace {

// OCCT 7.6's STEP writer loses a few bytes per part (GeomToStep_MakeDirection's default axis): a
// leak inside OCCT's writer, which only the tests use (to make their parts). Paused there, so that
// LeakSanitizer still watches everything else.
struct LeakCheckPaused {
#if defined(__SANITIZE_ADDRESS__)
  LeakCheckPaused() { __lsan_disable(); }
  ~LeakCheckPaused() { __lsan_enable(); }
#endif
};

}  // namespace

TopoDS_Shape filletedBox() {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(40.0, 30.0, 20.0).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  for (TopExp_Explorer e(box, TopAbs_EDGE); e.More(); e.Next()) fillet.Add(3.0, TopoDS::Edge(e.Current()));
  fillet.Build();
  if (!fillet.IsDone()) throw std::runtime_error("filletedBox: the fillet failed");
  return fillet.Shape();
}

std::vector<Hole> drilledPlateHoles() { return {{30.0, 30.0, 8.0}, {70.0, 30.0, 8.0}}; }

TopoDS_Shape drilledPlate() {
  TopoDS_Shape plate = BRepPrimAPI_MakeBox(100.0, 60.0, 5.0).Shape();
  for (const Hole& h : drilledPlateHoles()) {
    const TopoDS_Shape drill = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(h.x, h.y, -1.0), gp::DZ()), h.radius, 7.0).Shape();
    BRepAlgoAPI_Cut cut(plate, drill);
    if (!cut.IsDone()) throw std::runtime_error("drilledPlate: the cut failed");
    plate = cut.Shape();
  }
  return plate;
}

TopoDS_Shape cylinder() { return BRepPrimAPI_MakeCylinder(5.0, 12.0).Shape(); }
TopoDS_Shape sphere() { return BRepPrimAPI_MakeSphere(7.0).Shape(); }
TopoDS_Shape torus() { return BRepPrimAPI_MakeTorus(10.0, 3.0).Shape(); }

TopoDS_Shape freeForm() {
  TColgp_Array2OfPnt points(1, 6, 1, 5);
  for (int i = 1; i <= 6; ++i)
    for (int j = 1; j <= 5; ++j)
      points(i, j) = gp_Pnt(10.0 * i, 8.0 * j, 3.0 * std::sin(0.9 * i) * std::cos(0.7 * j));
  GeomAPI_PointsToBSplineSurface fit(points);
  if (!fit.IsDone()) throw std::runtime_error("freeForm: the fit failed");
  const Handle(Geom_Surface) surface(fit.Surface());
  return BRepBuilderAPI_MakeFace(surface, 1e-7).Face();
}

std::vector<TestPart> allTestParts() {
  return {{"filleted_box", filletedBox()}, {"drilled_plate", drilledPlate()}, {"cylinder", cylinder()},
          {"sphere", sphere()},            {"torus", torus()},                 {"free_form", freeForm()}};
}

void writeStep(const TopoDS_Shape& shape, const std::filesystem::path& path) {
  cad::initOcctControllers();
  [[maybe_unused]] const LeakCheckPaused paused;
  STEPControl_Writer writer;
  if (writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone || writer.Write(path.c_str()) != IFSelect_RetDone)
    throw std::runtime_error("writeStep failed: " + path.string());
}

void writeIges(const TopoDS_Shape& shape, const std::filesystem::path& path) {
  cad::initOcctControllers();
  [[maybe_unused]] const LeakCheckPaused paused;
  IGESControl_Writer writer("MM", 1);  // BRep mode: faces with their trimming loops
  if (!writer.AddShape(shape) || !writer.Write(path.c_str())) throw std::runtime_error("writeIges failed: " + path.string());
}

}  // namespace shapespline::test
