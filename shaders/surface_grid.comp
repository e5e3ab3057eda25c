#version 450
// Fast grid path of surface_eval.comp for plain tensor surfaces (MATH.md §1, §6) when samplesV is a
// multiple of 4 and no normal is asked: one invocation = RUN_LENGTH consecutive samples of one row a
// of one patch. The u contraction T_d[s] = Σ_r B_r^(d)(u_a) P[r][s] (core/grid_sampler.cpp order:
// u first, then v) is done once per invocation and shared by the RUN_LENGTH points; every loop bound is a
// specialization constant (m_u, m_v, degree) so LLVM unrolls them and the local arrays stay in registers.
// Output layout as surface_eval.comp (layout.h): 4 points = three REAL4 per field.
//
// Tuned for llvmpipe/lavapipe, where every SSBO access of a SIMD vector is a per-lane loop (gather /
// scatter with a bounds check per lane), so the number of load and store *components* is the cost:
//  - the v basis is evaluated in registers per sample (evalSpanBasis Horner, the same code and t =
//    b/(Sv-1) as basis_table.comp, so the values are identical) from the v coefficients loaded once
//    per invocation, instead of 2-3 m_v TABLE loads per point;
//  - likewise the u basis (evalSpanBasis on t = a/(Su-1), as basis_table.comp): the coefficient
//    loads have constant addresses, which llvmpipe turns into one scalar load instead of a gather;
//  - RUN_LENGTH may exceed samplesV: one invocation then covers RUN_LENGTH / samplesV consecutive
//    rows of one patch (evaluator.cpp picks RUN_LENGTH), so the m_u x m_v net gathers are paid once
//    per several rows.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"

layout(std430, binding = 5) writeonly buffer OutPoint { REAL4 outPoint[]; };
layout(std430, binding = 8) writeonly buffer OutDu { REAL4 outDu[]; };
layout(std430, binding = 9) writeonly buffer OutDv { REAL4 outDv[]; };
layout(std430, binding = 10) writeonly buffer OutDuu { REAL4 outDuu[]; };
layout(std430, binding = 11) writeonly buffer OutDuv { REAL4 outDuv[]; };
layout(std430, binding = 12) writeonly buffer OutDvv { REAL4 outDvv[]; };

layout(push_constant) uniform PushBlock { EvalPush pc; };

const bool kWantPoint = (OUTPUT_MASK & (1u << kFieldPoint)) != 0u;
const bool kWantDu = (OUTPUT_MASK & (1u << kFieldDu)) != 0u;
const bool kWantDv = (OUTPUT_MASK & (1u << kFieldDv)) != 0u;
const bool kWantDuu = (OUTPUT_MASK & (1u << kFieldDuu)) != 0u;
const bool kWantDuv = (OUTPUT_MASK & (1u << kFieldDuv)) != 0u;
const bool kWantDvv = (OUTPUT_MASK & (1u << kFieldDvv)) != 0u;
const bool kNeedT1 = kWantDu || kWantDuv;
const bool kNeedD1V = kWantDv || kWantDuv;
// Samples per invocation (a multiple of 4): RUN_LENGTH < samplesV: a run of one row (RUN_LENGTH
// divides samplesV); RUN_LENGTH >= samplesV: RUN_LENGTH / samplesV whole rows of one patch (dividing
// samplesU). The u contraction of a row is shared by all of its samples.
layout(constant_id = 9) const uint RUN_LENGTH = 4;
const uint MU = BASIS_COUNT_U;
const uint MV = BASIS_COUNT_V;
const uint DU = POLY_DEGREE_U;
const uint DV = POLY_DEGREE_V;

void main() {
  uint q = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  uint rowsPer = max(1u, RUN_LENGTH / pc.samplesV);  // rows of this invocation
  uint runLen = min(RUN_LENGTH, pc.samplesV);         // samples of each of its rows
  uint runs = pc.samplesV / runLen;
  uint block = q / runs;                              // row block: rows block*rowsPer ..
  uint row0 = block * rowsPer;
  if (row0 >= pc.itemCount * pc.samplesU) return;
  uint bRun = (q - block * runs) * runLen;
  uint item = row0 / pc.samplesU, a0 = row0 - item * pc.samplesU;
  uint lin = pc.firstItem + item;
  uint pi = lin / pc.itemsV;
  uint i = pi + pc.firstSpanU, j = lin - pi * pc.itemsV + pc.firstSpanV;
  uint base = (i + pc.netOffsetU) * pc.netCols + j + pc.netOffsetV;

  // The patch net, once per invocation.
  REAL3 P[MU][MV];
  [[unroll]] for (uint r = 0; r < MU; ++r)
    [[unroll]] for (uint s = 0; s < MV; ++s) P[r][s] = net[base + r * pc.netCols + s].xyz;
  // Basis coefficients coef[r][d] (PARAMS, constant addresses) in registers.
  REAL cu[MU][DU + 1u], cv[MV][DV + 1u];
  [[unroll]] for (uint r = 0; r < MU; ++r)
    [[unroll]] for (uint d = 0; d <= DU; ++d) cu[r][d] = params[kParamCoefU + r * kCoefStride + d];
  [[unroll]] for (uint s = 0; s < MV; ++s)
    [[unroll]] for (uint d = 0; d <= DV; ++d) cv[s][d] = params[kParamCoefV + s * kCoefStride + d];
  REAL denU = REAL(pc.samplesU - 1u), denV = REAL(pc.samplesV - 1u);

  for (uint k = 0; k < rowsPer; ++k) {
    uint a = a0 + k, row = row0 + k;
    // evalSpanBasis for u_a (basis_table.comp: t = a/(Su-1)).
    REAL tu = pc.samplesU > 1u ? REAL(a) / denU : REAL(0);
    REAL3 T0[MV], T1[MV], T2[MV];
    [[unroll]] for (uint s = 0; s < MV; ++s) {
      T0[s] = REAL3(0);
      T1[s] = REAL3(0);
      T2[s] = REAL3(0);
    }
    [[unroll]] for (uint r = 0; r < MU; ++r) {
      REAL w0 = cu[r][DU], dp = REAL(0), ddp = REAL(0);
      [[unroll]] for (int d = int(DU) - 1; d >= 0; --d) {
        ddp = ddp * tu + dp;
        dp = dp * tu + w0;
        w0 = w0 * tu + cu[r][d];
      }
      REAL w1 = dp, w2 = REAL(2) * ddp;
      [[unroll]] for (uint s = 0; s < MV; ++s) {
        T0[s] += w0 * P[r][s];
        if (kNeedT1) T1[s] += w1 * P[r][s];
        if (kWantDuu) T2[s] += w2 * P[r][s];
      }
    }

    for (uint g = 0; g < runLen / 4u; ++g) {
      uint b0 = bRun + 4u * g;
      REAL3 p[4], u[4], v[4], uu[4], uv[4], vv[4];
      [[unroll]] for (uint e = 0; e < 4u; ++e) {
        // evalSpanBasis for v_b (basis_table.comp: t = b/(Sv-1)): p, p', p''/2 by Horner.
        REAL t = pc.samplesV > 1u ? REAL(b0 + e) / denV : REAL(0);
        p[e] = REAL3(0); u[e] = REAL3(0); v[e] = REAL3(0); uu[e] = REAL3(0); uv[e] = REAL3(0); vv[e] = REAL3(0);
        [[unroll]] for (uint s = 0; s < MV; ++s) {
          REAL c0 = cv[s][DV], dp = REAL(0), ddp = REAL(0);
          [[unroll]] for (int d = int(DV) - 1; d >= 0; --d) {
            ddp = ddp * t + dp;
            dp = dp * t + c0;
            c0 = c0 * t + cv[s][d];
          }
          REAL c1 = dp, c2 = REAL(2) * ddp;
          p[e] += c0 * T0[s];
          if (kNeedT1) u[e] += c0 * T1[s];
          if (kNeedD1V) v[e] += c1 * T0[s];
          if (kWantDuu) uu[e] += c0 * T2[s];
          if (kWantDuv) uv[e] += c1 * T1[s];
          if (kWantDvv) vv[e] += c2 * T0[s];
        }
      }
      uint o = (row * pc.samplesV + b0) >> 2;
      if (kWantPoint) STORE_XYZ4(outPoint, o, p[0], p[1], p[2], p[3])
      if (kWantDu) STORE_XYZ4(outDu, o, u[0], u[1], u[2], u[3])
      if (kWantDv) STORE_XYZ4(outDv, o, v[0], v[1], v[2], v[3])
      if (kWantDuu) STORE_XYZ4(outDuu, o, uu[0], uu[1], uu[2], uu[3])
      if (kWantDuv) STORE_XYZ4(outDuv, o, uv[0], uv[1], uv[2], uv[3])
      if (kWantDvv) STORE_XYZ4(outDvv, o, vv[0], vv[1], vv[2], vv[3])
    }
  }
}
