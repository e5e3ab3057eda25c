#pragma once
// The parts the import tests make with Open CASCADE at test time (issue 32: no downloaded data),
// and writers for STEP and IGES.
#include <TopoDS_Shape.hxx>

#include <filesystem>
#include <string>
#include <vector>

namespace shapespline::test {

struct TestPart {
  std::string name;
  TopoDS_Shape shape;
};

TopoDS_Shape filletedBox();   // 40 x 30 x 20, every edge rounded with radius 3
TopoDS_Shape drilledPlate();  // 100 x 60 x 5, two through holes of radius 8 at (30, 30) and (70, 30)
TopoDS_Shape cylinder();      // radius 5, height 12
TopoDS_Shape sphere();        // radius 7
TopoDS_Shape torus();         // radii 10 and 3
TopoDS_Shape freeForm();      // one face of GeomAPI_PointsToBSplineSurface through a 6 x 5 height grid
std::vector<TestPart> allTestParts();

// Holes of drilledPlate(): centre (x, y) and radius.
struct Hole {
  double x, y, radius;
};
std::vector<Hole> drilledPlateHoles();

void writeStep(const TopoDS_Shape& shape, const std::filesystem::path& path);
void writeIges(const TopoDS_Shape& shape, const std::filesystem::path& path);

}  // namespace shapespline::test
