#version 450
// Layout pass of the adaptive tessellator (tess_layout.h): one workgroup. Edge rates are the max of
// the rates of the two patches along the edge (TessRates' default), so both patches of an edge read
// one rate. Vertex and index counts are those of core/tess_topology.cpp, numbered the same way, and
// their exclusive prefix sums give each corner, edge and patch its first vertex and each patch its
// first index and the index of its first interior quad; the totals go into the indirect draw
// command and the indirect dispatch of the interior-row pass.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = kAdaptBindingRates) readonly buffer RateBuf { uvec2 rates[]; };
layout(std430, binding = kAdaptBindingPatches) writeonly buffer PatchBuf { uvec4 patchRecords[]; };
layout(std430, binding = kAdaptBindingEdges) writeonly buffer EdgeBuf { uvec2 edges[]; };
layout(std430, binding = kAdaptBindingFrame) buffer FrameBuf { uint frame[]; };
layout(std430, binding = kAdaptBindingQuads) writeonly buffer QuadBuf { uint quadFirst[]; };
layout(std430, binding = kAdaptBindingRows) writeonly buffer RowBuf { uint rowFirst[]; };
layout(std430, binding = kAdaptBindingView) readonly buffer ViewBuf { AdaptiveViewBlock view; };
layout(push_constant) uniform PushBlock { AdaptivePush pc; };

#include "tess_adaptive_grid.glsl"

shared uint sVertexSums[kAdaptMaxWorkgroup], sIndexSums[kAdaptMaxWorkgroup], sRowSums[kAdaptMaxWorkgroup];

// The rate of u-edge (a, b) (at v-boundary b of patch column a) and of v-edge (a, b) (at
// u-boundary a of patch row b): the max of the patches on either side; an open boundary has one.
uint edgeRateU(uint a, uint b) {
  uint r = b < pc.patchesV ? rates[a * pc.patchesV + b].x : 0u;
  if (b > 0u || pc.closedV != 0u) r = max(r, rates[a * pc.patchesV + (b + pc.patchesV - 1u) % pc.patchesV].x);
  return r;
}
uint edgeRateV(uint a, uint b) {
  uint r = a < pc.patchesU ? rates[a * pc.patchesV + b].y : 0u;
  if (a > 0u || pc.closedU != 0u) r = max(r, rates[((a + pc.patchesU - 1u) % pc.patchesU) * pc.patchesV + b].y);
  return r;
}
uint edgeRate(uint x) {
  uint eu = uEdgeCount();
  return x < eu ? edgeRateU(x / boundariesV(), x % boundariesV()) : edgeRateV((x - eu) / pc.patchesV, (x - eu) % pc.patchesV);
}

// A 1-D dispatch of `invocations` as (x, y, 1) workgroups within the device's x limit.
void writeDispatch(uint word, uint invocations) {
  uint groups = (invocations + gl_WorkGroupSize.x - 1u) / gl_WorkGroupSize.x;
  uint x = min(groups, view.limits.w);
  frame[word] = x;
  frame[word + 1u] = x == 0u ? 0u : (groups + x - 1u) / x;
  frame[word + 2u] = 1u;
}

// Vertices of element e of the numbering: corners, u-edges, v-edges, patch interiors.
uint vertexCountOf(uint e) {
  uint corners = cornerCount(), eu = uEdgeCount(), ev = vEdgeCount();
  if (e < corners) return 1u;
  e -= corners;
  if (e < eu + ev) return edgeRate(e) - 1u;
  uvec2 r = rates[e - eu - ev];
  return (r.x - 1u) * (r.y - 1u);
}

// Writes element e's record, given its first vertex.
void writeVertexRecord(uint e, uint first) {
  uint corners = cornerCount(), eu = uEdgeCount(), ev = vEdgeCount();
  if (e < corners) return;
  e -= corners;
  if (e < eu + ev) {
    edges[e] = uvec2(edgeRate(e), first);
    return;
  }
  uint p = e - eu - ev;
  patchRecords[p].xyz = uvec3(rates[p], first);
}

// Indices of patch p's four transition rings, and of its interior quads.
uint ringIndexCountOf(uint p) {
  uint a = p / pc.patchesV, b = p - a * pc.patchesV;
  uvec4 e = uvec4(edgeRate(sideEdge(a, b, 0u)), edgeRate(sideEdge(a, b, 1u)), edgeRate(sideEdge(a, b, 2u)),
                  edgeRate(sideEdge(a, b, 3u)));
  return 3u * ringsTriangles(rates[p], e);
}
uint quadIndexCountOf(uint p) { return 3u * quadTriangles(rates[p]); }

void main() {
  uint t = gl_LocalInvocationID.x, threads = gl_WorkGroupSize.x;
  uint patches = pc.patchesU * pc.patchesV;
  uint elements = cornerCount() + uEdgeCount() + vEdgeCount() + patches;
  // Each invocation takes one contiguous block of elements and one of patches.
  uint vBlock = (elements + threads - 1u) / threads, pBlock = (patches + threads - 1u) / threads;
  uint v0 = min(t * vBlock, elements), v1 = min(v0 + vBlock, elements);
  uint p0 = min(t * pBlock, patches), p1 = min(p0 + pBlock, patches);
  uint vs = 0u, is = 0u, rs = 0u;
  for (uint e = v0; e < v1; ++e) vs += vertexCountOf(e);
  for (uint p = p0; p < p1; ++p) {
    is += ringIndexCountOf(p) + quadIndexCountOf(p);
    rs += rowBlocks(rates[p]);
  }
  sVertexSums[t] = vs;
  sIndexSums[t] = is;
  sRowSums[t] = rs;
  barrier();
  if (t == 0u) {  // exclusive scan of the block sums (at most kAdaptMaxWorkgroup)
    uint va = 0u, ia = 0u, ra = 0u;
    for (uint k = 0u; k < threads; ++k) {
      uint x = sVertexSums[k], y = sIndexSums[k], w = sRowSums[k];
      sVertexSums[k] = va;
      sIndexSums[k] = ia;
      sRowSums[k] = ra;
      va += x;
      ia += y;
      ra += w;
    }
    frame[0] = ia;  // VkDrawIndexedIndirectCommand: indexCount, instanceCount, firstIndex, vertexOffset, firstInstance
    frame[1] = 1u;
    frame[2] = 0u;
    frame[3] = 0u;
    frame[4] = 0u;
    frame[kAdaptFrameVertexCount] = va;
    frame[kAdaptFrameRowCount] = ra;
    writeDispatch(kAdaptFrameRowDispatch, ra);
  }
  barrier();
  uint vertex = sVertexSums[t], index = sIndexSums[t], row = sRowSums[t];
  for (uint e = v0; e < v1; ++e) {
    writeVertexRecord(e, vertex);
    vertex += vertexCountOf(e);
  }
  for (uint p = p0; p < p1; ++p) {
    patchRecords[p].w = index;
    index += ringIndexCountOf(p);
    quadFirst[p] = index;
    index += quadIndexCountOf(p);
    rowFirst[p] = row;
    row += rowBlocks(rates[p]);
  }
}
