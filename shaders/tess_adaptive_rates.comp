#version 450
// Rate pass of the adaptive tessellator (tess_layout.h, docs/tessellation.md), one invocation per
// patch. Probes (the patch's (P+1) x (P+1) probe grid, row-wise with the patch loaded once): the
// point and exact second partials of the patch, mapped to pixels by the chain rule of the
// perspective projection; the patch's maxima A = |f_uu|, B = |f_uv|, C = |f_vv| of the
// screen-space map f. Rates: a triangle whose
// vertices span at most 1/n in u and 1/m in v deviates from f by at most
// ((A + B)/n² + (C + B)/m²)/8, so n >= sqrt(κ(A + B)/(4 tol)) and m >= sqrt(κ(C + B)/(4 tol))
// keep it within tol (κ: the safety factor on the sampled maxima). Integer rates in [2, maxRate],
// raised at once and lowered with hysteresis; frustum culling with the same bound as margin.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = kAdaptBindingView) readonly buffer ViewBuf { AdaptiveViewBlock view; };
layout(std430, binding = kAdaptBindingRates) buffer RateBuf { uvec2 rates[]; };
layout(std430, binding = kAdaptBindingFrame) buffer FrameBuf { uint frame[]; };
layout(push_constant) uniform PushBlock { AdaptivePush pc; };
layout(constant_id = kSpecAdaptMode) const uint MODE = 0u;  // = pc.mode, a constant per pipeline

#include "surface_patch.glsl"

const bool kAEB = ALPHA_EB != 0u;
const uint MU = BASIS_COUNT_U;
const uint MV = BASIS_COUNT_V;
const uint DU = POLY_DEGREE_U;
const uint DV = POLY_DEGREE_V;
#include "patch_rows.glsl"

// Row-wise second derivatives (patch_rows.glsl's setupRow / evalSample with one order more): the
// u contraction of a probe row in the power basis of v for B_r, B_r' and B_r'' (W0, W1, W2); a
// probe is one Horner pass in v giving Q, Q_v, Q_vv (W0), Q_u, Q_uv (W1), Q_uu (W2); α-EB: all six
// weights per probe (alphaEBWeights); rational: the same of the weights, then the quotient rule.
REAL3 gR0[DV + 1u], gR1[DV + 1u], gR2[DV + 1u];
REAL gRW0[DV + 1u], gRW1[DV + 1u], gRW2[DV + 1u];
REAL3 gSu;  // singularBlend(u) of the row

void setupProbeRow(REAL tu) {
  REAL3 T0[MV], T1[MV], T2[MV];
  REAL TW0[MV], TW1[MV], TW2[MV];
  [[unroll]] for (uint s = 0; s < MV; ++s) {
    T0[s] = REAL3(0);
    T1[s] = REAL3(0);
    T2[s] = REAL3(0);
    TW0[s] = REAL(0);
    TW1[s] = REAL(0);
    TW2[s] = REAL(0);
  }
  [[unroll]] for (uint r = 0; r < MU; ++r) {
    REAL w0 = gCu[r][DU], dp = REAL(0), hp = REAL(0);
    [[unroll]] for (int d = int(DU) - 1; d >= 0; --d) hornerStep(w0, dp, hp, tu, gCu[r][d]);
    REAL w2 = REAL(2) * hp;
    [[unroll]] for (uint s = 0; s < MV; ++s) {
      accumulate3(T0[s], T1[s], T2[s], w0, dp, w2, gP[r][s]);
      if (RATIONAL != 0u) accumulate3(TW0[s], TW1[s], TW2[s], w0, dp, w2, gPW[r][s]);
    }
  }
  [[unroll]] for (uint d = 0; d <= DV; ++d) {
    REAL3 w0 = REAL3(0), w1 = REAL3(0), w2 = REAL3(0);
    REAL ww0 = REAL(0), ww1 = REAL(0), ww2 = REAL(0);
    [[unroll]] for (uint s = 0; s < MV; ++s) {
      w0 += cv[s][d] * T0[s];
      w1 += cv[s][d] * T1[s];
      w2 += cv[s][d] * T2[s];
      if (RATIONAL != 0u) {
        ww0 += cv[s][d] * TW0[s];
        ww1 += cv[s][d] * TW1[s];
        ww2 += cv[s][d] * TW2[s];
      }
    }
    gR0[d] = w0;
    gR1[d] = w1;
    gR2[d] = w2;
    gRW0[d] = ww0;
    gRW1[d] = ww1;
    gRW2[d] = ww2;
  }
  if (kAEB) gSu = singularBlend(tu);
}

PatchDerivs evalProbe(REAL t) {
  PatchDerivs q;
  q.p = gR0[DV];
  q.v = REAL3(0);
  REAL3 hv = REAL3(0);
  q.u = gR1[DV];
  q.uv = REAL3(0);
  q.uu = gR2[DV];
  REAL3 unused0 = REAL3(0), unused1 = REAL3(0), unused2 = REAL3(0);
  REAL w = gRW0[DV], wv = REAL(0), hwv = REAL(0), wu = gRW1[DV], wuv = REAL(0), wuu = gRW2[DV], unusedW = REAL(0);
  [[unroll]] for (int d = int(DV) - 1; d >= 0; --d) {
    hornerStep(q.p, q.v, hv, t, gR0[d]);
    hornerStep(q.u, q.uv, unused0, t, gR1[d]);
    hornerStep(q.uu, unused1, unused2, t, gR2[d]);
    if (RATIONAL != 0u) {
      hornerStep(w, wv, hwv, t, gRW0[d]);
      hornerStep(wu, wuv, unusedW, t, gRW1[d]);
      hornerStep(wuu, unusedW, unusedW, t, gRW2[d]);
    }
  }
  q.vv = REAL(2) * hv;
  if (RATIONAL != 0u) rationalSurface(q.p, q.u, q.v, q.uu, q.uv, q.vv, w, wu, wv, wuu, wuv, REAL(2) * hwv);
  if (kAEB) {
    AlphaEBWeights w = alphaEBWeights(gSu, singularBlend(t), gAl, gV);
    alphaEBBlendPatch(w, q.p, q.u, q.v, q.uu, q.uv, q.vv);
  }
  return q;
}

// (PROBES is no longer used: the maxima stay in the invocation.)

// Clip-space plane distances (Vulkan: -w <= x, y <= w, 0 <= z <= w); >= 0 inside.
float planeDistance(vec4 c, uint k) {
  if (k == 0u) return c.w + c.x;
  if (k == 1u) return c.w - c.x;
  if (k == 2u) return c.w + c.y;
  if (k == 3u) return c.w - c.y;
  if (k == 4u) return c.z;
  return c.w - c.z;
}

// The probe (u, v) of patch q: its screen-space second-derivative norms into e (max), the frustum
// planes it is inside of into inside, near when it is behind the camera's near plane or its
// derivatives are not finite.
void probe(PatchDerivs q, uint P, inout vec3 emax, inout uint inside, inout bool near) {
  mat4 M = view.viewProj;
  vec4 x = M * vec4(vec3(q.p), 1.0);
  vec4 xu = M * vec4(vec3(q.u), 0.0), xv = M * vec4(vec3(q.v), 0.0);
  vec4 xuu = M * vec4(vec3(q.uu), 0.0), xuv = M * vec4(vec3(q.uv), 0.0), xvv = M * vec4(vec3(q.vv), 0.0);
  // Frustum: inside plane k unless below it by the interpolation bound of the plane distance
  // (linear in the clip position) at the probe spacing.
  float safety = view.viewport.w;
  float h2 = 1.0 / (8.0 * float(P * P));
  [[unroll]] for (uint pl = 0u; pl < 6u; ++pl) {
    float margin = safety * h2 *
                   (abs(planeDistance(xuu, pl)) + 2.0 * abs(planeDistance(xuv, pl)) + abs(planeDistance(xvv, pl)));
    inside |= planeDistance(x, pl) >= -margin ? (1u << pl) : 0u;
  }
  bool behind = x.w <= 0.0 || x.z < 0.0;  // behind the camera's near plane
  // g = xy / w and its second partials (g w = xy differentiated twice), in pixels.
  vec2 pixels = 0.5 * view.viewport.xy;
  float w = x.w;
  vec2 g = x.xy / w;
  vec2 gu = (xu.xy - g * xu.w) / w, gv = (xv.xy - g * xv.w) / w;
  vec2 guu = (xuu.xy - 2.0 * gu * xu.w - g * xuu.w) / w;
  vec2 gvv = (xvv.xy - 2.0 * gv * xv.w - g * xvv.w) / w;
  vec2 guv = (xuv.xy - gu * xv.w - gv * xu.w - g * xuv.w) / w;
  vec3 e = vec3(length(guu * pixels), length(guv * pixels), length(gvv * pixels));
  bool bad = !(e.x < 3.0e38 && e.y < 3.0e38 && e.z < 3.0e38);  // NaN or overflow
  near = near || behind || bad;
  emax = behind || bad ? emax : max(emax, e);
}

// Per patch: the (P+1)^2 probes row-wise (the patch loaded once), then the rates.
void choosePatchRates(uint patchIndex) {
  if (patchIndex >= pc.patchesU * pc.patchesV) return;
  uint P = view.limits.y;
  uint a = patchIndex / pc.patchesV, b = patchIndex - a * pc.patchesV;
  loadPatchRows(a + pc.firstSpanU, b + pc.firstSpanV);
  vec3 emax = vec3(0);
  uint insideAny = 0u;
  bool nearAny = false;
  for (uint pu = 0u; pu <= P; ++pu) {
    setupProbeRow(REAL(pu) / REAL(P));
    for (uint pv = 0u; pv <= P; ++pv) probe(evalProbe(REAL(pv) / REAL(P)), P, emax, insideAny, nearAny);
  }
  uint maxRate = view.limits.x;
  bool cull = view.limits.z != 0u && insideAny != 0x3fu;  // some plane no probe is inside of
  uvec2 need, high;
  if (cull) {
    need = uvec2(2u);
    high = need;
    atomicAdd(frame[kAdaptFrameCulled], 1u);
  } else if (nearAny) {
    // The projection is unbounded near the camera plane: the finest rate.
    need = uvec2(maxRate);
    high = need;
    atomicAdd(frame[kAdaptFrameNear], 1u);
  } else {
    float tol = view.viewport.z, safety = view.viewport.w;
    float B = emax.y;
    vec2 wanted = sqrt(safety * vec2(emax.x + B, emax.z + B) / (4.0 * tol));
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
  choosePatchRates(k);
}
