#include "distance_map.h"

#include <shapespline/core/grid_sampler.h>
#include <shapespline/render/colour_map.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>

namespace shapespline::cli {
namespace {

const glm::vec4 kPatchLineColour{0.25f, 0.2f, 0.2f, 1.0f};
constexpr double kLineLift = 0.003;  // of the way to the eye: in front of the triangles beneath

}  // namespace

DistanceMesh distanceMesh(const Surface& from, const Surface& to, int n) {
  DistanceMesh m;
  m.n = n;
  for (const auto& [i, j] : surfaceGridItems(to))
    for (int a = 0; a <= n; ++a)
      for (int b = 0; b <= n; ++b) {
        const double u = double(a) / n, v = double(b) / n;
        const glm::dvec3 p = to.evaluate(i, j, u, v).point;
        m.points.push_back(p);
        m.distance.push_back(glm::length(p - from.evaluate(i, j, u, v).point));
        m.maxDistance = std::max(m.maxDistance, m.distance.back());
      }
  glm::dvec3 lo = m.points.front(), hi = lo;
  for (const glm::dvec3& p : m.points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  m.scaleTop = std::max(m.maxDistance, kSmallestScale * glm::length(hi - lo));
  return m;
}

void addDistanceMesh(render::Scene& scene, const DistanceMesh& m, const render::Camera& camera) {
  const int side = m.n + 1;
  const size_t perPatch = size_t(side) * side;
  const auto vertex = [&](size_t k) {
    const glm::dvec3& p = m.points[k];
    const double t = m.scaleTop > 0.0 ? m.distance[k] / m.scaleTop : 0.0;
    const glm::vec3 c = render::heatColour(t);
    scene.markers.push_back({{float(p.x), float(p.y), float(p.z)}, {0.0f, 0.0f}, {c.r, c.g, c.b, 1.0f}});
  };
  const glm::dvec3 eye(camera.eye);
  const auto lifted = [&](size_t k) { return m.points[k] + (eye - m.points[k]) * kLineLift; };
  for (size_t base = 0; base < m.points.size(); base += perPatch) {
    const auto at = [&](int a, int b) { return base + size_t(a) * side + b; };
    for (int a = 0; a < m.n; ++a)
      for (int b = 0; b < m.n; ++b)
        for (size_t k : {at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b), at(a + 1, b + 1), at(a, b + 1)}) vertex(k);
    for (int line : {0, m.n / 2, m.n}) {
      std::vector<glm::dvec3> alongU, alongV;
      for (int s = 0; s <= m.n; ++s) {
        alongU.push_back(lifted(at(s, line)));
        alongV.push_back(lifted(at(line, s)));
      }
      render::addPolyline(scene.lines, alongU, kPatchLineColour);
      render::addPolyline(scene.lines, alongV, kPatchLineColour);
    }
  }
}

}  // namespace shapespline::cli
