#include <shapespline/core/singular_blend.h>

#include <shapespline/core/point_math.h>

namespace shapespline {

BlendValue singularBlend(double t) {
  const glm::dvec3 s = pm::singularBlend(t);
  return {s.x, s.y, s.z};
}

}  // namespace shapespline
