#version 450
// Grid path of bspline_surface_eval.comp (knot-vector B-spline surfaces, docs/math.md §10.1): the
// bases of every interval's grid samples come tabulated in TABLE (gpu/knot_grid_table.h, filled from
// core/knot_table.h, the one de Boor–Cox of point_math.h), per sample [span, N, N', N''], so that a
// point costs the tensor contraction alone, as on the uniform path. One invocation = RUN_LENGTH
// consecutive samples of one row a of one interval pair: the net is contracted in u once
// (T_d[s] = Σ_r N_r^(d)(u_a) P[r][s], core/grid_sampler.cpp order: u first, then v), again only where
// a sample's v span changes (the last sample of an interval at a knot where a derivative jumps).
// Normals: du x dv; degenerate points take knot_patch.glsl's rule.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "bspline.glsl"

layout(std430, binding = kBindingTable) readonly buffer TableBuf { REAL table[]; };
layout(std430, binding = kBindingOutput + kFieldPoint) writeonly buffer OutPoint { REAL4 outPoint[]; };
layout(std430, binding = kBindingOutput + kFieldDu) writeonly buffer OutDu { REAL4 outDu[]; };
layout(std430, binding = kBindingOutput + kFieldDv) writeonly buffer OutDv { REAL4 outDv[]; };
layout(std430, binding = kBindingOutput + kFieldDuu) writeonly buffer OutDuu { REAL4 outDuu[]; };
layout(std430, binding = kBindingOutput + kFieldDuv) writeonly buffer OutDuv { REAL4 outDuv[]; };
layout(std430, binding = kBindingOutput + kFieldDvv) writeonly buffer OutDvv { REAL4 outDvv[]; };
layout(std430, binding = kBindingOutput + kFieldNormal) writeonly buffer OutNormal { REAL4 outNormal[]; };

layout(push_constant) uniform PushBlock { KnotEvalPush pc; };

const bool kWantPoint = (OUTPUT_MASK & (1u << kFieldPoint)) != 0u;
const bool kWantDu = (OUTPUT_MASK & (1u << kFieldDu)) != 0u;
const bool kWantDv = (OUTPUT_MASK & (1u << kFieldDv)) != 0u;
const bool kWantDuu = (OUTPUT_MASK & (1u << kFieldDuu)) != 0u;
const bool kWantDuv = (OUTPUT_MASK & (1u << kFieldDuv)) != 0u;
const bool kWantDvv = (OUTPUT_MASK & (1u << kFieldDvv)) != 0u;
const bool kWantNormal = (OUTPUT_MASK & (1u << kFieldNormal)) != 0u;

#include "knot_patch.glsl"

// Samples per invocation (divides samplesV; at most 8).
layout(constant_id = kSpecRunLength) const uint RUN_LENGTH = 1;
const uint MU = BASIS_COUNT_U;
const uint MV = BASIS_COUNT_V;
const uint STRIDE_U = 1u + 3u * MU;  // TABLE entry of one sample: span, N, N', N''
const uint STRIDE_V = 1u + 3u * MV;

void main() {
  uint q = flatInvocation();
  uint runs = pc.samplesV / RUN_LENGTH;
  uint row = q / runs;  // row of the chunk
  if (row >= pc.rowCount) return;
  uint b0 = (q - row * runs) * RUN_LENGTH;
  uint g = pc.firstRow + row;
  uint item = g / pc.samplesU, a = g - item * pc.samplesU;
  uint lin = pc.firstItem + item;
  uint pu = lin / pc.itemsV, pv = lin - pu * pc.itemsV;

  uint eu = (pu * pc.samplesU + a) * STRIDE_U;
  int spanU = int(table[eu]);
  REAL bu[3][MU];
  [[unroll]] for (uint d = 0; d < 3u; ++d)
    [[unroll]] for (uint r = 0; r < MU; ++r) bu[d][r] = table[eu + 1u + d * MU + r];
  uint netRow = uint(spanU + 1 - int(MU)) * pc.netCols;

  REAL3 t0[MV], t1[MV], t2[MV];
  REAL tw0[MV], tw1[MV], tw2[MV];  // the same sums of the weights (rational surfaces)
  int span = -1;
  for (uint e = 0; e < RUN_LENGTH; ++e) {
    uint b = b0 + e;
    uint ev = pc.tableOffsetV + (pv * pc.samplesV + b) * STRIDE_V;
    int spanV = int(table[ev]);
    if (spanV != span) {
      span = spanV;
      uint first = netRow + uint(spanV + 1 - int(MV));
      [[unroll]] for (uint s = 0; s < MV; ++s) {
        t0[s] = REAL3(0);
        t1[s] = REAL3(0);
        t2[s] = REAL3(0);
        tw0[s] = REAL(0), tw1[s] = REAL(0), tw2[s] = REAL(0);
        [[unroll]] for (uint r = 0; r < MU; ++r) {
          REAL4 P = net[first + r * pc.netCols + s];
          accumulate3(t0[s], t1[s], t2[s], bu[0][r], bu[1][r], bu[2][r], P.xyz);
          tw0[s] += bu[0][r] * P.w, tw1[s] += bu[1][r] * P.w, tw2[s] += bu[2][r] * P.w;
        }
      }
    }
    Sample o;
    o.p = REAL3(0); o.u = REAL3(0); o.v = REAL3(0); o.uu = REAL3(0); o.uv = REAL3(0); o.vv = REAL3(0);
    // v contraction of the u-contracted rows: accumulateTensorRow with the directions' roles swapped.
    REAL w = REAL(0), wu = REAL(0), wv = REAL(0), wuu = REAL(0), wuv = REAL(0), wvv = REAL(0);
    [[unroll]] for (uint s = 0; s < MV; ++s) {
      REAL b0v = table[ev + 1u + s], b1v = table[ev + 1u + MV + s], b2v = table[ev + 1u + 2u * MV + s];
      accumulateTensorRow(o.p, o.v, o.u, o.vv, o.uv, o.uu, b0v, b1v, b2v, t0[s], t1[s], t2[s]);
      w += b0v * tw0[s], wv += b1v * tw0[s], wvv += b2v * tw0[s], wu += b0v * tw1[s], wuv += b1v * tw1[s],
          wuu += b0v * tw2[s];
    }
    if (RATIONAL != 0u) rationalSurface(o.p, o.u, o.v, o.uu, o.uv, o.vv, w, wu, wv, wuu, wuv, wvv);
    uint k = row * pc.samplesV + b;
    if (kWantPoint) STORE_XYZ_SCALAR(outPoint, k, o.p)
    if (kWantDu) STORE_XYZ_SCALAR(outDu, k, o.u)
    if (kWantDv) STORE_XYZ_SCALAR(outDv, k, o.v)
    if (kWantDuu) STORE_XYZ_SCALAR(outDuu, k, o.uu)
    if (kWantDuv) STORE_XYZ_SCALAR(outDuv, k, o.uv)
    if (kWantDvv) STORE_XYZ_SCALAR(outDvv, k, o.vv)
    if (kWantNormal) {
      uint recU = pc.intervalOffsetU + pu * kIntervalStride, recV = pc.intervalOffsetV + pv * kIntervalStride;
      REAL lu = pc.samplesU > 1u ? REAL(a) / REAL(pc.samplesU - 1u) : REAL(0);
      REAL lv = pc.samplesV > 1u ? REAL(b) / REAL(pc.samplesV - 1u) : REAL(0);
      STORE_XYZ_SCALAR(outNormal, k, knotNormal(o.u, o.v, int(params[recU]), int(params[recV]), lu, lv))
    }
  }
}
