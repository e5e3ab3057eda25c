#pragma once
// Tessellation topology of a patch grid (data, no Vulkan; built on the host once per rate
// configuration, OpenSubdiv far/ style). Every unique vertex — patch-grid corner, patch-edge
// interior point, patch interior point — appears exactly once in a global vertex list with one
// canonical (patch, u, v) sample, so a vertex on a shared edge is evaluated once and referenced by
// the index lists of both patches: watertight by construction, bitwise.
//
// Patch grid: patchesU x patchesV patches (a, b), row-major (a outer), local (u,v) in [0,1]^2.
// Closed directions wrap: the boundary after the last patch is the first one.
// Rates:
//  * patch (a,b) has an interior rate (rateU, rateV) = segments along u and v (>= 1). The interior
//    grid is (i/n, j/m), 0 < i < n, 0 < j < m with n = max(rateU, 2), m = max(rateV, 2) (rate 1
//    fans the four edges to the patch centre);
//  * each patch edge has its own rate (segments along it); by default the max of the rates of the
//    two patches that share it along that direction, or caller-chosen. An edge's points are
//    k/e, 0 < k < e, in the direction of increasing u (or v), the same for both neighbours.
//  * a transition ring stitches each edge to the interior grid: a "zipper" between the edge
//    polyline and the outermost interior row/column, advancing whichever side lags in parameter.
// Triangles are counter-clockwise in the local (u,v) plane of their patch, i.e. front-facing
// towards Q_u x Q_v; the triangles of patch p are indices [firstIndex[p], firstIndex[p] + count).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shapespline {

struct TessRates {
  int patchesU = 0, patchesV = 0;
  bool closedU = false, closedV = false;
  // Per patch (patchesU * patchesV, row-major), or a single value for every patch.
  std::vector<int> rateU{8}, rateV{8};
  // Optional per-edge rates (empty: the max of the neighbouring patches' rates along the edge).
  // edgeU[a * boundariesV() + b]: edge at v-boundary b of patch column a (runs along u).
  // edgeV[a * patchesV + b]: edge at u-boundary a of patch row b (runs along v).
  std::vector<int> edgeU, edgeV;

  int boundariesU() const { return closedU ? patchesU : patchesU + 1; }
  int boundariesV() const { return closedV ? patchesV : patchesV + 1; }
  int patchRateU(int a, int b) const { return rateU.size() == 1 ? rateU[0] : rateU[size_t(a) * patchesV + b]; }
  int patchRateV(int a, int b) const { return rateV.size() == 1 ? rateV[0] : rateV[size_t(a) * patchesV + b]; }

  // Every patch and edge at `rate` segments per side.
  static TessRates uniform(int patchesU, int patchesV, bool closedU, bool closedV, int rate);
};

// One evaluation: patch (a, b) of the grid at local (u, v).
struct TessSample {
  int a = 0, b = 0;
  double u = 0.0, v = 0.0;
};

struct TessTopology {
  TessRates rates;                    // as given, edge rates resolved (edgeU/edgeV filled)
  std::vector<TessSample> samples;    // samples[k], k < vertexCount(): the canonical sample of vertex k;
                                      // then the extra normal samples of shared vertices
  std::vector<uint32_t> extraFirst;   // per vertex: first extra sample (>= vertexCount()) and count:
  std::vector<uint32_t> extraCount;   //   the other patches that contain the vertex (normal averaging)
  std::vector<uint32_t> indices;      // triangle list, 3 per triangle
  std::vector<uint32_t> interiorFirst;  // per patch: its first interior vertex; the (n-1) x (m-1)
                                        //   interior grid follows row-major (i outer), n = max(rateU, 2)
  std::vector<uint32_t> firstIndex;   // per patch
  std::vector<uint32_t> indexCount;   // per patch
  // Per patch and side (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0), the boundary polyline as global
  // vertex indices in increasing u (sides 0, 2) or v (sides 1, 3), corners included.
  std::vector<std::vector<uint32_t>> sides;
  uint32_t vertexCount = 0;
  uint32_t cornerCount = 0, edgeVertexCount = 0;  // vertices [0, corners), [corners, corners+edge), interior

  size_t patchCount() const { return firstIndex.size(); }
  const std::vector<uint32_t>& side(int a, int b, int s) const {
    return sides[(size_t(a) * rates.patchesV + b) * 4 + s];
  }
};

// Builds the topology. Throws std::invalid_argument for a non-positive size or rate, or per-patch /
// per-edge arrays of the wrong size.
TessTopology buildTessTopology(const TessRates& rates);

// The undirected edges of a triangle list, each once (wireframe index list, 2 per line).
std::vector<uint32_t> triangleEdges(const std::vector<uint32_t>& triangles);

}  // namespace shapespline
