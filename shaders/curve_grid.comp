#version 450
// Fast grid path of curve_eval.comp (docs/math.md §1 with optional span knots, α-EB curves §4.2) when
// the samples per span are a multiple of 4: one invocation = RUN_LENGTH consecutive samples of one
// span (RUN_LENGTH < samplesU, dividing it) or RUN_LENGTH / samplesU whole consecutive spans. The
// span's points, its α-EB vertex data and 1/h are gathered once per span instead of once per
// sample, the span is turned into a polynomial in t (basis coefficients in registers), t =
// a/(S-1) as in basis_table.comp, and every loop bound is a specialization constant. The α-EB
// blend is point_math.h's (as in host/core/curve.cpp evalAlphaEBSpan); see surface_grid.comp for
// the llvmpipe reasoning.
// variant: packed-stores (fp32 output planes stored as uint64 pairs; common.glsl)
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"

layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = kBindingOutput + kFieldPoint) writeonly buffer OutPoint { PLANE4 outPoint[]; };
layout(std430, binding = kBindingOutput + kFieldD1) writeonly buffer OutD1 { PLANE4 outD1[]; };
layout(std430, binding = kBindingOutput + kFieldD2) writeonly buffer OutD2 { PLANE4 outD2[]; };

layout(push_constant) uniform PushBlock { EvalPush pc; };

const bool kWantPoint = (OUTPUT_MASK & (1u << kFieldPoint)) != 0u;
const bool kWantD1 = (OUTPUT_MASK & (1u << kFieldD1)) != 0u;
const bool kWantD2 = (OUTPUT_MASK & (1u << kFieldD2)) != 0u;
const bool kAEB = ALPHA_EB != 0u;
layout(constant_id = kSpecRunLength) const uint RUN_LENGTH = 4;  // a multiple of 4 (evaluator.cpp picks it)
const uint MU = BASIS_COUNT_U;
const uint DU = POLY_DEGREE_U;

void main() {
  uint q = flatInvocation();
  uint spansPer = max(1u, RUN_LENGTH / pc.samplesU);  // spans of this invocation
  uint runLen = min(RUN_LENGTH, pc.samplesU);          // samples of each of its spans
  uint runs = pc.samplesU / runLen;
  // The chunk's samples are rows firstRow .. firstRow + rowCount - 1 counted from the start of span
  // firstItem (a span larger than a chunk comes in sample ranges, whole runs each).
  uint local0 = q * runLen * spansPer;
  if (local0 >= pc.rowCount) return;
  uint g0 = pc.firstRow + local0;
  uint item0 = g0 / pc.samplesU;
  uint aRun = g0 - item0 * pc.samplesU;
  uint spanCount = min(spansPer, pc.itemCount - item0);

  REAL cu[MU][DU + 1u];
  [[unroll]] for (uint r = 0; r < MU; ++r)
    [[unroll]] for (uint d = 0; d <= DU; ++d) cu[r][d] = params[kParamCoefU + r * kCoefStride + d];
  REAL den = REAL(pc.samplesU - 1u);

  for (uint k = 0; k < spanCount; ++k) {
    uint item = item0 + k;
    uint span = pc.firstItem + item + pc.firstSpanU;
    uint first = span + pc.netOffsetU;
    REAL3 P[MU];
    [[unroll]] for (uint r = 0; r < MU; ++r) P[r] = net[first + r].xyz;
    // α-EB: the span's vertices j0 = span, j1 = span + 1 (mod the vertex count: closed curves);
    // plain curves: 1/h of the span (span knots) or 1.
    REAL3 v0 = REAL3(0), v1 = REAL3(0);
    REAL a0 = REAL(0), a1 = REAL(0), invH = REAL(1);
    if (kAEB) {
      uint j0 = span % pc.rows, j1 = (span + 1u) % pc.rows;
      v0 = verts[j0].xyz;
      v1 = verts[j1].xyz;
      a0 = params[pc.alphaOffset + j0];
      a1 = params[pc.alphaOffset + j1];
    } else if (pc.invHOffset != kNoOffset) {
      invH = params[pc.invHOffset + span - pc.firstSpanU];
    }
    // The span in the power basis: W[d] = Σ_r c_r,d P[r] (B_r(t) = Σ_d c_r,d t^d), so a sample is
    // one Horner pass for the point and both derivatives instead of every basis function and a
    // contraction (90 instead of 288 operations at degree 5; llvmpipe fuses no multiply-adds).
    REAL3 W[DU + 1u];
    [[unroll]] for (uint d = 0; d <= DU; ++d) {
      W[d] = REAL3(0);
      [[unroll]] for (uint r = 0; r < MU; ++r) W[d] += cu[r][d] * P[r];
    }

    for (uint g = 0; g < runLen / 4u; ++g) {
      uint a0s = aRun + 4u * g;
      REAL3 p[4], d1[4], d2[4];
      [[unroll]] for (uint e = 0; e < 4u; ++e) {
        REAL t = pc.samplesU > 1u ? REAL(a0s + e) / den : REAL(0);
        // Point, first and half second derivative by simultaneous Horner.
        REAL3 c0 = W[DU], c1 = REAL3(0), h2 = REAL3(0);
        [[unroll]] for (int d = int(DU) - 1; d >= 0; --d) hornerStep(c0, c1, h2, t, W[d]);  // h2 dead unless d2
        REAL3 c2 = REAL(2) * h2;
        if (kAEB) {
          // evalAlphaEBSpan (the base span with 1/h = 1).
          alphaEBBlendCurve(singularBlend(t), v0, v1, a0, a1, c0, c1, c2);
          p[e] = c0;
          d1[e] = c1;
          d2[e] = c2;
        } else {
          p[e] = c0;
          d1[e] = c1 * invH;
          d2[e] = c2 * (invH * invH);
        }
      }
      uint o = (item * pc.samplesU + a0s - pc.firstRow) >> 2;
      if (kWantPoint) STORE_XYZ4_PLANE(outPoint, o, p[0], p[1], p[2], p[3])
      if (kWantD1) STORE_XYZ4_PLANE(outD1, o, d1[0], d1[1], d1[2], d1[3])
      if (kWantD2) STORE_XYZ4_PLANE(outD2, o, d2[0], d2[1], d2[2], d2[3])
    }
  }
}
