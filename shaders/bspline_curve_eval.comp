#version 450
// Knot-vector B-spline curves (docs/math.md §10.1, core/bspline.h evalBSplineCurve): point, d1, d2 with
// respect to the knot parameter, for a grid of S samples on every non-empty knot interval (items as
// core/grid_sampler.h curveGridItems) or a list of (span, knot parameter). Order = BASIS_COUNT_U.
// 4 output points per invocation (layout.h).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "bspline.glsl"

layout(std430, binding = kBindingSamples) readonly buffer SampleBuf { ListSample samples[]; };
layout(std430, binding = kBindingOutput + kFieldPoint) writeonly buffer OutPoint { REAL4 outPoint[]; };
layout(std430, binding = kBindingOutput + kFieldD1) writeonly buffer OutD1 { REAL4 outD1[]; };
layout(std430, binding = kBindingOutput + kFieldD2) writeonly buffer OutD2 { REAL4 outD2[]; };

layout(push_constant) uniform PushBlock { KnotEvalPush pc; };

const bool kWantPoint = (OUTPUT_MASK & (1u << kFieldPoint)) != 0u;
const bool kWantD1 = (OUTPUT_MASK & (1u << kFieldD1)) != 0u;
const bool kWantD2 = (OUTPUT_MASK & (1u << kFieldD2)) != 0u;

struct CurvePoint {
  REAL3 point, d1, d2;
};

CurvePoint evalSample(uint k) {
  int span;
  REAL x;
  if (pc.listMode != 0u) {
    ListSample s = samples[pc.firstItem + k];
    span = int(s.i);
    x = s.u;
  } else {
    uint g = pc.firstRow + k;  // rows of a curve chunk are samples
    uint item = g / pc.samplesU, a = g - item * pc.samplesU;
    REAL local;
    gridKnotParameter(pc.knotOffsetU, pc.intervalOffsetU + (pc.firstItem + item) * kIntervalStride, a, pc.samplesU,
                      span, x, local);
  }
  REAL b[kMaxBasis], d1[kMaxBasis], d2[kMaxBasis];
  bsplineBasisDerivs(pc.knotOffsetU, BASIS_COUNT_U, span, x, b, d1, d2);
  uint first = uint(span) + 1u - BASIS_COUNT_U;
  CurvePoint o;
  o.point = REAL3(0);
  o.d1 = REAL3(0);
  o.d2 = REAL3(0);
  REAL w0 = REAL(0), w1 = REAL(0), w2 = REAL(0);  // W, W', W'' of a rational curve
  for (uint r = 0; r < BASIS_COUNT_U; ++r) {
    REAL4 P = net[first + r];
    accumulate3(o.point, o.d1, o.d2, b[r], d1[r], d2[r], P.xyz);
    w0 += b[r] * P.w, w1 += d1[r] * P.w, w2 += d2[r] * P.w;
  }
  if (RATIONAL != 0u) rationalCurve(o.point, o.d1, o.d2, w0, w1, w2);
  return o;
}

// One point at a time in a loop the compiler keeps rolled: de Boor–Cox of order up to 10 is large
// code, and four inlined copies (the uniform kernels' vec4 path) multiply llvmpipe compile time.
void main() {
  uint q = flatInvocation();
  uint total = pc.listMode != 0u ? pc.itemCount : pc.rowCount;
  uint k0 = q * kPointsPerInvocation;
  if (k0 >= total) return;
  uint n = min(kPointsPerInvocation, total - k0);
  [[dont_unroll]] for (uint e = 0; e < n; ++e) {
    CurvePoint s = evalSample(k0 + e);
    if (kWantPoint) STORE_XYZ_SCALAR(outPoint, k0 + e, s.point)
    if (kWantD1) STORE_XYZ_SCALAR(outD1, k0 + e, s.d1)
    if (kWantD2) STORE_XYZ_SCALAR(outD2, k0 + e, s.d2)
  }
}
