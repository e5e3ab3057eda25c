#pragma once
// Closest points with the search on the GPU (gpu/closest_point_search.h, shaders/closest_points.comp)
// and each foot finished on the host by the CPU's own code (ClosestPoints::finish: the face's id, the
// normal, the sign), so both paths give the same kind of answer. A query past the kernel's stack or
// loop budget is searched again on the CPU. Surfaces and parts; a curve's tree is refused.
#include <shapespline/core/sample_grid.h>
#include <shapespline/gpu/evaluator_options.h>
#include <shapespline/part/closest_points.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <memory>
#include <span>
#include <vector>

namespace shapespline::vk {
class Context;
}
namespace shapespline::gpu {
class ClosestPointSearch;
}

namespace shapespline::part {

class GpuClosestPoints {
 public:
  // The tree of `cpu` (which must outlive this object) uploaded to ctx's device. Throws
  // std::invalid_argument for a curve's tree, std::length_error when a table exceeds the device's
  // buffer range, std::runtime_error for fp64 on a device without it.
  GpuClosestPoints(const ClosestPoints& cpu, std::shared_ptr<vk::Context> ctx, Precision precision,
                   gpu::EvaluatorOptions options = {});
  ~GpuClosestPoints();

  // out[k] = the foot of points[k], finished on `threads` threads (0: every core).
  void of(std::span<const glm::dvec3> points, std::span<FootPoint> out, bool signedDistance, int threads);
  // How many queries the last of() searched again on the CPU (past the kernel's stack or loop budget,
  // or a value fp32 could not hold).
  size_t redone() const { return redone_; }

 private:
  const ClosestPoints& cpu_;
  glm::dvec3 origin_{0.0};
  std::vector<glm::dvec2> faceCorners_;
  std::unique_ptr<gpu::ClosestPointSearch> search_;
  size_t redone_ = 0;
};

}  // namespace shapespline::part
