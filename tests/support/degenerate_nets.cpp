#include "support/degenerate_nets.h"

#include <cmath>

namespace shapespline::test {

SurfaceModel collapsedRowsNet() {
  SurfaceModel m;
  m.family.construction = Construction::ExtendedBSpline;
  m.family.degree = 4;
  m.rows = 7;
  m.cols = 5;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j)
      m.points.push_back(i < 4 ? glm::dvec3(0.0) : glm::dvec3(i, j, 0.3 * std::sin(1.3 * i + j)));
  return m;
}

}  // namespace shapespline::test
