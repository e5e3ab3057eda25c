#version 450
// Tensor-product surfaces of the uniform families (docs/math.md §6) and α-EB surfaces (§5.2, §5.3):
// point, first and second partials and the unit normal of the §5.3 convention, for a per-patch
// Su x Sv grid (basis values read from the TABLE written by basis_table.comp) or a list of
// (patch, u, v). Each invocation evaluates 4 consecutive output points and stores each field as
// three vec4 (layout.h). Patch evaluation and normals: surface_patch.glsl.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = kBindingTable) readonly buffer TableBuf { REAL table[]; };
layout(std430, binding = kBindingSamples) readonly buffer SampleBuf { ListSample samples[]; };
layout(std430, binding = kBindingOutput + kFieldPoint) writeonly buffer OutPoint { REAL4 outPoint[]; };
layout(std430, binding = kBindingOutput + kFieldDu) writeonly buffer OutDu { REAL4 outDu[]; };
layout(std430, binding = kBindingOutput + kFieldDv) writeonly buffer OutDv { REAL4 outDv[]; };
layout(std430, binding = kBindingOutput + kFieldDuu) writeonly buffer OutDuu { REAL4 outDuu[]; };
layout(std430, binding = kBindingOutput + kFieldDuv) writeonly buffer OutDuv { REAL4 outDuv[]; };
layout(std430, binding = kBindingOutput + kFieldDvv) writeonly buffer OutDvv { REAL4 outDvv[]; };
layout(std430, binding = kBindingOutput + kFieldNormal) writeonly buffer OutNormal { REAL4 outNormal[]; };

layout(push_constant) uniform PushBlock { EvalPush pc; };

const bool kWantPoint = (OUTPUT_MASK & (1u << kFieldPoint)) != 0u;
const bool kWantDu = (OUTPUT_MASK & (1u << kFieldDu)) != 0u;
const bool kWantDv = (OUTPUT_MASK & (1u << kFieldDv)) != 0u;
const bool kWantDuu = (OUTPUT_MASK & (1u << kFieldDuu)) != 0u;
const bool kWantDuv = (OUTPUT_MASK & (1u << kFieldDuv)) != 0u;
const bool kWantDvv = (OUTPUT_MASK & (1u << kFieldDvv)) != 0u;
const bool kWantNormal = (OUTPUT_MASK & (1u << kFieldNormal)) != 0u;

#include "surface_patch.glsl"

struct Sample {
  REAL3 p, u, v, uu, uv, vv, n;
};

Sample evalSample(uint k) {
  uint i, j;
  REAL u, v;
  Basis2 B;
  if (LIST_MODE != 0u) {
    ListSample s = samples[pc.firstItem + k];
    i = s.i;
    j = s.j;
    u = s.u;
    v = s.v;
    hornerBasis(i, j, u, v, B);
  } else {
    // Row of the chunk, then row counted from the start of item firstItem (no Su*Sv product:
    // 65536 x 65536 overflows 32 bits).
    uint row = k / pc.samplesV, b = k - row * pc.samplesV;
    uint g = pc.firstRow + row;
    uint item = g / pc.samplesU, a = g - item * pc.samplesU;
    uint lin = pc.firstItem + item;
    uint pi = lin / pc.itemsV;
    i = pi + pc.firstSpanU;
    j = lin - pi * pc.itemsV + pc.firstSpanV;
    u = pc.samplesU > 1u ? REAL(a) / REAL(pc.samplesU - 1u) : REAL(0);
    v = pc.samplesV > 1u ? REAL(b) / REAL(pc.samplesV - 1u) : REAL(0);
    uint tu = a * 3u * BASIS_COUNT_U, tv = pc.tableOffsetV + b * 3u * BASIS_COUNT_V;
    for (uint r = 0; r < BASIS_COUNT_U; ++r) {
      B.bu[r] = table[tu + r];
      B.du[r] = table[tu + BASIS_COUNT_U + r];
      B.ddu[r] = table[tu + 2u * BASIS_COUNT_U + r];
    }
    for (uint r = 0; r < BASIS_COUNT_V; ++r) {
      B.bv[r] = table[tv + r];
      B.dv[r] = table[tv + BASIS_COUNT_V + r];
      B.ddv[r] = table[tv + 2u * BASIS_COUNT_V + r];
    }
  }
  PatchDerivs c;
  PatchDerivs q = evalPatch(B, i, j, u, v, c);
  Sample o;
  o.p = q.p; o.u = q.u; o.v = q.v; o.uu = q.uu; o.uv = q.uv; o.vv = q.vv;
  o.n = kWantNormal ? surfaceNormal(i, j, u, v, q, c) : REAL3(0);
  return o;
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
  uint total = LIST_MODE != 0u ? pc.itemCount : pc.rowCount * pc.samplesV;
  uint k0 = q * kPointsPerInvocation;
  if (k0 >= total) return;
  uint n = min(kPointsPerInvocation, total - k0);
  bool full = n == kPointsPerInvocation;
  Sample s[4];
  for (uint e = 0; e < kPointsPerInvocation; ++e) s[e] = evalSample(min(k0 + e, total - 1u));
  STORE_FIELD(kWantPoint, outPoint, p)
  STORE_FIELD(kWantDu, outDu, u)
  STORE_FIELD(kWantDv, outDv, v)
  STORE_FIELD(kWantDuu, outDuu, uu)
  STORE_FIELD(kWantDuv, outDuv, uv)
  STORE_FIELD(kWantDvv, outDvv, vv)
  STORE_FIELD(kWantNormal, outNormal, n)
}
