#include <shapespline/render/camera.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace shapespline::render {

glm::dvec3 Camera::toPixel(const glm::dvec3& p, int width, int height) const {
  const glm::dvec4 c = glm::dmat4(viewProj()) * glm::dvec4(p, 1.0);
  const glm::dvec3 ndc = glm::dvec3(c) / c.w;
  return {(ndc.x * 0.5 + 0.5) * width, (ndc.y * 0.5 + 0.5) * height, ndc.z};
}

Camera Camera::frame(const glm::dvec3& lo, const glm::dvec3& hi, double azDeg, double elDeg, double aspect,
                     double fovYDeg) {
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * glm::length(hi - lo), 1e-9);
  const double az = glm::radians(azDeg), el = glm::radians(std::clamp(elDeg, -90.0, 90.0));
  const glm::dvec3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  const double fovY = glm::radians(fovYDeg);
  const double fovX = 2.0 * std::atan(std::tan(0.5 * fovY) * aspect);
  const double dist = radius / std::sin(0.5 * std::min(fovX, fovY)) * 1.02;
  const glm::dvec3 up = std::abs(std::cos(el)) < 1e-3 ? glm::dvec3(-std::cos(az), -std::sin(az), 0.0) * std::copysign(1.0, elDeg)
                                                      : glm::dvec3(0, 0, 1);
  Camera c;
  c.eye = glm::vec3(centre + dist * dir);
  c.view = glm::mat4(glm::lookAtRH(centre + dist * dir, centre, up));
  c.proj = glm::mat4(glm::perspectiveRH_ZO(fovY, aspect, std::max(dist - 1.5 * radius, 0.01 * dist), dist + 1.5 * radius));
  c.proj[1][1] *= -1.0f;  // Vulkan's y axis points down
  return c;
}

}  // namespace shapespline::render
