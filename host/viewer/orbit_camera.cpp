#include <shapespline/viewer/orbit_camera.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace shapespline::viewer {

constexpr double kMaxElevation = 89.0;

OrbitCamera::OrbitCamera(const glm::dvec3& lo, const glm::dvec3& hi) {
  // render::Camera::frame decides the starting distance (the box's bounding sphere fits the view).
  const render::Camera framed = render::Camera::frame(lo, hi, az_, el_, 1.0, fovYDeg_);
  target_ = 0.5 * (lo + hi);
  radius_ = std::max(0.5 * glm::length(hi - lo), 1e-9);
  dist_ = startDist_ = glm::length(glm::dvec3(framed.eye) - target_);
}

glm::dvec3 OrbitCamera::forward() const {
  const double az = glm::radians(az_), el = glm::radians(el_);
  return -glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
}

void OrbitCamera::rotate(double dAzDeg, double dElDeg) {
  az_ = std::fmod(az_ + dAzDeg, 360.0);
  el_ = std::clamp(el_ + dElDeg, -kMaxElevation, kMaxElevation);
}

void OrbitCamera::zoom(double factor) {
  if (!(factor > 0.0)) return;
  dist_ = std::clamp(dist_ * factor, 1e-3 * startDist_, 1e3 * startDist_);
}

void OrbitCamera::pan(double dxPx, double dyPx, int heightPx) {
  const glm::dvec3 f = forward();
  const glm::dvec3 right = glm::normalize(glm::cross(f, glm::dvec3(0, 0, 1)));
  const glm::dvec3 up = glm::cross(right, f);
  // World units per pixel at the target's depth.
  const double perPixel = 2.0 * dist_ * std::tan(0.5 * glm::radians(fovYDeg_)) / std::max(heightPx, 1);
  target_ += (-dxPx * right + dyPx * up) * perPixel;  // image y runs down
}

render::Camera OrbitCamera::camera(int width, int height) const {
  const glm::dvec3 eye = target_ - dist_ * forward();
  const double zNear = std::max(dist_ - 2.0 * radius_, 1e-3 * dist_);
  const double zFar = dist_ + 2.0 * radius_;
  return render::Camera::look(eye, target_, glm::dvec3(0, 0, 1), fovYDeg_, double(width) / std::max(height, 1), zNear,
                              zFar);
}

}  // namespace shapespline::viewer
