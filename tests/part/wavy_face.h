#pragma once
// The part tests' free-form face: a bicubic B-spline over [0, 1]^2 of 4 x 4 knot intervals whose net
// waves in z (0.3 sin(1.7 i + 2.3 j)), trimmed by the loops given.
#include <shapespline/core/model.h>
#include <shapespline/core/surface.h>

#include <glm/vec2.hpp>

#include <cmath>
#include <vector>

namespace shapespline::part {

inline Surface wavyFace(std::vector<std::vector<glm::dvec2>> loops) {
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
    for (int j = 0; j < rows; ++j)
      m.points.push_back({double(i) / (rows - 1), double(j) / (rows - 1), 0.3 * std::sin(1.7 * i + 2.3 * j)});
  m.trim.loops = std::move(loops);
  m.trim.tolerance = 1e-9;
  return Surface::create(std::move(m));
}

}  // namespace shapespline::part
