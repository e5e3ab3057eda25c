#pragma once
// OrbitCamera: the viewer's camera, orbiting a target point. Azimuth about +z from +x and elevation
// above the xy plane, as render::Camera::frame, which it starts from; the camera() it gives has
// render::Camera's conventions (Vulkan clip: y down, depth 0..1).
#include <shapespline/render/camera.h>

#include <glm/vec3.hpp>

namespace shapespline::viewer {

class OrbitCamera {
 public:
  // Frames the box [lo, hi] from azimuth 35°, elevation 30° (the `render` default).
  OrbitCamera(const glm::dvec3& lo, const glm::dvec3& hi);

  // Degrees; the elevation stays within ±89° (the up vector stays +z).
  void rotate(double dAzDeg, double dElDeg);
  // Distance to the target times factor (> 1 moves away), kept within [1e-3, 1e3] x the start.
  void zoom(double factor);
  // Moves the target in the view plane by (dx, dy) pixels of a viewport heightPx tall, measured at
  // the target's depth (a dragged point under the cursor follows it).
  void pan(double dxPx, double dyPx, int heightPx);

  render::Camera camera(int width, int height) const;
  double azimuth() const { return az_; }
  double elevation() const { return el_; }
  double distance() const { return dist_; }

 private:
  glm::dvec3 forward() const;  // from the eye to the target, unit

  glm::dvec3 target_;
  double radius_;      // of the framed box's bounding sphere: the depth range
  double az_ = 35.0, el_ = 30.0;
  double dist_, startDist_;
  double fovYDeg_ = 30.0;
};

}  // namespace shapespline::viewer
