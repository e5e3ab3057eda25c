// Tessellation and render layouts shared by shaders/tessellate_pack.comp, shaders/render_*.vert and
// host/gpu/tessellator.* / host/render/*: compiled as GLSL (after common.glsl or with
// SHAPESPLINE_GLSL defined) and as C++ (host mirrors with static_asserts).
//
// ---- Tessellated vertex (the VERTEX buffer written by SurfaceTessellator::record) ---------------
//  32 bytes, tightly packed floats, usable as vertex input binding with stride kTessVertexStride:
//    location 0: position  R32G32B32_SFLOAT at byte 0   (model space)
//    location 1: normal    R32G32B32_SFLOAT at byte 12  (unit, docs/math.md §5.3 + shared-vertex mean)
//    location 2: uv        R32G32_SFLOAT    at byte 24  (global (U,V) = (i+u, j+v) of the owner patch)
// ---- Grid pass (tessellate_grid.comp; descriptor set 0 of the evaluation kernels) -------------
//  One invocation = one row a (0..n) of one patch's (n+1) x (m+1) grid (u = a/n, v = b/m): point
//  and docs/math.md §5.3 normal. Interior samples (0<a<n, 0<b<m) are final vertices and go straight into
//  VERTICES; perimeter samples go to BOUNDARY for the pack pass (shared vertices).
//  0 NET, 1 PARAMS, 2 VERTS as layout.h
//  3 PATCHES  (uvec4) per patch: n, m, first interior vertex, first BOUNDARY slot
//  4 ROWS     (uvec2) per invocation: patch index (row-major a * patchesV + b), row a; the inner
//                     rows of every patch first, then rows 0 and n (so SIMD lanes agree on where
//                     their samples go)
//  5 VERTICES (vec4)  output, 2 vec4 per vertex (the layout above)
//  6 BOUNDARY (REAL4) perimeter samples, 2 per slot: (point, 0), (normal, 0); slot = first slot of
//                     the patch + tessPerimeterSlot(n, m, a, b)
// ---- Pack pass (tessellate_pack.comp): the corner and edge vertices -----------------------------
//  Vertex k < boundaryVertexCount takes its position from its canonical source SOURCES[k] and the
//  normalised mean of the normals of SOURCES[k] and its extra sources (the other patches sharing
//  the vertex). A source is a BOUNDARY slot, or (bit 31 set) a sample of the list-mode planes
//  (edge points that are not on their patch's grid: an edge rate differing from the patch rate).
//  2 POINTS  (REAL)  packed xyz point plane of surface_eval (list mode)
//  3 NORMALS (REAL)  packed xyz normal plane
//  4 UV      (vec2)  per boundary vertex: global (U,V) of its canonical sample
//  5 EXTRA   (uvec2) per boundary vertex: first and count of its extra sources in SOURCES
//  6 VERTICES (vec4) output
//  7 BOUNDARY (REAL4) the grid pass's perimeter samples
//  8 SOURCES (uint)  canonical source of each boundary vertex, then the extra sources
#ifndef SHAPESPLINE_SHADERS_TESS_LAYOUT_H
#define SHAPESPLINE_SHADERS_TESS_LAYOUT_H

#ifdef SHAPESPLINE_GLSL
#define TS_CONST(type, name, value) const type name = value
#define TS_UINT uint
#define TS_FUNC
#else
#include <cstddef>
#include <cstdint>
namespace shapespline::gpu::tess_layout {
#define TS_CONST(type, name, value) inline constexpr type name = value
#define TS_UINT uint32_t
#define TS_FUNC constexpr
#endif

TS_CONST(TS_UINT, kTessGridBindingPatches, 3u);
TS_CONST(TS_UINT, kTessGridBindingRows, 4u);
TS_CONST(TS_UINT, kTessGridBindingVertices, 5u);
TS_CONST(TS_UINT, kTessGridBindingBoundary, 6u);

TS_CONST(TS_UINT, kTessBindingPoints, 2u);
TS_CONST(TS_UINT, kTessBindingNormals, 3u);
TS_CONST(TS_UINT, kTessBindingUV, 4u);
TS_CONST(TS_UINT, kTessBindingExtra, 5u);
TS_CONST(TS_UINT, kTessBindingVertices, 6u);
TS_CONST(TS_UINT, kTessBindingBoundary, 7u);
TS_CONST(TS_UINT, kTessBindingSources, 8u);
TS_CONST(TS_UINT, kTessBindingCount, 9u);
TS_CONST(TS_UINT, kTessListSource, 0x80000000u);  // SOURCES bit: a list-mode sample
TS_CONST(TS_UINT, kTessSpecListSources, 11u);     // pack spec constant: 1 when SOURCES has list samples

TS_CONST(TS_UINT, kTessVertexFloats, 8u);
TS_CONST(TS_UINT, kTessVertexStride, 32u);
TS_CONST(TS_UINT, kTessOffsetPosition, 0u);
TS_CONST(TS_UINT, kTessOffsetNormal, 12u);
TS_CONST(TS_UINT, kTessOffsetUV, 24u);

// Push constants of tessellate_pack.comp.
struct TessPackPush {
  TS_UINT boundaryVertexCount;
  TS_UINT pad0;
  TS_UINT pad1;
  TS_UINT pad2;
};

// Push constants of tessellate_grid.comp; the net/α fields are those of layout.h EvalPush, under
// the same names (surface_patch.glsl reads them).
struct TessGridPush {
  TS_UINT invocations;   // of this dispatch
  TS_UINT patchesV;      // patches per row of the tessellated patch range
  TS_UINT firstSpanU;    // model index of patch row 0
  TS_UINT firstSpanV;
  TS_UINT netCols;
  TS_UINT netOffsetU;
  TS_UINT netOffsetV;
  TS_UINT rows;          // α-EB vertex counts (α and V index wrap)
  TS_UINT cols;
  TS_UINT alphaOffset;
  // Uniform rates (spec constant kSpecUniformRates = 1): every patch has the (rateN+1) x (rateM+1)
  // grid, patch p's interior starts at interiorFirst + p (n-1)(m-1), its slots at p 2(n+m); two
  // dispatches: edgeRows = 0, invocation q covers rowsPerInvocation inner rows of one patch
  // (ceil((n-1)/rowsPerInvocation) invocations a patch); edgeRows = 1, rows 0 and n of patch q.
  // Then every SIMD lane agrees on where a sample goes.
  // Otherwise PATCHES and ROWS say it (one dispatch).
  TS_UINT rateN;
  TS_UINT rateM;
  TS_UINT interiorFirst;
  TS_UINT edgeRows;
  TS_UINT rowsPerInvocation;  // inner rows per invocation (uniform rates)
  TS_UINT pad0;
};

// Slot of perimeter sample (a, b) of an (n+1) x (m+1) patch grid among its 2(n+m) perimeter
// samples: row 0, row n, then (b = 0, b = m) of each inner row. Shared by host and shader.
TS_FUNC TS_UINT tessPerimeterSlot(TS_UINT n, TS_UINT m, TS_UINT a, TS_UINT b) {
  if (a == 0u) return b;
  if (a == n) return m + 1u + b;
  return 2u * (m + 1u) + 2u * (a - 1u) + (b == 0u ? 0u : 1u);
}

// ---- Adaptive tessellation (tess_adaptive_*.comp, host/gpu/adaptive_tessellator.*) -----------
//  0 NET, 1 PARAMS, 2 VERTS as layout.h
//  3 VIEW     (AdaptiveViewBlock) the frame's camera and options (vkCmdUpdateBuffer per record)
//  4 RATES    (uvec2) per patch: the rates (n, m) of the last frame; (0, 0) before the first
//  5 PATCHES  (uvec4) per patch: n, m, first interior vertex, first index (layout pass)
//  6 EDGES    (uvec2) per edge, the u-edges (TessRates::edgeU order) then the v-edges: rate, first
//                     edge vertex
//  7 FRAME    (uint)  VkDrawIndexedIndirectCommand at 0 (5 words), then kAdaptFrame* counters and
//                     the VkDispatchIndirectCommand of the interior-row pass
//  8 VERTICES (vec4)  output, 2 vec4 per vertex (the layout above)
//  9 INDICES  (uint)  output triangle list
// 11 QUADS    (uint)  per patch: the index (into INDICES) of its first interior-quad triangle
// 12 ROWS     (uint)  per patch: its first block of interior rows (tess_adaptive_grid.glsl rowBlocks)
// Vertex numbering and triangles are core/tess_topology.cpp buildTessTopology's: corners, u-edge
// points, v-edge points, patch interiors; per patch its four transition rings, then its quads.
TS_CONST(TS_UINT, kAdaptBindingView, 3u);
TS_CONST(TS_UINT, kAdaptBindingRates, 4u);
TS_CONST(TS_UINT, kAdaptBindingPatches, 5u);
TS_CONST(TS_UINT, kAdaptBindingEdges, 6u);
TS_CONST(TS_UINT, kAdaptBindingFrame, 7u);
TS_CONST(TS_UINT, kAdaptBindingVertices, 8u);
TS_CONST(TS_UINT, kAdaptBindingIndices, 9u);
TS_CONST(TS_UINT, kAdaptBindingQuads, 11u);
TS_CONST(TS_UINT, kAdaptBindingRows, 12u);
TS_CONST(TS_UINT, kAdaptFrameVertexCount, 5u);
TS_CONST(TS_UINT, kAdaptFrameCulled, 6u);
TS_CONST(TS_UINT, kAdaptFrameClamped, 7u);
TS_CONST(TS_UINT, kAdaptFrameNear, 8u);
TS_CONST(TS_UINT, kAdaptFrameRowCount, 17u);        // interior row blocks of all patches
TS_CONST(TS_UINT, kAdaptFrameRowDispatch, 18u);     // 3 words: x, y, z workgroups
TS_CONST(TS_UINT, kAdaptFrameWords, 24u);
TS_CONST(TS_UINT, kAdaptMaxWorkgroup, 256u);  // the layout pass's shared arrays
// mode of each pass's dispatches (AdaptivePush.mode, and the specialization constant kSpecAdaptMode:
// one pipeline per mode, so that llvmpipe, which runs an if's body whatever the lane mask, compiles
// only the mode's code)
TS_CONST(TS_UINT, kSpecAdaptMode, 11u);
TS_CONST(TS_UINT, kAdaptModeRates, 1u);    // rates: one invocation per patch
TS_CONST(TS_UINT, kAdaptModeCorners, 0u);  // mesh: one invocation per corner
TS_CONST(TS_UINT, kAdaptModeEdgesU, 2u);   // mesh: one invocation per u-edge (its points along u; the rings of sides 0, 2)
TS_CONST(TS_UINT, kAdaptModeEdgesV, 3u);   // mesh: one invocation per v-edge (its points along v; the rings of sides 1, 3)
TS_CONST(TS_UINT, kAdaptModeRows, 1u);     // mesh: one invocation per block of interior rows (their points and quads)

// Push constants of every tess_adaptive_*.comp pass; the net/α fields are those of layout.h
// EvalPush, under the same names (surface_patch.glsl reads them).
struct AdaptivePush {
  TS_UINT mode;
  TS_UINT patchesU;
  TS_UINT patchesV;
  TS_UINT closedU;
  TS_UINT closedV;
  TS_UINT firstSpanU;
  TS_UINT firstSpanV;
  TS_UINT netCols;
  TS_UINT netOffsetU;
  TS_UINT netOffsetV;
  TS_UINT rows;
  TS_UINT cols;
  TS_UINT alphaOffset;
  TS_UINT pad0;
  TS_UINT pad1;
  TS_UINT pad2;
};

// Push constants of render_surface.* and render_overlay.* (host/render/renderer.cpp).
// mode: 0 shaded surface, 1 flat-coloured surface lines (wireframe), 2 overlay lines/markers.
#ifdef SHAPESPLINE_GLSL
// The VIEW block: clip = viewProj * (position, 1) (column-major); viewport: width, height in pixels,
// tolerance in pixels, safety factor; tuning: hysteresis, 0, 0, 0; limits: maxRate, probeRate, cull, 0.
struct AdaptiveViewBlock {
  mat4 viewProj;
  vec4 viewport;
  vec4 tuning;
  uvec4 limits;
};
struct RenderPush {
  mat4 viewProj;
  vec4 eye;        // xyz camera position
  vec4 color;      // base colour (surface) or line colour (wireframe)
  vec4 params;     // x: mode, y: depth pull (clip-space z offset * w), z,w: viewport size in pixels
};
#else
struct AdaptiveViewBlock {
  float viewProj[16];
  float viewport[4];
  float tuning[4];
  uint32_t limits[4];
};
struct RenderPush {
  float viewProj[16];
  float eye[4];
  float color[4];
  float params[4];
};
static_assert(sizeof(TessPackPush) == 16 && sizeof(TessGridPush) == 64 && offsetof(TessGridPush, alphaOffset) == 36 &&
              offsetof(TessGridPush, rowsPerInvocation) == 56);
static_assert(sizeof(RenderPush) == 112 && offsetof(RenderPush, params) == 96);
static_assert(sizeof(AdaptivePush) == 64 && offsetof(AdaptivePush, alphaOffset) == 48);
static_assert(sizeof(AdaptiveViewBlock) == 112 && offsetof(AdaptiveViewBlock, limits) == 96);
#endif

// Overlay vertex (render_overlay.vert): position, screen-space offset in pixels (markers), colour.
TS_CONST(TS_UINT, kOverlayVertexStride, 36u);
#ifndef SHAPESPLINE_GLSL
struct OverlayVertex {
  float position[3];
  float offset[2];
  float color[4];
};
static_assert(sizeof(OverlayVertex) == 36 && offsetof(OverlayVertex, color) == 20);
struct TessVertex {
  float position[3];
  float normal[3];
  float uv[2];
};
static_assert(sizeof(TessVertex) == kTessVertexStride && offsetof(TessVertex, normal) == kTessOffsetNormal &&
              offsetof(TessVertex, uv) == kTessOffsetUV);
}  // namespace shapespline::gpu::tess_layout
#endif

#undef TS_UINT
#undef TS_FUNC
#undef TS_CONST
#endif  // SHAPESPLINE_SHADERS_TESS_LAYOUT_H
