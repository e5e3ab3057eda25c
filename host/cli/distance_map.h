#pragma once
// `render --distance`: a surface at one parameter value coloured by how far each of its points lies
// from the point of the same (u, v) at another value (render/colour_map.h), evaluated on the CPU in
// fp64 and drawn as a coloured triangle mesh with its patch lines, so that a change of λ or α too
// small to see in the shape reads as colour.
#include <shapespline/core/surface.h>
#include <shapespline/render/camera.h>
#include <shapespline/render/renderer.h>

#include <glm/vec3.hpp>

#include <vector>

namespace shapespline::cli {

struct DistanceMesh {
  int n = 0;                         // segments per patch edge
  std::vector<glm::dvec3> points;    // of `to`, (n+1)^2 per patch, row-major, patch after patch
  std::vector<double> distance;      // |to - from| at each point
  double maxDistance = 0.0;
  // The distance the colour scale ends at: maxDistance, but at least kSmallestScale of the drawn
  // surface's bounding-box diagonal, so that a change too small to matter stays pale instead of
  // being stretched over the whole scale.
  double scaleTop = 0.0;
};
inline constexpr double kSmallestScale = 0.02;

// `from` and `to`: one model at two parameter values (the same patches).
DistanceMesh distanceMesh(const Surface& from, const Surface& to, int n);

// The mesh's triangles coloured by distance / scaleTop into
// scene.markers, and its patch edges and the lines halfway across each patch as dark lines, drawn
// a little towards `camera`'s eye so that the triangles under them do not hide them.
void addDistanceMesh(render::Scene& scene, const DistanceMesh& mesh, const render::Camera& camera);

}  // namespace shapespline::cli
