#version 450
// Rate pass of the adaptive tessellator (tess_layout.h, docs/tessellation.md): one workgroup per
// patch. Each invocation evaluates probe samples of the patch's (P+1) x (P+1) probe grid (point
// and exact second partials, surface_patch.glsl), maps them to pixels by the chain rule of the
// perspective projection, and the workgroup keeps the maxima A = |f_uu|, B = |f_uv|, C = |f_vv| of
// the screen-space map f. A triangle whose vertices span at most 1/n in u and 1/m in v deviates from
// f by at most ((A + B)/n² + (C + B)/m²)/8, so n >= sqrt(κ(A + B)/(4 tol)) and
// m >= sqrt(κ(C + B)/(4 tol)) keep it within tol (κ: the safety factor on the sampled maxima).
// Integer rates in [2, maxRate], raised at once and lowered with hysteresis; frustum culling with
// the same bound as margin.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = kAdaptBindingView) readonly buffer ViewBuf { AdaptiveViewBlock view; };
layout(std430, binding = kAdaptBindingRates) buffer RateBuf { uvec2 rates[]; };
layout(std430, binding = kAdaptBindingFrame) buffer FrameBuf { uint frame[]; };
layout(push_constant) uniform PushBlock { AdaptivePush pc; };

#include "surface_patch.glsl"

// Non-negative floats compare like their bit patterns, so the maxima are uint atomics.
shared uint sA, sB, sC;
shared uint sOutside;  // planes every probe lies outside of (bit k: plane k)
shared uint sNearCount, sBad;

// Clip-space plane distances (Vulkan: -w <= x, y <= w, 0 <= z <= w); >= 0 inside.
float planeDistance(vec4 c, uint k) {
  if (k == 0u) return c.w + c.x;
  if (k == 1u) return c.w - c.x;
  if (k == 2u) return c.w + c.y;
  if (k == 3u) return c.w - c.y;
  if (k == 4u) return c.z;
  return c.w - c.z;
}

void main() {
  uint patchIndex = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (patchIndex >= pc.patchesU * pc.patchesV) return;  // uniform per workgroup
  uint lid = gl_LocalInvocationID.x;
  if (lid == 0u) {
    sA = 0u;
    sB = 0u;
    sC = 0u;
    sOutside = 0x3fu;
    sNearCount = 0u;
    sBad = 0u;
  }
  barrier();

  uint a = patchIndex / pc.patchesV, b = patchIndex - a * pc.patchesV;
  uint i = a + pc.firstSpanU, j = b + pc.firstSpanV;
  uint P = view.limits.y;
  float safety = view.viewport.w;
  vec2 pixels = 0.5 * view.viewport.xy;  // NDC -> pixel scale
  float h2 = 1.0 / (8.0 * float(P * P));  // the bound's h²/8 at the probe spacing (culling margin)
  float A = 0.0, B = 0.0, C = 0.0;
  uint outside = 0x3fu, nearCount = 0u;
  bool bad = false;
  uint probes = (P + 1u) * (P + 1u);
  for (uint k = lid; k < probes; k += gl_WorkGroupSize.x) {
    uint pu = k / (P + 1u), pv = k - pu * (P + 1u);
    REAL u = REAL(pu) / REAL(P), v = REAL(pv) / REAL(P);
    Basis2 Bs;
    hornerBasis(u, v, Bs);
    PatchDerivs c;
    PatchDerivs q = evalPatch(Bs, i, j, u, v, c);
    mat4 M = view.viewProj;
    vec4 x = M * vec4(vec3(q.p), 1.0);
    vec4 xu = M * vec4(vec3(q.u), 0.0), xv = M * vec4(vec3(q.v), 0.0);
    vec4 xuu = M * vec4(vec3(q.uu), 0.0), xuv = M * vec4(vec3(q.uv), 0.0), xvv = M * vec4(vec3(q.vv), 0.0);
    // Frustum: this probe is outside plane k with the interpolation bound of the plane distance
    // (linear in the clip position) as margin.
    uint out_ = 0u;
    for (uint pl = 0u; pl < 6u; ++pl) {
      float d = planeDistance(x, pl);
      float margin = safety * h2 *
                     (abs(planeDistance(xuu, pl)) + 2.0 * abs(planeDistance(xuv, pl)) + abs(planeDistance(xvv, pl)));
      out_ |= d < -margin ? (1u << pl) : 0u;
    }
    outside &= out_;
    if (x.w <= 0.0 || x.z < 0.0) {  // behind the camera's near plane
      ++nearCount;
      continue;
    }
    // g = xy / w and its second partials (g w = xy differentiated twice), in pixels.
    float w = x.w;
    vec2 g = x.xy / w;
    vec2 gu = (xu.xy - g * xu.w) / w, gv = (xv.xy - g * xv.w) / w;
    vec2 guu = (xuu.xy - 2.0 * gu * xu.w - g * xuu.w) / w;
    vec2 gvv = (xvv.xy - 2.0 * gv * xv.w - g * xvv.w) / w;
    vec2 guv = (xuv.xy - gu * xv.w - gv * xu.w - g * xuv.w) / w;
    float ea = length(guu * pixels), eb = length(guv * pixels), ec = length(gvv * pixels);
    if (!(ea < 3.0e38 && eb < 3.0e38 && ec < 3.0e38)) bad = true;  // NaN or overflow
    A = max(A, ea);
    B = max(B, eb);
    C = max(C, ec);
  }
  if (!bad) {
    atomicMax(sA, floatBitsToUint(A));
    atomicMax(sB, floatBitsToUint(B));
    atomicMax(sC, floatBitsToUint(C));
  } else {
    atomicOr(sBad, 1u);
  }
  atomicAnd(sOutside, outside);
  atomicAdd(sNearCount, nearCount);
  barrier();
  if (lid != 0u) return;

  uint maxRate = view.limits.x;
  bool cull = view.limits.z != 0u && sOutside != 0u;
  bool straddles = !cull && (sNearCount > 0u || sBad != 0u);
  uvec2 need, high;
  if (cull) {
    need = uvec2(2u);
    high = need;
    atomicAdd(frame[kAdaptFrameCulled], 1u);
  } else if (straddles) {
    // The projection is unbounded near the camera plane: the finest rate.
    need = uvec2(maxRate);
    high = need;
    atomicAdd(frame[kAdaptFrameNear], 1u);
  } else {
    float tol = view.viewport.z;
    float B4 = uintBitsToFloat(sB);
    vec2 wanted = sqrt(safety * vec2(uintBitsToFloat(sA) + B4, uintBitsToFloat(sC) + B4) / (4.0 * tol));
    vec2 cap = vec2(float(maxRate));
    if (wanted.x > cap.x || wanted.y > cap.y) atomicAdd(frame[kAdaptFrameClamped], 1u);
    need = uvec2(clamp(ceil(min(wanted, cap)), vec2(2.0), cap));
    high = uvec2(clamp(ceil(min(wanted * (1.0 + view.tuning.x), cap)), vec2(need), cap));
  }
  uvec2 prev = rates[patchIndex];
  rates[patchIndex] = prev.x == 0u ? need : clamp(prev, need, high);
}
