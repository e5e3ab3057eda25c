#pragma once
// Camera that frames a bounding box: perspective, Vulkan clip conventions (y down, depth 0..1).
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace shapespline::render {

struct Camera {
  glm::mat4 view{1.0f}, proj{1.0f};
  glm::vec3 eye{0.0f};
  glm::mat4 viewProj() const { return proj * view; }
  // Projects a model-space point to pixel coordinates (x right, y down, pixel centres at +0.5);
  // z is the depth in [0,1]. Same matrices as the renderer.
  glm::dvec3 toPixel(const glm::dvec3& p, int width, int height) const;

  // Looks at the centre of the box [lo, hi] from azimuth azDeg (about +z, from +x) and elevation
  // elDeg (above the xy plane) at a distance where the box's bounding sphere fits both fields of
  // view. +z is up (+y when looking straight down or up). aspect = width / height.
  static Camera frame(const glm::dvec3& lo, const glm::dvec3& hi, double azDeg, double elDeg, double aspect,
                      double fovYDeg = 30.0);
};

}  // namespace shapespline::render
