#include <shapespline/render/camera.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace shapespline::render {
namespace {

// The view axes of azimuth/elevation: `forward` from the eye into the scene, `up` the lookAt hint.
struct ViewAxes {
  glm::dvec3 forward, up;
};

ViewAxes viewAxes(double azDeg, double elDeg) {
  const double az = glm::radians(azDeg), el = glm::radians(std::clamp(elDeg, -90.0, 90.0));
  const glm::dvec3 towardsEye(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  // Straight down or up, +z is the view direction: the up hint turns to the horizontal azimuth.
  const glm::dvec3 up = std::abs(std::cos(el)) < 1e-3
                            ? glm::dvec3(-std::cos(az), -std::sin(az), 0.0) * std::copysign(1.0, elDeg)
                            : glm::dvec3(0, 0, 1);
  return {-towardsEye, up};
}

// Camera::look with fovY in radians.
Camera lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, double fovY, double aspect,
              double zNear, double zFar) {
  Camera c;
  c.eye = glm::vec3(eye);
  c.view = glm::mat4(glm::lookAtRH(eye, target, up));
  c.proj = glm::mat4(glm::perspectiveRH_ZO(fovY, aspect, zNear, zFar));
  c.proj[1][1] *= -1.0f;  // Vulkan's y axis points down
  return c;
}

Camera lookFrom(const glm::dvec3& eye, const ViewAxes& axes, double fovY, double aspect, double zNear, double zFar) {
  return lookAt(eye, eye + axes.forward, axes.up, fovY, aspect, zNear, zFar);
}

// One image axis of Camera::fit. Points have lateral coordinate s_i and depth coordinate z_i along
// the view direction; with the eye at (e, ez) a point is inside the slab of tangents [lo, hi] when
// lo <= (s_i - e) / (z_i - ez) <= hi, i.e. A + hi ez <= e <= B + lo ez with A = max(s_i - hi z_i),
// B = min(s_i - lo z_i). The nearest feasible eye depth makes both bounds equal: both sides touch.
struct AxisFit {
  double lo, hi;  // tangents of the target's sides
  double a = -INFINITY, b = INFINITY;
  void add(double s, double z) {
    a = std::max(a, s - hi * z);
    b = std::min(b, s - lo * z);
  }
  double tightestEyeDepth() const { return (b - a) / (hi - lo); }
  // Centred for an eye depth at or behind tightestEyeDepth().
  double lateral(double ez) const { return 0.5 * (a + hi * ez + b + lo * ez); }
};

}  // namespace

Camera Camera::look(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up, double fovYDeg,
                    double aspect, double zNear, double zFar) {
  return lookAt(eye, target, up, glm::radians(fovYDeg), aspect, zNear, zFar);
}

glm::dvec3 Camera::toPixel(const glm::dvec3& p, int width, int height) const {
  const glm::dvec4 c = glm::dmat4(viewProj()) * glm::dvec4(p, 1.0);
  const glm::dvec3 ndc = glm::dvec3(c) / c.w;
  return {(ndc.x * 0.5 + 0.5) * width, (ndc.y * 0.5 + 0.5) * height, ndc.z};
}

Camera Camera::frame(const glm::dvec3& lo, const glm::dvec3& hi, double azDeg, double elDeg, double aspect,
                     double fovYDeg) {
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * glm::length(hi - lo), 1e-9);
  const double fovY = glm::radians(fovYDeg);
  const double fovX = 2.0 * std::atan(std::tan(0.5 * fovY) * aspect);
  const double dist = radius / std::sin(0.5 * std::min(fovX, fovY)) * 1.02;
  const ViewAxes axes = viewAxes(azDeg, elDeg);
  return lookFrom(centre - dist * axes.forward, axes, fovY, aspect, std::max(dist - 1.5 * radius, 0.01 * dist),
                  dist + 1.5 * radius);
}

Camera Camera::fit(std::span<const glm::dvec3> points, double azDeg, double elDeg, int width, int height,
                   const PixelRect& target, double fovYDeg) {
  if (points.empty()) throw std::invalid_argument("Camera::fit needs at least one point");
  const ViewAxes axes = viewAxes(azDeg, elDeg);
  // The orthonormal axes lookAtRH builds from forward and the hint.
  const glm::dvec3 right = glm::normalize(glm::cross(axes.forward, axes.up));
  const glm::dvec3 up = glm::cross(right, axes.forward);
  const double fovY = glm::radians(fovYDeg), aspect = double(width) / height;
  const double tanY = std::tan(0.5 * fovY), tanX = tanY * aspect;
  // Pixels to view-space tangents; image rows run down, view-space y up.
  AxisFit fx{(2.0 * target.x0 / width - 1.0) * tanX, (2.0 * target.x1 / width - 1.0) * tanX};
  AxisFit fy{(1.0 - 2.0 * target.y1 / height) * tanY, (1.0 - 2.0 * target.y0 / height) * tanY};
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  double zMin = INFINITY;
  for (const glm::dvec3& p : points) {
    const double z = glm::dot(p, axes.forward);
    fx.add(glm::dot(p, right), z);
    fy.add(glm::dot(p, up), z);
    zMin = std::min(zMin, z);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  // A point (or a set that projects to one) still gets a size that fp32 matrices resolve.
  const double extent = std::max(glm::length(hi - lo), 1e-4 * (1.0 + glm::length(hi + lo)));
  // The axis that needs the farther eye is tight; the other is centred. The nearest point stays a
  // twentieth of the extent in front of the eye.
  const double ez = std::min({fx.tightestEyeDepth(), fy.tightestEyeDepth(), zMin - 0.05 * extent});
  const glm::dvec3 eye = fx.lateral(ez) * right + fy.lateral(ez) * up + ez * axes.forward;
  double dMin = INFINITY, dMax = 0.0;
  for (const glm::dvec3& p : points) {
    const double d = glm::dot(p - eye, axes.forward);
    dMin = std::min(dMin, d);
    dMax = std::max(dMax, d);
  }
  // Room in depth for a surface that bulges between the given samples.
  const double room = 0.5 * extent;
  return lookFrom(eye, axes, fovY, aspect, std::max(dMin - room, 0.01 * dMin), dMax + room);
}

}  // namespace shapespline::render
