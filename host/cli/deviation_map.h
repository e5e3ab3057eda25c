#pragma once
// `render MODEL --deviation CLOUD`: a scan (any cloud `project` reads) drawn over the part or surface
// it was taken of, each point coloured by its distance to it (render/colour_map.h), so that a
// deviation heat map is one command. Every point is projected (part/closest_points.h, fp64, every
// core) for the colour scale; at most kMaxDeviationMarkers of them, evenly spread through the
// cloud's order, are drawn.
#include <shapespline/part/projection_tree.h>
#include <shapespline/render/camera.h>
#include <shapespline/render/renderer.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace shapespline::cli {

inline constexpr std::size_t kMaxDeviationMarkers = std::size_t{1} << 18;

struct DeviationCloud {
  std::vector<glm::dvec3> points;  // those drawn: every `stride`-th point of the cloud
  std::vector<double> distance;    // of each drawn point to the model
  std::uint64_t count = 0;         // points in the cloud
  std::uint64_t stride = 1;
  double maxDistance = 0.0, meanDistance = 0.0;  // over the whole cloud
};

// Reads the cloud at `path` (errors name `field`) and projects every point onto `tree`.
DeviationCloud deviationCloud(const std::string& path, const std::string& field, const part::ProjectionTree& tree);

// The drawn points as square markers of `sizePx`, coloured by distance / scaleTop (0 when scaleTop
// is 0), each moved a little towards `camera`'s eye so that the surface they lie on does not hide them.
void addDeviationMarkers(render::Scene& scene, const DeviationCloud& cloud, double scaleTop, float sizePx,
                         const render::Camera& camera);

}  // namespace shapespline::cli
