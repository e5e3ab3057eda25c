#pragma once
// Which part of a Surface each patch of a tessellation (core/tess_topology.h) covers, and the uv a
// vertex carries: shared by the GPU tessellator (gpu/tessellator.h) and the Python module's CPU one.
// The tessellation's patch grid is the surface's patch range, or for a knot-vector B-spline its
// non-empty knot intervals (an empty interval has no surface to mesh).
#include <shapespline/core/surface.h>
#include <shapespline/core/tess_topology.h>

#include <array>
#include <vector>

namespace shapespline {

struct TessPatches {
  std::vector<int> u, v;  // model patch (or knot interval) index of tessellation patch a, b

  explicit TessPatches(const Surface& surface);
  int countU() const { return int(u.size()); }
  int countV() const { return int(v.size()); }
  // The model patch and local parameters of a tessellation sample, as Surface::evaluate takes them.
  SurfacePoint evaluate(const Surface& surface, const TessSample& s) const {
    return surface.evaluate(u[s.a], v[s.b], s.u, s.v);
  }
  // A vertex's uv: the global parameter, patch index + local (summed in float) for uniform
  // families, the knot parameters for knot-vector B-splines.
  std::array<float, 2> uv(const Surface& surface, const TessSample& s) const;
};

// Every patch and edge of `surface` at `rate` segments.
TessRates uniformTessRates(const Surface& surface, int rate);

}  // namespace shapespline
