#pragma once
// The part tests' free-form faces: bicubic B-splines over a unit square of 4 x 4 knot intervals
// whose nets are lifted in z, trimmed by the loops given. `wavyFace` is the tests' face over
// [0, 1]^2 (z = 0.3 sin(1.7 i + 2.3 j) at net point (i, j)); the closest-point scaling bench tiles
// `bicubicSheet`s into a sheet of many faces.
#include <shapespline/core/model.h>
#include <shapespline/core/surface.h>

#include <glm/vec2.hpp>

#include <cmath>
#include <vector>

namespace shapespline::part {

// Over [origin, origin + (1, 1)]: net point (i, j) (7 x 7, evenly spaced) at height z(i, j, x, y).
template <typename Height>
Surface bicubicSheet(glm::dvec2 origin, const Height& z, std::vector<std::vector<glm::dvec2>> loops = {}) {
  SurfaceModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 4;
  m.orderV = 4;
  const int n = 4, rows = n + 3;
  std::vector<double> knots = {0, 0, 0};
  for (int i = 0; i <= n; ++i) knots.push_back(double(i) / n);
  knots.insert(knots.end(), {1, 1, 1});
  m.knotsU = m.knotsV = knots;
  m.rows = m.cols = rows;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < rows; ++j) {
      const double x = origin.x + double(i) / (rows - 1), y = origin.y + double(j) / (rows - 1);
      m.points.push_back({x, y, z(i, j, x, y)});
    }
  m.trim.loops = std::move(loops);
  m.trim.tolerance = 1e-9;
  return Surface::create(std::move(m));
}

inline Surface wavyFace(std::vector<std::vector<glm::dvec2>> loops) {
  return bicubicSheet({0.0, 0.0}, [](int i, int j, double, double) { return 0.3 * std::sin(1.7 * i + 2.3 * j); },
                      std::move(loops));
}

}  // namespace shapespline::part
