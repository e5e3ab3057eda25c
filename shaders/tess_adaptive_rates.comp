#version 450
// Rate pass of the adaptive tessellator (tess_layout.h, docs/tessellation.md), two dispatches.
// Probes (one invocation per sample of each patch's (P+1) x (P+1) probe grid): the point and exact
// second partials of the patch (surface_patch.glsl), mapped to pixels by the chain rule of the
// perspective projection; the patch's maxima A = |f_uu|, B = |f_uv|, C = |f_vv| of the
// screen-space map f go into PROBES by atomics. Rates (one invocation per patch): a triangle whose
// vertices span at most 1/n in u and 1/m in v deviates from f by at most
// ((A + B)/n² + (C + B)/m²)/8, so n >= sqrt(κ(A + B)/(4 tol)) and m >= sqrt(κ(C + B)/(4 tol))
// keep it within tol (κ: the safety factor on the sampled maxima). Integer rates in [2, maxRate],
// raised at once and lowered with hysteresis; frustum culling with the same bound as margin.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = kAdaptBindingView) readonly buffer ViewBuf { AdaptiveViewBlock view; };
layout(std430, binding = kAdaptBindingRates) buffer RateBuf { uvec2 rates[]; };
layout(std430, binding = kAdaptBindingFrame) buffer FrameBuf { uint frame[]; };
layout(std430, binding = kAdaptBindingProbes) buffer ProbeBuf { uvec4 probes[]; };
layout(push_constant) uniform PushBlock { AdaptivePush pc; };
layout(constant_id = kSpecAdaptMode) const uint MODE = 0u;  // = pc.mode, a constant per pipeline

#include "surface_patch.glsl"

// PROBES of patch p: [2p] = float bits of the maxima A, B, C (non-negative floats compare like
// their bit patterns, so the maxima are uint atomics); [2p + 1].x = the frustum planes some probe
// is inside of (bit k: plane k, with margin), .y = 1 when a probe is behind the near plane or its
// derivatives are not finite.

// Clip-space plane distances (Vulkan: -w <= x, y <= w, 0 <= z <= w); >= 0 inside.
float planeDistance(vec4 c, uint k) {
  if (k == 0u) return c.w + c.x;
  if (k == 1u) return c.w - c.x;
  if (k == 2u) return c.w + c.y;
  if (k == 3u) return c.w - c.y;
  if (k == 4u) return c.z;
  return c.w - c.z;
}

void probe(uint k) {
  uint P = view.limits.y, perPatch = (P + 1u) * (P + 1u);
  uint patchIndex = k / perPatch, s = k - patchIndex * perPatch;
  if (patchIndex >= pc.patchesU * pc.patchesV) return;
  uint a = patchIndex / pc.patchesV, b = patchIndex - a * pc.patchesV;
  uint i = a + pc.firstSpanU, j = b + pc.firstSpanV;
  uint pu = s / (P + 1u), pv = s - pu * (P + 1u);
  REAL u = REAL(pu) / REAL(P), v = REAL(pv) / REAL(P);
  Basis2 Bs;
  hornerBasis(u, v, Bs);
  PatchDerivs c;
  PatchDerivs q = evalPatch(Bs, i, j, u, v, c);
  mat4 M = view.viewProj;
  vec4 x = M * vec4(vec3(q.p), 1.0);
  vec4 xu = M * vec4(vec3(q.u), 0.0), xv = M * vec4(vec3(q.v), 0.0);
  vec4 xuu = M * vec4(vec3(q.uu), 0.0), xuv = M * vec4(vec3(q.uv), 0.0), xvv = M * vec4(vec3(q.vv), 0.0);
  // Frustum: inside plane k unless below it by the interpolation bound of the plane distance
  // (linear in the clip position) at the probe spacing.
  float safety = view.viewport.w;
  float h2 = 1.0 / (8.0 * float(P * P));
  uint inside = 0u;
  for (uint pl = 0u; pl < 6u; ++pl) {
    float margin = safety * h2 *
                   (abs(planeDistance(xuu, pl)) + 2.0 * abs(planeDistance(xuv, pl)) + abs(planeDistance(xvv, pl)));
    inside |= planeDistance(x, pl) >= -margin ? (1u << pl) : 0u;
  }
  if (inside != 0u) atomicOr(probes[2u * patchIndex + 1u].x, inside);
  if (x.w <= 0.0 || x.z < 0.0) {  // behind the camera's near plane
    atomicOr(probes[2u * patchIndex + 1u].y, 1u);
    return;
  }
  // g = xy / w and its second partials (g w = xy differentiated twice), in pixels.
  vec2 pixels = 0.5 * view.viewport.xy;
  float w = x.w;
  vec2 g = x.xy / w;
  vec2 gu = (xu.xy - g * xu.w) / w, gv = (xv.xy - g * xv.w) / w;
  vec2 guu = (xuu.xy - 2.0 * gu * xu.w - g * xuu.w) / w;
  vec2 gvv = (xvv.xy - 2.0 * gv * xv.w - g * xvv.w) / w;
  vec2 guv = (xuv.xy - gu * xv.w - gv * xu.w - g * xuv.w) / w;
  vec3 e = vec3(length(guu * pixels), length(guv * pixels), length(gvv * pixels));
  if (!(e.x < 3.0e38 && e.y < 3.0e38 && e.z < 3.0e38)) {  // NaN or overflow
    atomicOr(probes[2u * patchIndex + 1u].y, 1u);
    return;
  }
  atomicMax(probes[2u * patchIndex].x, floatBitsToUint(e.x));
  atomicMax(probes[2u * patchIndex].y, floatBitsToUint(e.y));
  atomicMax(probes[2u * patchIndex].z, floatBitsToUint(e.z));
}

void choosePatchRates(uint patchIndex) {
  if (patchIndex >= pc.patchesU * pc.patchesV) return;
  uvec4 maxima = probes[2u * patchIndex], flags = probes[2u * patchIndex + 1u];
  uint maxRate = view.limits.x;
  bool cull = view.limits.z != 0u && flags.x != 0x3fu;  // some plane no probe is inside of
  uvec2 need, high;
  if (cull) {
    need = uvec2(2u);
    high = need;
    atomicAdd(frame[kAdaptFrameCulled], 1u);
  } else if (flags.y != 0u) {
    // The projection is unbounded near the camera plane: the finest rate.
    need = uvec2(maxRate);
    high = need;
    atomicAdd(frame[kAdaptFrameNear], 1u);
  } else {
    float tol = view.viewport.z, safety = view.viewport.w;
    float B = uintBitsToFloat(maxima.y);
    vec2 wanted = sqrt(safety * vec2(uintBitsToFloat(maxima.x) + B, uintBitsToFloat(maxima.z) + B) / (4.0 * tol));
    vec2 cap = vec2(float(maxRate));
    if (wanted.x > cap.x || wanted.y > cap.y) atomicAdd(frame[kAdaptFrameClamped], 1u);
    need = uvec2(clamp(ceil(min(wanted, cap)), vec2(2.0), cap));
    high = uvec2(clamp(ceil(min(wanted * (1.0 + view.tuning.x), cap)), vec2(need), cap));
  }
  uvec2 prev = rates[patchIndex];
  rates[patchIndex] = prev.x == 0u ? need : clamp(prev, need, high);
}

void main() {
  uint k = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  if (MODE == kAdaptModeProbes) probe(k);
  else choosePatchRates(k);
}
