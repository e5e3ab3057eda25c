#pragma once
// The surfaces the closest-point tests project onto (CPU: closest_points_test.cpp, GPU:
// closest_points_gpu_test.cpp), and the random queries they use.
#include <shapespline/core/model.h>
#include <shapespline/core/surface.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace shapespline::part {

inline std::vector<double> clampedKnots(int order, int intervals) {
  std::vector<double> k(order - 1, 0.0);
  for (int i = 0; i <= intervals; ++i) k.push_back(double(i) / intervals);
  k.insert(k.end(), order - 1, 1.0);
  return k;
}

// A bicubic NURBS of 6 x 6 knot intervals, its net waving in z and its weights in [0.5, 1.5].
inline Surface wavyNurbs() {
  SurfaceModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = m.orderV = 4;
  m.knotsU = m.knotsV = clampedKnots(4, 6);
  m.rows = m.cols = 9;
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) {
      m.points.push_back({i / 8.0, j / 8.0, 0.1 * std::sin(1.7 * i + 2.3 * j)});
      m.weights.push_back(1.0 + 0.5 * std::sin(0.9 * i * j + 0.4));
    }
  return Surface::create(std::move(m));
}

// Half a cylinder of radius 1 and length 2, exact: two rational quadratic quarter circles in u.
inline Surface halfCylinder() {
  SurfaceModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 3;
  m.orderV = 2;
  m.knotsU = {0, 0, 0, 0.5, 0.5, 1, 1, 1};
  m.knotsV = {0, 0, 1, 1};
  m.rows = 5;
  m.cols = 2;
  const glm::dvec2 arc[5] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}};
  const double w[5] = {1, std::sqrt(0.5), 1, std::sqrt(0.5), 1};
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 2; ++j) {
      m.points.push_back({arc[i].x, arc[i].y, 2.0 * j});
      m.weights.push_back(w[i]);
    }
  return Surface::create(std::move(m));
}

// A Xu-Wang degree-5 surface (λ = 0.5) of 8 x 7 points: the uniform families' patch path.
inline Surface xuWangSurface() {
  SurfaceModel m;
  m.family.construction = Construction::ExtendedBSpline;
  m.family.degree = 5;
  m.family.lambda = 0.5;
  m.rows = 8;
  m.cols = 7;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) m.points.push_back({double(i), double(j), 1.5 * std::cos(1.3 * i - 0.7 * j)});
  return Surface::create(std::move(m));
}



// Points on the surface at random parameters, and the same moved along the normal by up to 5% of
// the diagonal, and points anywhere in the box widened by 5%.
struct Queries {
  std::vector<glm::dvec3> on, off;
  std::vector<glm::dvec2> onUV;
};

inline Queries queriesFor(const Surface& s, double diagonal, int count, uint32_t seed) {
  std::mt19937_64 rng(seed);
  const auto [u0, u1] = s.parameterRangeU();
  const auto [v0, v1] = s.parameterRangeV();
  std::uniform_real_distribution<double> U(u0, u1), V(v0, v1), offset(-0.05 * diagonal, 0.05 * diagonal),
      unit(-0.05, 1.05);
  Queries q;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (int k = 0; k < count; ++k) {
    const glm::dvec2 uv(U(rng), V(rng));
    const SurfacePoint p = s.evaluateAt(uv.x, uv.y);
    q.on.push_back(p.point);
    q.onUV.push_back(uv);
    lo = glm::min(lo, p.point), hi = glm::max(hi, p.point);
    if (k % 4 != 3) q.off.push_back(p.point + offset(rng) * p.normal);
  }
  while (q.off.size() < size_t(count)) q.off.push_back(lo + (hi - lo) * glm::dvec3(unit(rng), unit(rng), unit(rng)));
  return q;
}

}  // namespace shapespline::part
