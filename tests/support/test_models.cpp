#include "support/test_models.h"

#include <cmath>
#include <random>

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

SurfaceModel wavyNet(FamilySpec family, int n, bool alpha, double scale) {
  SurfaceModel m;
  m.family = family;
  m.orderV = family.order;
  m.rows = m.cols = n;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-0.3, 0.3), al(0.05, 1.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      m.points.push_back(scale * glm::dvec3(i + d(rng), j + d(rng), std::sin(0.9 * i) * std::cos(0.7 * j)));
      if (alpha) m.alpha.push_back(al(rng));
    }
  return m;
}

}  // namespace shapespline::test
