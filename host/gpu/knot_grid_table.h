#pragma once
// The TABLE of the knot-vector grid kernels (shaders/bspline_curve_grid.comp,
// bspline_surface_grid.comp): for every non-empty knot interval, in grid-item order, and each of
// its S grid samples, the span and the basis derivatives that core tabulates for the CPU sampler
// (core/knot_table.h), as [span, N_0..N_{m-1}, N'_0..N'_{m-1}, N''_0..N''_{m-1}] (m = the order):
// the GPU grid then contracts the net as the uniform path does, with no de Boor–Cox per point.
// Private to gpu.
#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace shapespline::gpu {

struct KnotGridTable {
  std::vector<double> values;
  uint32_t offsetV = 0;  // surfaces: the index of the v direction's first entry
};

// nullopt where the per-point kernels must run instead: an interval needs scaled derivatives
// (knot widths below 2^-500, core/bspline.h bsplineBasisDerivsScaled), or the table would hold
// more than `maxValues` values.
std::optional<KnotGridTable> knotGridTable(const Curve& curve, int samples, size_t maxValues);
std::optional<KnotGridTable> knotGridTable(const Surface& surface, int samplesU, int samplesV, size_t maxValues);

}  // namespace shapespline::gpu
