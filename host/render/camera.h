#pragma once
// Cameras that frame a model: perspective, Vulkan clip conventions (y down, depth 0..1).
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <span>

namespace shapespline::render {

// A rectangle of the image in pixels (x right, y down), x0 < x1, y0 < y1.
struct PixelRect {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
};

struct Camera {
  glm::mat4 view{1.0f}, proj{1.0f};
  glm::vec3 eye{0.0f};
  glm::mat4 viewProj() const { return proj * view; }
  // Projects a model-space point to pixel coordinates (x right, y down, pixel centres at +0.5);
  // z is the depth in [0,1]. Same matrices as the renderer.
  glm::dvec3 toPixel(const glm::dvec3& p, int width, int height) const;

  // Perspective from `eye` towards `target` with the `up` hint, Vulkan conventions; fovY in
  // degrees, aspect = width / height. What every other camera here is made with.
  static Camera look(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, double fovYDeg,
                     double aspect, double zNear, double zFar);

  // Looks at the centre of the box [lo, hi] from azimuth azDeg (about +z, from +x) and elevation
  // elDeg (above the xy plane) at a distance where the box's bounding sphere fits both fields of
  // view: the distance does not change with the direction (an orbit keeps its size). +z is up (+y
  // when looking straight down or up). aspect = width / height.
  static Camera frame(const glm::dvec3& lo, const glm::dvec3& hi, double azDeg, double elDeg, double aspect,
                      double fovYDeg = 30.0);

  // Looks from the same direction as frame() (same view axes, same vertical field of view over the
  // whole width x height image) but places the eye so that the projections of `points` fill
  // `target` tightly: the points' extreme projections touch both sides of `target` in one axis and
  // are centred in the other. Solved exactly for the perspective (each frustum side plane pushed
  // against its extreme point), so no bounding sphere's slack is left. Near and far enclose the
  // points with room for what lies between them. Needs at least one point.
  static Camera fit(std::span<const glm::dvec3> points, double azDeg, double elDeg, int width, int height,
                    const PixelRect& target, double fovYDeg = 30.0);
};

}  // namespace shapespline::render
