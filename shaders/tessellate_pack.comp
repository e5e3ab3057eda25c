#version 450
// Packs the per-sample point/normal planes of surface_eval (list mode) into the interleaved vertex
// buffer of tess_layout.h: position of the vertex's canonical sample, normal = normalised mean of
// the normals of every patch that shares the vertex (canonical + extra samples; the per-patch
// MATH.md §5.3 rule, so an α = 1 corner gets the mean of its patches' diagonal limits), uv = global
// (U,V) of the canonical sample. Never writes NaN.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = 2) readonly buffer PointPlane { REAL points[]; };
layout(std430, binding = 3) readonly buffer NormalPlane { REAL normals[]; };
layout(std430, binding = 4) readonly buffer SampleBuf { ListSample samples[]; };
layout(std430, binding = 5) readonly buffer ExtraBuf { uvec2 extra[]; };
layout(std430, binding = 6) writeonly buffer VertexBuf { float outVerts[]; };
layout(push_constant) uniform PushBlock { TessPackPush pc; };

vec3 planeAt(uint which, uint k) {
  return which == 0u ? vec3(points[3u * k], points[3u * k + 1u], points[3u * k + 2u])
                     : vec3(normals[3u * k], normals[3u * k + 1u], normals[3u * k + 2u]);
}

void main() {
  uint k = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (k >= pc.vertexCount) return;
  vec3 p = planeAt(0u, k);
  vec3 n0 = planeAt(1u, k);
  vec3 n = n0;
  uvec2 e = extra[k];
  for (uint s = 0u; s < e.y; ++s) n += planeAt(1u, e.x + s);
  float len = length(n);
  // Opposite patch normals (a fold) cancel: keep the canonical one.
  n = len > 1e-6 * float(e.y + 1u) ? n / len : n0;
  ListSample s = samples[k];
  vec2 uv = vec2(float(s.i) + float(s.u), float(s.j) + float(s.v));
  uint o = k * kTessVertexFloats;
  outVerts[o + 0u] = p.x;
  outVerts[o + 1u] = p.y;
  outVerts[o + 2u] = p.z;
  outVerts[o + 3u] = n.x;
  outVerts[o + 4u] = n.y;
  outVerts[o + 5u] = n.z;
  outVerts[o + 6u] = uv.x;
  outVerts[o + 7u] = uv.y;
}
