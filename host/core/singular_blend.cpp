#include <shapespline/core/singular_blend.h>

namespace shapespline {

BlendValue singularBlend(double t) {
  if (t <= 1.0 / 3.0) return {4.5 * t * t * t, 13.5 * t * t, 27.0 * t};
  if (t <= 2.0 / 3.0)
    return {0.5 + t * (-4.5 + t * (13.5 - 9.0 * t)), -4.5 + t * (27.0 - 27.0 * t), 27.0 - 54.0 * t};
  const double u = 1.0 - t;
  return {1.0 - 4.5 * u * u * u, 13.5 * u * u, -27.0 * u};
}

}  // namespace shapespline
