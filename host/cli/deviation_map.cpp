#include "deviation_map.h"

#include <shapespline/io/point_cloud.h>
#include <shapespline/part/closest_points.h>
#include <shapespline/render/colour_map.h>

#include <algorithm>

namespace shapespline::cli {
namespace {

constexpr std::size_t kBlockPoints = std::size_t{1} << 18;  // projected at a time: bounded memory
constexpr double kMarkerLift = 0.003;                        // of the way to the eye, as the distance map's lines

}  // namespace

DeviationCloud deviationCloud(const std::string& path, const std::string& field, const part::ProjectionTree& tree) {
  io::PointCloudReader reader(path, field);
  DeviationCloud cloud;
  cloud.count = reader.count();
  cloud.stride = (cloud.count + kMaxDeviationMarkers - 1) / kMaxDeviationMarkers;
  const part::ClosestPoints closest(tree);
  const bool signedDistance = false;
  std::vector<glm::dvec3> block;
  std::vector<part::FootPoint> feet;
  std::uint64_t index = 0;
  double sum = 0.0;
  while (reader.next(block, kBlockPoints)) {
    feet.resize(block.size());
    closest.of(block, feet, signedDistance, 0);
    for (std::size_t k = 0; k < block.size(); ++k, ++index) {
      cloud.maxDistance = std::max(cloud.maxDistance, feet[k].distance);
      sum += feet[k].distance;
      if (index % cloud.stride != 0) continue;
      cloud.points.push_back(block[k]);
      cloud.distance.push_back(feet[k].distance);
    }
  }
  cloud.meanDistance = sum / double(cloud.count);
  return cloud;
}

void addDeviationMarkers(render::Scene& scene, const DeviationCloud& cloud, double scaleTop, float sizePx,
                         const render::Camera& camera) {
  const glm::dvec3 eye(camera.eye);
  for (std::size_t k = 0; k < cloud.points.size(); ++k) {
    const glm::vec3 c = render::heatColour(scaleTop > 0.0 ? cloud.distance[k] / scaleTop : 0.0);
    const glm::dvec3& p = cloud.points[k];
    render::addMarker(scene.markers, p + (eye - p) * kMarkerLift, sizePx, {c.r, c.g, c.b, 1.0f});
  }
}

}  // namespace shapespline::cli
