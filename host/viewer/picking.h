#pragma once
// Picking a control point with the mouse: the point whose projection lies nearest to the cursor.
#include <shapespline/render/camera.h>

#include <glm/vec3.hpp>

#include <span>

namespace shapespline::viewer {

// How far from a projected point a click still picks it.
inline constexpr double kPickRadiusPx = 10.0;

// Index of the point nearest to pixel (x, y) among those projecting within maxPx and in front of
// the camera (depth in [0, 1]); -1 when there is none.
int pickPoint(std::span<const glm::dvec3> points, const render::Camera& camera, int width, int height, double x,
              double y, double maxPx = kPickRadiusPx);

}  // namespace shapespline::viewer
