#pragma once
// Closest points on the GPU (shaders/closest_points.comp): the search half of part::ClosestPoints
// over a projection tree flattened into tables (shaders/projection_layout.h; part flattens its tree,
// part/projection_tables.h, since gpu does not know parts). The tables are uploaded once; each
// search() runs the queries in dispatches of a bounded size and reads the hits back in fp64.
#include <shapespline/core/sample_grid.h>
#include <shapespline/gpu/evaluator_options.h>
#include <shapespline/shaders/projection_layout.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/context.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace shapespline::gpu {

class KernelSet;

// A tree as closest_points.comp reads it: REALs, uints and the patches' power-form coefficients, with
// each table's offset in `offsets` (queryCount left 0). Positions relative to the tree's origin.
struct ProjectionTables {
  std::vector<double> reals;
  std::vector<uint32_t> ints;
  std::vector<glm::dvec4> coefficients;
  int degreeU = 0, degreeV = 0;  // every patch's coefficients padded to these degrees
  projection_layout::ProjectionPush offsets{};
};

// What the search found for one query (projection_layout.h's hit), in fp64.
struct ProjectionHit {
  double d2 = 0.0;
  glm::dvec3 point{0.0};  // relative to the origin
  glm::dvec2 uv{0.0};     // relative to the face's domain's low corner
  glm::dvec2 local{0.0};  // in patch (i, j)
  glm::dvec3 du{0.0}, dv{0.0};
  uint32_t face = 0, i = 0, j = 0, flags = 0;  // flags: projection_layout kHit*
};

class ClosestPointSearch {
 public:
  // Uploads the tables. Throws std::length_error naming the table when one exceeds the device's
  // storage-buffer range, std::runtime_error for fp64 on a device without shaderFloat64.
  ClosestPointSearch(std::shared_ptr<vk::Context> ctx, Precision precision, const ProjectionTables& tables,
                     EvaluatorOptions options = {});
  ~ClosestPointSearch();
  // hits[k] for queries[k] (relative to the origin).
  void search(std::span<const glm::dvec3> queries, std::span<ProjectionHit> hits);

  // Queries per dispatch: the query and hit buffers' size (bounded memory, and no dispatch long
  // enough for a driver's watchdog).
  static constexpr size_t kQueriesPerDispatch = size_t{1} << 16;

 private:
  std::unique_ptr<KernelSet> kernels_;
  uint32_t loopBudget_ = 0;  // see closest_point_search.cpp
  int degreeU_ = 0, degreeV_ = 0;
  vk::Buffer coefficients_, reals_, ints_;
  projection_layout::ProjectionPush offsets_{};
};

}  // namespace shapespline::gpu
