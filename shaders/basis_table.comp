#version 450
// Basis table: B_r, B_r', B_r'' of one SpanBasis (coefficients in PARAMS) at N parameter values,
// table[tableOffset + a*3m + d*m + r] (layout.h). The evaluation kernels read it in grid mode (the
// values depend only on the sample position, so they are computed once per job instead of once
// per point); renderers that evaluate in their own shaders can bind it too.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(std430, binding = kBindingTable) writeonly buffer TableBuf { REAL table[]; };
layout(std430, binding = kBindingSamples) readonly buffer SampleBuf { ListSample samples[]; };
layout(push_constant) uniform PushBlock { TablePush pc; };

void main() {
  uint a = flatInvocation();
  if (a >= pc.sampleCount) return;
  REAL t;
  if (pc.listMode != 0u) t = samples[a].u;
  else t = pc.sampleCount > 1u ? REAL(a) / REAL(pc.sampleCount - 1u) : REAL(0);
  REAL b[kMaxBasis], d1[kMaxBasis], d2[kMaxBasis];
  evalSpanBasis(pc.coefOffset, BASIS_COUNT_U, POLY_DEGREE_U, t, b, d1, d2);
  uint base = pc.tableOffset + a * 3u * BASIS_COUNT_U;
  for (uint r = 0; r < BASIS_COUNT_U; ++r) {
    table[base + r] = b[r];
    table[base + BASIS_COUNT_U + r] = d1[r];
    table[base + 2u * BASIS_COUNT_U + r] = d2[r];
  }
}
