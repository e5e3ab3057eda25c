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

namespace {

const glm::dvec3 kCircle[9] = {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}, {-1, 0, 0},
                               {-1, -1, 0}, {0, -1, 0}, {1, -1, 0}, {1, 0, 0}};
double circleWeight(int i) { return i % 2 ? std::sqrt(0.5) : 1.0; }
const std::vector<double> kCircleKnots = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};

}  // namespace

CurveModel nurbsCircle(double radius) {
  CurveModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 3;
  m.dimension = 2;
  for (int i = 0; i < 9; ++i) {
    m.points.push_back(radius * kCircle[i]);
    m.weights.push_back(circleWeight(i));
  }
  m.knots = kCircleKnots;
  return m;
}

SurfaceModel nurbsTorus(double R, double r) {
  SurfaceModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 3;
  m.orderV = 3;
  m.rows = m.cols = 9;
  m.knotsU = m.knotsV = kCircleKnots;
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) {
      const double x = R + r * kCircle[j].x;
      m.points.push_back({x * kCircle[i].x, x * kCircle[i].y, r * kCircle[j].y});
      m.weights.push_back(circleWeight(i) * circleWeight(j));
    }
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
