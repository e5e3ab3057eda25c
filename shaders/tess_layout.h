// Tessellation and render layouts shared by shaders/tessellate_pack.comp, shaders/render_*.vert and
// host/gpu/tessellator.* / host/render/*: compiled as GLSL (after common.glsl or with
// SHAPESPLINE_GLSL defined) and as C++ (host mirrors with static_asserts).
//
// ---- Tessellated vertex (the VERTEX buffer written by SurfaceTessellator::record) ---------------
//  32 bytes, tightly packed floats, usable as vertex input binding with stride kTessVertexStride:
//    location 0: position  R32G32B32_SFLOAT at byte 0   (model space)
//    location 1: normal    R32G32B32_SFLOAT at byte 12  (unit, MATH.md §5.3 + shared-vertex mean)
//    location 2: uv        R32G32_SFLOAT    at byte 24  (global (U,V) = (i+u, j+v) of the owner patch)
// ---- Pack pass bindings (descriptor set 0) ------------------------------------------------------
//  2 POINTS  (REAL)  packed xyz point plane of surface_eval (list mode), one entry per sample
//  3 NORMALS (REAL)  packed xyz normal plane
//  4 SAMPLES (ListSample) the sample list: sample k < vertexCount is vertex k's canonical sample
//  5 EXTRA   (uvec2) per vertex: first and count of its extra normal samples (>= vertexCount)
//  6 VERTICES (float) output, kTessVertexFloats per vertex
#ifndef SHAPESPLINE_SHADERS_TESS_LAYOUT_H
#define SHAPESPLINE_SHADERS_TESS_LAYOUT_H

#ifdef SHAPESPLINE_GLSL
#define TS_CONST(type, name, value) const type name = value
#define TS_UINT uint
#else
#include <cstddef>
#include <cstdint>
namespace shapespline::gpu::tess_layout {
#define TS_CONST(type, name, value) inline constexpr type name = value
#define TS_UINT uint32_t
#endif

TS_CONST(TS_UINT, kTessBindingPoints, 2u);
TS_CONST(TS_UINT, kTessBindingNormals, 3u);
TS_CONST(TS_UINT, kTessBindingSamples, 4u);
TS_CONST(TS_UINT, kTessBindingExtra, 5u);
TS_CONST(TS_UINT, kTessBindingVertices, 6u);
TS_CONST(TS_UINT, kTessBindingCount, 7u);

TS_CONST(TS_UINT, kTessVertexFloats, 8u);
TS_CONST(TS_UINT, kTessVertexStride, 32u);
TS_CONST(TS_UINT, kTessOffsetPosition, 0u);
TS_CONST(TS_UINT, kTessOffsetNormal, 12u);
TS_CONST(TS_UINT, kTessOffsetUV, 24u);

// Push constants of tessellate_pack.comp.
struct TessPackPush {
  TS_UINT vertexCount;
  TS_UINT pad0;
  TS_UINT pad1;
  TS_UINT pad2;
};

// Push constants of render_surface.* and render_overlay.* (host/render/renderer.cpp).
// mode: 0 shaded surface, 1 flat-coloured surface lines (wireframe), 2 overlay lines/markers.
#ifdef SHAPESPLINE_GLSL
struct RenderPush {
  mat4 viewProj;
  vec4 eye;        // xyz camera position
  vec4 color;      // base colour (surface) or line colour (wireframe)
  vec4 params;     // x: mode, y: depth pull (clip-space z offset * w), z,w: viewport size in pixels
};
#else
struct RenderPush {
  float viewProj[16];
  float eye[4];
  float color[4];
  float params[4];
};
static_assert(sizeof(TessPackPush) == 16);
static_assert(sizeof(RenderPush) == 112 && offsetof(RenderPush, params) == 96);
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
#undef TS_CONST
#endif  // SHAPESPLINE_SHADERS_TESS_LAYOUT_H
