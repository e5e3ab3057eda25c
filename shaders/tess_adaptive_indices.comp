#version 450
// Index pass of the adaptive tessellator (tess_layout.h): the triangles of core/tess_topology.cpp
// buildTessTopology for the frame's rates, in its order (per patch: the rings of sides 0..3, then
// the interior quads). Dispatches (AdaptivePush.mode): rings, one invocation per patch side (the
// zipper is sequential); quads, one invocation per quad (an indirect dispatch the layout pass
// sized), its patch found by binary search in QUADS.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = kAdaptBindingPatches) readonly buffer PatchBuf { uvec4 patchRecords[]; };
layout(std430, binding = kAdaptBindingEdges) readonly buffer EdgeBuf { uvec2 edges[]; };
layout(std430, binding = kAdaptBindingQuads) readonly buffer QuadBuf { uint quadFirst[]; };
layout(std430, binding = kAdaptBindingFrame) readonly buffer FrameBuf { uint frame[]; };
layout(std430, binding = kAdaptBindingIndices) writeonly buffer IndexOut { uint outIndices[]; };
layout(push_constant) uniform PushBlock { AdaptivePush pc; };
layout(constant_id = kSpecAdaptMode) const uint MODE = 0u;  // = pc.mode, a constant per pipeline

#include "tess_adaptive_grid.glsl"

uint gN, gM, gInterior, gCursor;

uint interiorVertex(uint i, uint j) { return gInterior + (i - 1u) * (gM - 1u) + (j - 1u); }

void emit(uint p, uint q, uint r) {
  outIndices[gCursor] = p;
  outIndices[gCursor + 1u] = q;
  outIndices[gCursor + 2u] = r;
  gCursor += 3u;
}

// Side s of patch (a, b): its edge polyline (corner, edge points, corner, increasing parameter)
// zipped to the outermost interior row. The outer side advances when its next point comes first
// in parameter ((k+1)/e < (i+2)/L, compared exactly in integers), the inner one on ties.
// Counter-clockwise in (u, v): as emitted on sides 0 and 1, reversed on sides 2 and 3.
void ring(uint a, uint b, uint s) {
  bool alongU = s == 0u || s == 2u;
  uvec2 edge = edges[sideEdge(a, b, s)];
  uint e = edge.x;
  uint c0, c1;
  if (alongU) {
    uint bb = b + (s == 2u ? 1u : 0u);
    c0 = cornerIndex(a, bb);
    c1 = cornerIndex(a + 1u, bb);
  } else {
    uint aa = a + (s == 1u ? 1u : 0u);
    c0 = cornerIndex(aa, b);
    c1 = cornerIndex(aa, b + 1u);
  }
  uint L = alongU ? gN : gM;
  bool reversed = s >= 2u;
  uint k = 0u, i = 0u;
  while (k < e || i + 2u < L) {
    bool advanceOuter = i + 2u >= L || (k < e && (k + 1u) * L < (i + 2u) * e);
    uint o0 = k == 0u ? c0 : edge.y + k - 1u;
    uint in0 = alongU ? interiorVertex(i + 1u, s == 0u ? 1u : gM - 1u) : interiorVertex(s == 3u ? 1u : gN - 1u, i + 1u);
    uint q, r;
    if (advanceOuter) {
      q = k + 1u == e ? c1 : edge.y + k;
      r = in0;
      ++k;
    } else {
      q = alongU ? interiorVertex(i + 2u, s == 0u ? 1u : gM - 1u) : interiorVertex(s == 3u ? 1u : gN - 1u, i + 2u);
      r = in0;
      ++i;
    }
    if (reversed) emit(o0, r, q);
    else emit(o0, q, r);
  }
}

uvec4 sideRates(uint a, uint b) {
  return uvec4(edges[sideEdge(a, b, 0u)].x, edges[sideEdge(a, b, 1u)].x, edges[sideEdge(a, b, 2u)].x,
               edges[sideEdge(a, b, 3u)].x);
}

void main() {
  uint k = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  uint patches = pc.patchesU * pc.patchesV;
  if (MODE == kAdaptModeRings) {
    if (k >= 4u * patches) return;
    uint p = k / 4u, s = k - 4u * p;
    uint a = p / pc.patchesV, b = p - a * pc.patchesV;
    uvec4 rec = patchRecords[p];
    gN = rec.x;
    gM = rec.y;
    gInterior = rec.z;
    uvec4 e = sideRates(a, b);
    uint before = 0u;  // triangles of the sides before s
    if (s > 0u) before += ringTriangles(e.x, gN);
    if (s > 1u) before += ringTriangles(e.y, gM);
    if (s > 2u) before += ringTriangles(e.z, gN);
    gCursor = rec.w + 3u * before;
    ring(a, b, s);
    return;
  }
  if (k >= frame[kAdaptFrameQuadCount]) return;
  uint lo = 0u, hi = patches - 1u;  // the last patch whose first quad is <= k (patches without
  while (lo < hi) {                 // quads share their successor's first quad and lose to it)
    uint mid = (lo + hi + 1u) / 2u;
    if (quadFirst[mid] <= k) lo = mid;
    else hi = mid - 1u;
  }
  uint p = lo, t = k - quadFirst[p];
  uint a = p / pc.patchesV, b = p - a * pc.patchesV;
  uvec4 rec = patchRecords[p];
  gN = rec.x;
  gM = rec.y;
  gInterior = rec.z;
  uvec4 e = sideRates(a, b);
  uint rings = ringTriangles(e.x, gN) + ringTriangles(e.y, gM) + ringTriangles(e.z, gN) + ringTriangles(e.w, gM);
  uint i = 1u + t / (gM - 2u), j = 1u + t % (gM - 2u);
  uint q00 = interiorVertex(i, j), q10 = interiorVertex(i + 1u, j), q01 = interiorVertex(i, j + 1u),
       q11 = interiorVertex(i + 1u, j + 1u);
  gCursor = rec.w + 3u * rings + 6u * t;
  emit(q00, q10, q11);
  emit(q00, q11, q01);
}
