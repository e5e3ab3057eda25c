#pragma once
// A projection tree (part/projection_tree.h) as the GPU search reads it (shaders/projection_layout.h):
// its nodes, leaves, cells, patches, trim runs, faces, trim classifiers and patch lookups flattened
// into arrays of REALs and uints. Positions are made relative to the tree's centre and parameters to
// each face's low corner, so that fp32 keeps the digits a part far from 0 would lose.
#include <shapespline/core/sample_grid.h>
#include <shapespline/gpu/closest_point_search.h>
#include <shapespline/part/projection_tree.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <vector>

namespace shapespline::part {

struct FlatProjectionTree {
  gpu::ProjectionTables tables;
  glm::dvec3 origin{0.0};                // subtracted from every position
  std::vector<glm::dvec2> faceCorners;  // per tree face: subtracted from its parameters
};

// The tables of a surface or part tree (std::invalid_argument for a curve's). `tolerance` as
// ClosestPoints takes it; `precision` sets the step and on-surface thresholds the kernel uses.
FlatProjectionTree flattenProjectionTree(const ProjectionTree& tree, double tolerance, Precision precision);

}  // namespace shapespline::part
