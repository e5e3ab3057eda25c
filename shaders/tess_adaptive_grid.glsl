// The patch grid of the adaptive tessellator's passes (tess_layout.h): counts, the EDGES index of a
// patch side, the corner numbering and the triangle counts of core/tess_topology.cpp. The includer
// declares `pc` (AdaptivePush).
#ifndef SHAPESPLINE_TESS_ADAPTIVE_GRID_GLSL
#define SHAPESPLINE_TESS_ADAPTIVE_GRID_GLSL

uint boundariesU() { return pc.closedU != 0u ? pc.patchesU : pc.patchesU + 1u; }
uint boundariesV() { return pc.closedV != 0u ? pc.patchesV : pc.patchesV + 1u; }
uint cornerCount() { return boundariesU() * boundariesV(); }
uint uEdgeCount() { return pc.patchesU * boundariesV(); }  // TessRates::edgeU: a * boundariesV + b
uint vEdgeCount() { return boundariesU() * pc.patchesV; }  // TessRates::edgeV: a * patchesV + b
uint cornerIndex(uint ca, uint cb) { return (ca % boundariesU()) * boundariesV() + cb % boundariesV(); }

// EDGES index of side s of patch (a, b): 0 v = 0, 1 u = 1, 2 v = 1, 3 u = 0 (TessTopology::sides).
uint sideEdge(uint a, uint b, uint s) {
  if (s == 0u || s == 2u) return a * boundariesV() + (b + (s == 2u ? 1u : 0u)) % boundariesV();
  return uEdgeCount() + ((a + (s == 1u ? 1u : 0u)) % boundariesU()) * pc.patchesV + b;
}

// A transition ring zips the e + 1 points of an edge to the L - 1 points of the outermost
// interior row: one triangle per step of either.
uint ringTriangles(uint e, uint L) { return e + L - 2u; }

// Triangles of the four rings of a patch with rates r = (n, m) and side rates e (sides 0..3), and
// of its interior quads.
uint ringsTriangles(uvec2 r, uvec4 e) {
  return ringTriangles(e.x, r.x) + ringTriangles(e.y, r.y) + ringTriangles(e.z, r.x) + ringTriangles(e.w, r.y);
}
uint quadTriangles(uvec2 r) { return 2u * (r.x - 2u) * (r.y - 2u); }

// Interior rows one vertex-pass invocation evaluates for a patch with m - 1 samples a row: at
// least 32 samples, so that loading the patch's net is shared by enough of them.
uint rowsPerBlock(uint m) { return max(1u, 32u / (m - 1u)); }
uint rowBlocks(uvec2 r) { return (r.x - 2u) / rowsPerBlock(r.y) + 1u; }

#endif  // SHAPESPLINE_TESS_ADAPTIVE_GRID_GLSL
