#version 450
// Curves of the uniform local families (docs/math.md §1, with optional span knots: derivatives times
// 1/h^r) and α-EB curves (§4.2): point, d1, d2 for a per-span grid of S samples (basis values from
// the TABLE of basis_table.comp) or a list of (span, t). 4 output points per invocation, each field
// stored as three vec4 (layout.h). The loops of host/core/curve.cpp evalLocalSpan / evalAlphaEBSpan
// around the formulas of point_math.h.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = kBindingTable) readonly buffer TableBuf { REAL table[]; };
layout(std430, binding = kBindingSamples) readonly buffer SampleBuf { ListSample samples[]; };
layout(std430, binding = kBindingOutput + kFieldPoint) writeonly buffer OutPoint { REAL4 outPoint[]; };
layout(std430, binding = kBindingOutput + kFieldD1) writeonly buffer OutD1 { REAL4 outD1[]; };
layout(std430, binding = kBindingOutput + kFieldD2) writeonly buffer OutD2 { REAL4 outD2[]; };

layout(push_constant) uniform PushBlock { EvalPush pc; };

const bool kWantPoint = (OUTPUT_MASK & (1u << kFieldPoint)) != 0u;
const bool kWantD1 = (OUTPUT_MASK & (1u << kFieldD1)) != 0u;
const bool kWantD2 = (OUTPUT_MASK & (1u << kFieldD2)) != 0u;

struct CurvePoint {
  REAL3 point, d1, d2;
};

// core/curve.cpp evalLocalSpan: pts = NET[first .. first + m - 1].
CurvePoint evalLocalSpan(in REAL b[kMaxBasis], in REAL d1[kMaxBasis], in REAL d2[kMaxBasis], uint first,
                         REAL invH) {
  REAL3 p = REAL3(0), q1 = REAL3(0), q2 = REAL3(0);
  for (uint r = 0; r < BASIS_COUNT_U; ++r) accumulate3(p, q1, q2, b[r], d1[r], d2[r], net[first + r].xyz);
  CurvePoint o;
  o.point = p;
  o.d1 = q1 * invH;
  o.d2 = q2 * (invH * invH);
  return o;
}

// core/curve.cpp evalAlphaEBSpan (docs/math.md §4.2).
CurvePoint evalAlphaEBSpan(in REAL b[kMaxBasis], in REAL d1[kMaxBasis], in REAL d2[kMaxBasis], uint first,
                           REAL3 v0, REAL3 v1, REAL a0, REAL a1, REAL t) {
  CurvePoint c = evalLocalSpan(b, d1, d2, first, REAL(1));
  alphaEBBlendCurve(singularBlend(t), v0, v1, a0, a1, c.point, c.d1, c.d2);
  return c;
}

CurvePoint evalSample(uint k) {
  uint span;
  REAL t;
  REAL b[kMaxBasis], d1[kMaxBasis], d2[kMaxBasis];
  if (LIST_MODE != 0u) {
    ListSample s = samples[pc.firstItem + k];
    span = s.i;
    t = s.u;
    evalSpanBasis(kParamCoefU, BASIS_COUNT_U, POLY_DEGREE_U, t, b, d1, d2);
  } else {
    uint g = pc.firstRow + k;  // rows of a curve chunk are samples
    uint item = g / pc.samplesU, a = g - item * pc.samplesU;
    span = pc.firstItem + item + pc.firstSpanU;
    t = pc.samplesU > 1u ? REAL(a) / REAL(pc.samplesU - 1u) : REAL(0);
    uint tu = a * 3u * BASIS_COUNT_U;
    for (uint r = 0; r < BASIS_COUNT_U; ++r) {
      b[r] = table[tu + r];
      d1[r] = table[tu + BASIS_COUNT_U + r];
      d2[r] = table[tu + 2u * BASIS_COUNT_U + r];
    }
  }
  uint first = span + pc.netOffsetU;
  if (ALPHA_EB != 0u) {
    uint j0 = span % pc.rows, j1 = (span + 1u) % pc.rows;
    return evalAlphaEBSpan(b, d1, d2, first, verts[j0].xyz, verts[j1].xyz, params[pc.alphaOffset + j0],
                           params[pc.alphaOffset + j1], t);
  }
  REAL invH = pc.invHOffset != kNoOffset ? params[pc.invHOffset + span - pc.firstSpanU] : REAL(1);
  return evalLocalSpan(b, d1, d2, first, invH);
}

#define STORE_FIELD(want, plane, member)                                                   \
  if (want) {                                                                              \
    if (full) {                                                                            \
      STORE_XYZ4(plane, q, s[0].member, s[1].member, s[2].member, s[3].member);            \
    } else {                                                                               \
      for (uint e = 0; e < n; ++e) STORE_XYZ_SCALAR(plane, k0 + e, s[e].member);           \
    }                                                                                      \
  }

void main() {
  uint q = flatInvocation();
  uint total = LIST_MODE != 0u ? pc.itemCount : pc.rowCount;
  uint k0 = q * kPointsPerInvocation;
  if (k0 >= total) return;
  uint n = min(kPointsPerInvocation, total - k0);
  bool full = n == kPointsPerInvocation;
  CurvePoint s[4];
  for (uint e = 0; e < kPointsPerInvocation; ++e) s[e] = evalSample(min(k0 + e, total - 1u));
  STORE_FIELD(kWantPoint, outPoint, point)
  STORE_FIELD(kWantD1, outD1, d1)
  STORE_FIELD(kWantD2, outD2, d2)
}
