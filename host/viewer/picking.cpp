#include <shapespline/viewer/picking.h>

#include <cmath>

namespace shapespline::viewer {

int pickPoint(std::span<const glm::dvec3> points, const render::Camera& camera, int width, int height, double x,
              double y, double maxPx) {
  int best = -1;
  double bestDist = maxPx;
  for (size_t k = 0; k < points.size(); ++k) {
    const glm::dvec3 p = camera.toPixel(points[k], width, height);
    if (!(p.z >= 0.0 && p.z <= 1.0)) continue;
    const double d = std::hypot(p.x - x, p.y - y);
    if (d <= bestDist) {
      bestDist = d;
      best = int(k);
    }
  }
  return best;
}

}  // namespace shapespline::viewer
