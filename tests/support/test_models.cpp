#include "support/test_models.h"

#include <cmath>

namespace shapespline::test {

SurfaceModel alphaEBTube(int rows, int cols) {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.family.lambda = 0.0;
  m.rows = rows;
  m.cols = cols;
  m.closedV = true;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const double t = j * 2.0 * M_PI / cols;
      m.points.push_back({i * 1.0, std::cos(t), std::sin(t) + 0.1 * i});
    }
  m.alpha.assign(static_cast<size_t>(rows) * cols, 0.5);
  return m;
}

}  // namespace shapespline::test
