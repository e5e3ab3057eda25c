#version 450
// Pack pass of the tessellator (shaders/tess_layout.h): the corner and edge vertices, shared by up
// to four patches. Position from the vertex's canonical source (one evaluation, so both sides of
// a shared edge reference bitwise the same vertex); normal = normalised mean of the normals of
// every patch that contains the vertex (canonical + extra sources; the per-patch docs/math.md §5.3
// rule, so an α = 1 corner gets the mean of its patches' diagonal limits); uv from the host.
// Never writes NaN.
// variant: packed-stores (vertices stored as uint64 pairs of floats; common.glsl)
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = kTessBindingPoints) readonly buffer PointPlane { REAL points[]; };
layout(std430, binding = kTessBindingNormals) readonly buffer NormalPlane { REAL normals[]; };
// Packed variant: 64-bit loads as well (llvmpipe gathers one scalar per lane at a time, so a vec2
// read as one uint64 is one gather instead of two).
#if defined(PACKED_STORES) && PACKED_STORES
layout(std430, binding = kTessBindingUV) readonly buffer UVBuf { uint64_t uvs[]; };
layout(std430, binding = kTessBindingExtra) readonly buffer ExtraBuf { uint64_t extra[]; };
vec2 uvOf(uint k) { return uintBitsToFloat(unpackUint2x32(uvs[k])); }
uvec2 extraOf(uint k) { return unpackUint2x32(extra[k]); }
#else
layout(std430, binding = kTessBindingUV) readonly buffer UVBuf { vec2 uvs[]; };
layout(std430, binding = kTessBindingExtra) readonly buffer ExtraBuf { uvec2 extra[]; };
vec2 uvOf(uint k) { return uvs[k]; }
uvec2 extraOf(uint k) { return extra[k]; }
#endif
layout(std430, binding = kTessBindingVertices) writeonly buffer VertexBuf { VERTEX outVerts[]; };
#if defined(PACKED_STORES) && PACKED_STORES && !(defined(REAL_IS_DOUBLE) && REAL_IS_DOUBLE)
layout(std430, binding = kTessBindingBoundary) readonly buffer BoundaryBuf { u64vec2 boundary[]; };
vec3 boundaryXYZ(uint i) {
  u64vec2 w = boundary[i];
  return vec3(uintBitsToFloat(unpackUint2x32(w.x)), uintBitsToFloat(unpackUint2x32(w.y).x));
}
#else
layout(std430, binding = kTessBindingBoundary) readonly buffer BoundaryBuf { REAL4 boundary[]; };
vec3 boundaryXYZ(uint i) { return vec3(boundary[i].xyz); }
#endif
layout(std430, binding = kTessBindingSources) readonly buffer SourceBuf { uint sources[]; };
layout(push_constant) uniform PushBlock { TessPackPush pc; };
layout(constant_id = kTessSpecListSources) const uint LIST_SOURCES = 1;

// field 0: point, 1: normal of a source.
vec3 sourceValue(uint source, uint field) {
  if (LIST_SOURCES != 0u && (source & kTessListSource) != 0u) {
    uint k = 3u * (source & ~kTessListSource);
    return field == 0u ? vec3(points[k], points[k + 1u], points[k + 2u])
                       : vec3(normals[k], normals[k + 1u], normals[k + 2u]);
  }
  return boundaryXYZ(2u * source + field);
}

void main() {
  uint k = flatInvocation();
  if (k >= pc.boundaryVertexCount) return;
  uint canonical = sources[k];
  vec3 p = sourceValue(canonical, 0u);
  vec3 n0 = sourceValue(canonical, 1u);
  vec3 n = n0;
  uvec2 e = extraOf(k);
  for (uint s = 0u; s < e.y; ++s) n += sourceValue(sources[e.x + s], 1u);
  float len = length(n);
  // Opposite patch normals (a fold) cancel: keep the canonical one.
  n = len > 1e-6 * float(e.y + 1u) ? n / len : n0;
  STORE_VERTEX(outVerts, k, vec4(p, n.x), vec4(n.yz, uvOf(k)))
}
