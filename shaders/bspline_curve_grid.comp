#version 450
// Grid path of bspline_curve_eval.comp (knot-vector B-spline curves, docs/math.md §10.1): each
// grid sample's span and basis come tabulated in TABLE (gpu/knot_grid_table.h, from
// core/knot_table.h), [span, N, N', N''] per sample, so that a point costs the sum over the span's
// control points alone (the sums and order of core/bspline.cpp evalBSplineCurve; rational curves
// through the quotient rule of point_math.h). One point per invocation.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"

layout(std430, binding = kBindingTable) readonly buffer TableBuf { REAL table[]; };
layout(std430, binding = kBindingOutput + kFieldPoint) writeonly buffer OutPoint { REAL4 outPoint[]; };
layout(std430, binding = kBindingOutput + kFieldD1) writeonly buffer OutD1 { REAL4 outD1[]; };
layout(std430, binding = kBindingOutput + kFieldD2) writeonly buffer OutD2 { REAL4 outD2[]; };

layout(push_constant) uniform PushBlock { KnotEvalPush pc; };

const bool kWantPoint = (OUTPUT_MASK & (1u << kFieldPoint)) != 0u;
const bool kWantD1 = (OUTPUT_MASK & (1u << kFieldD1)) != 0u;
const bool kWantD2 = (OUTPUT_MASK & (1u << kFieldD2)) != 0u;
const uint M = BASIS_COUNT_U;
const uint STRIDE = 1u + 3u * M;

void main() {
  uint k = flatInvocation();
  if (k >= pc.rowCount) return;  // rows of a curve chunk are samples
  uint g = pc.firstRow + k;
  uint item = g / pc.samplesU, a = g - item * pc.samplesU;
  uint e = ((pc.firstItem + item) * pc.samplesU + a) * STRIDE;
  uint first = uint(int(table[e]) + 1 - int(M));
  REAL3 p = REAL3(0), d1 = REAL3(0), d2 = REAL3(0);
  REAL w0 = REAL(0), w1 = REAL(0), w2 = REAL(0);  // W, W', W'' of a rational curve
  [[unroll]] for (uint r = 0; r < M; ++r) {
    REAL b0 = table[e + 1u + r], b1 = table[e + 1u + M + r], b2 = table[e + 1u + 2u * M + r];
    REAL4 P = net[first + r];
    accumulate3(p, d1, d2, b0, b1, b2, P.xyz);
    w0 += b0 * P.w, w1 += b1 * P.w, w2 += b2 * P.w;
  }
  if (RATIONAL != 0u) rationalCurve(p, d1, d2, w0, w1, w2);
  if (kWantPoint) STORE_XYZ_SCALAR(outPoint, k, p)
  if (kWantD1) STORE_XYZ_SCALAR(outD1, k, d1)
  if (kWantD2) STORE_XYZ_SCALAR(outD2, k, d2)
}
