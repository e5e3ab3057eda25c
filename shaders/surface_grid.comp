#version 450
// Fast grid path of surface_eval.comp for tensor surfaces (docs/math.md §1, §6; also knot-vector
// B-splines, rational or not, as knot patches, §10.1, §10.8, gpu/kernel_runs.h knotPatchGridJob) and α-EB surfaces
// (§5.2, §5.3: Q = C + a (L - C) with the bilinear singular-blend weights of the 4 corner α and V,
// their u half blended once per row, derivatives by the weight rule) when samplesV is a multiple
// of 4, with or without the unit normal: one invocation = RUN_LENGTH consecutive samples of one
// row a of one patch. The u contraction T_d[s] = Σ_r B_r^(d)(u_a) P[r][s] (core/grid_sampler.cpp order:
// u first, then v) is done once per invocation and shared by the RUN_LENGTH points; every loop bound is a
// specialization constant (m_u, m_v, degree) so LLVM unrolls them and the local arrays stay in registers.
// Output layout as surface_eval.comp (layout.h): 4 points = three REAL4 per field.
// Normals (core/grid_sampler.cpp): regular points get normalize(cross(Q_u, Q_v)); α-EB patch corners
// and degenerate crosses call surfaceNormal() of surface_patch.glsl (the full §5.3 convention of
// surface_eval.comp: α = 1 corner limit, δ = 2^-12 shift, base-surface fallback).
//
// Tuned for llvmpipe/lavapipe, where every SSBO access of a SIMD vector is a per-lane loop (gather /
// scatter with a bounds check per lane), so the number of load and store *components* is the cost:
//  - the v direction is evaluated in registers per sample, instead of 2-3 m_v TABLE loads per
//    point: each row's u contraction is turned into polynomials in v (the power basis of the v
//    basis coefficients, loaded once per invocation), one Horner pass per sample;
//  - likewise the u basis (evalSpanBasis on t = a/(Su-1), as basis_table.comp): the coefficient
//    loads have constant addresses, which llvmpipe turns into one scalar load instead of a gather;
//  - RUN_LENGTH may exceed samplesV: one invocation then covers RUN_LENGTH / samplesV consecutive
//    rows of one patch (evaluator.cpp picks RUN_LENGTH), so the m_u x m_v net gathers are paid once
//    per several rows.
// variant: packed-stores (fp32 output planes stored as uint64 pairs; common.glsl)
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"

layout(std430, binding = kBindingOutput + kFieldPoint) writeonly buffer OutPoint { PLANE4 outPoint[]; };
layout(std430, binding = kBindingOutput + kFieldDu) writeonly buffer OutDu { PLANE4 outDu[]; };
layout(std430, binding = kBindingOutput + kFieldDv) writeonly buffer OutDv { PLANE4 outDv[]; };
layout(std430, binding = kBindingOutput + kFieldDuu) writeonly buffer OutDuu { PLANE4 outDuu[]; };
layout(std430, binding = kBindingOutput + kFieldDuv) writeonly buffer OutDuv { PLANE4 outDuv[]; };
layout(std430, binding = kBindingOutput + kFieldDvv) writeonly buffer OutDvv { PLANE4 outDvv[]; };
// Normals stay REAL4 in every variant: the fallback pass rewrites single points (3 REALs), which
// a packed view could not do without the neighbouring point's normal.
layout(std430, binding = kBindingOutput + kFieldNormal) writeonly buffer OutNormal { REAL4 outNormal[]; };
layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };

layout(push_constant) uniform PushBlock { EvalPush pc; };

#include "surface_patch.glsl"

const bool kWantPoint = (OUTPUT_MASK & (1u << kFieldPoint)) != 0u;
const bool kWantDu = (OUTPUT_MASK & (1u << kFieldDu)) != 0u;
const bool kWantDv = (OUTPUT_MASK & (1u << kFieldDv)) != 0u;
const bool kWantDuu = (OUTPUT_MASK & (1u << kFieldDuu)) != 0u;
const bool kWantDuv = (OUTPUT_MASK & (1u << kFieldDuv)) != 0u;
const bool kWantDvv = (OUTPUT_MASK & (1u << kFieldDvv)) != 0u;
const bool kWantNormal = (OUTPUT_MASK & (1u << kFieldNormal)) != 0u;
const bool kAEB = ALPHA_EB != 0u;
// Rational knot patches (NURBS): NET holds (w P, w); the weight sums W ride along as a scalar
// channel and the quotient rule of point_math.h turns the homogeneous partials into the surface's.
const bool kRational = RATIONAL != 0u;
// Base partials C_u / C_v: for their own field, the normal, and the α-EB or rational second
// partials (the quotient rule of S_uu needs S_u). (Plain integer spec-constant arithmetic: glslang
// emits invalid SPIR-V for nested && / || of them.)
const bool kNeedT1 = (OUTPUT_MASK & ((1u << kFieldDu) | (1u << kFieldDuv) | (1u << kFieldNormal) |
                                     (ALPHA_EB | RATIONAL) * (1u << kFieldDuu))) != 0u;
const bool kNeedD1V = (OUTPUT_MASK & ((1u << kFieldDv) | (1u << kFieldDuv) | (1u << kFieldNormal) |
                                      (ALPHA_EB | RATIONAL) * (1u << kFieldDvv))) != 0u;
// Samples per invocation (a multiple of 4): RUN_LENGTH < samplesV: a run of one row (RUN_LENGTH
// divides samplesV); RUN_LENGTH >= samplesV: RUN_LENGTH / samplesV whole rows of one patch (dividing
// samplesU). The u contraction of a row is shared by all of its samples.
layout(constant_id = kSpecRunLength) const uint RUN_LENGTH = 4;
const uint MU = BASIS_COUNT_U;
const uint MV = BASIS_COUNT_V;
const uint DU = POLY_DEGREE_U;
const uint DV = POLY_DEGREE_V;

void main() {
  uint q = flatInvocation();
  uint rowsPer = max(1u, RUN_LENGTH / pc.samplesV);  // rows of this invocation
  uint runLen = min(RUN_LENGTH, pc.samplesV);         // samples of each of its rows
  uint runs = pc.samplesV / runLen;
  uint block = q / runs;                              // row block: rows block*rowsPer ..
  uint row0 = block * rowsPer;
  if (row0 >= pc.rowCount) return;
  uint bRun = (q - block * runs) * runLen;
  // row0 counts from the chunk's first row, firstRow rows into item firstItem (a multiple of
  // rowsPer: a patch larger than a chunk comes in row ranges).
  uint item = (pc.firstRow + row0) / pc.samplesU, a0 = pc.firstRow + row0 - item * pc.samplesU;
  uint lin = pc.firstItem + item;
  uint pi = lin / pc.itemsV;
  uint i = pi + pc.firstSpanU, j = lin - pi * pc.itemsV + pc.firstSpanV;
  uint base = netBase(i, j);
  // Knot patches (layout.h): partials with respect to the knot parameters, 1/h per direction times
  // the local ones (uniform families: 1, folded away).
  REAL ku = KNOT_PATCHES != 0u ? REAL(1) / params[knotPatchU(i) + 2u] : REAL(1);
  REAL kv = KNOT_PATCHES != 0u ? REAL(1) / params[knotPatchV(j) + 2u] : REAL(1);

  // The patch net, once per invocation.
  REAL3 P[MU][MV];
  REAL PW[MU][MV];  // rational: the weights (dead code otherwise, w never loaded)
  [[unroll]] for (uint r = 0; r < MU; ++r)
    [[unroll]] for (uint s = 0; s < MV; ++s) {
      REAL4 h = net[base + r * pc.netCols + s];
      P[r][s] = h.xyz;
      PW[r][s] = kRational ? h.w : REAL(0);
    }
  // Basis coefficients coef[r][d] (PARAMS, constant addresses) in registers.
  REAL cu[MU][DU + 1u], cv[MV][DV + 1u];
  [[unroll]] for (uint r = 0; r < MU; ++r)
    [[unroll]] for (uint d = 0; d <= DU; ++d) cu[r][d] = params[coefBaseU(i) + r * kCoefStride + d];
  [[unroll]] for (uint s = 0; s < MV; ++s)
    [[unroll]] for (uint d = 0; d <= DV; ++d) cv[s][d] = params[coefBaseV(j) + s * kCoefStride + d];
  REAL denU = REAL(pc.samplesU - 1u), denV = REAL(pc.samplesV - 1u);
  // α-EB corner data (i,j), (i,j+1), (i+1,j), (i+1,j+1), once per invocation.
  REAL3 V[4];
  REAL al[4];
  if (kAEB) {
    loadPatchCorners(i, j, V, al);
  }

  // Points whose normal needs the full §5.3 convention (degenerate crosses, α = 1 patch corners
  // among them): the first four are remembered, more make the whole invocation redo its normals.
  uint fallbackCount = 0u, fallback0 = 0u, fallback1 = 0u, fallback2 = 0u, fallback3 = 0u;
  for (uint k = 0; k < rowsPer; ++k) {
    uint a = a0 + k, row = row0 + k;
    // evalSpanBasis for u_a (basis_table.comp: t = a/(Su-1)).
    REAL tu = pc.samplesU > 1u ? REAL(a) / denU : REAL(0);
    BlendFactors fu = blendFactors(kAEB ? singularBlend(tu) : REAL3(0));
    // The u halves of the corner weights of this row, u orders 0, 1, 2.
    CornerHalf H0, H1, H2;
    if (kAEB) {
      H0 = cornerBlendU(fu.f00, fu.f01, al, V);
      H1 = cornerBlendU(fu.f10, fu.f11, al, V);
      H2 = cornerBlendU(fu.f20, fu.f21, al, V);
    }
    REAL3 T0[MV], T1[MV], T2[MV];
    REAL TW0[MV], TW1[MV], TW2[MV];  // the same sums of the weights (rational)
    [[unroll]] for (uint s = 0; s < MV; ++s) {
      T0[s] = REAL3(0);
      T1[s] = REAL3(0);
      T2[s] = REAL3(0);
      TW0[s] = REAL(0);
      TW1[s] = REAL(0);
      TW2[s] = REAL(0);
    }
    [[unroll]] for (uint r = 0; r < MU; ++r) {
      REAL w0 = cu[r][DU], dp = REAL(0), ddp = REAL(0);
      [[unroll]] for (int d = int(DU) - 1; d >= 0; --d) hornerStep(w0, dp, ddp, tu, cu[r][d]);
      // T1 and T2 feed only the outputs that need them (the rest is dead code).
      [[unroll]] for (uint s = 0; s < MV; ++s) {
        accumulate3(T0[s], T1[s], T2[s], w0, dp, REAL(2) * ddp, P[r][s]);
        accumulate3(TW0[s], TW1[s], TW2[s], w0, dp, REAL(2) * ddp, PW[r][s]);
      }
    }
    // The row in the power basis of v: W_k[d] = Σ_s c_s,d T_k[s] (B_s(v) = Σ_d c_s,d v^d), so a
    // sample is one Horner pass over d instead of every v basis function and a contraction
    // (llvmpipe fuses no multiply-adds: 54 instead of 120 operations for P, Q_u, Q_v of a bicubic).
    REAL3 W0[DV + 1u], W1[DV + 1u], W2[DV + 1u];
    REAL WW0[DV + 1u], WW1[DV + 1u], WW2[DV + 1u];  // rational: of TW0, TW1, TW2
    [[unroll]] for (uint d = 0; d <= DV; ++d) {
      W0[d] = REAL3(0);
      W1[d] = REAL3(0);
      W2[d] = REAL3(0);
      WW0[d] = REAL(0);
      WW1[d] = REAL(0);
      WW2[d] = REAL(0);
      [[unroll]] for (uint s = 0; s < MV; ++s) {
        W0[d] += cv[s][d] * T0[s];
        if (kNeedT1) W1[d] += cv[s][d] * T1[s];
        if (kWantDuu) W2[d] += cv[s][d] * T2[s];
        if (kRational) {
          WW0[d] += cv[s][d] * TW0[s];
          if (kNeedT1) WW1[d] += cv[s][d] * TW1[s];
          if (kWantDuu) WW2[d] += cv[s][d] * TW2[s];
        }
      }
    }

    for (uint g = 0; g < runLen / 4u; ++g) {
      uint b0 = bRun + 4u * g;
      REAL3 p[4], u[4], v[4], uu[4], uv[4], vv[4], nn[4];
      [[unroll]] for (uint e = 0; e < 4u; ++e) {
        // v_b = b/(Sv-1) (basis_table.comp's t); value, first and half second derivative of the
        // row polynomials by simultaneous Horner.
        REAL t = pc.samplesV > 1u ? REAL(b0 + e) / denV : REAL(0);
        // Partials no output needs are dead code.
        REAL3 c0 = W0[DV], c1 = REAL3(0), c2 = REAL3(0);  // of W0: C, C_v, C_vv / 2
        REAL3 e0 = W1[DV], e1 = REAL3(0), e2 = REAL3(0);  // of W1: C_u, C_uv
        REAL3 f0 = W2[DV], f1 = REAL3(0), f2 = REAL3(0);  // of W2: C_uu
        REAL cw0 = WW0[DV], cw1 = REAL(0), cw2 = REAL(0);   // rational: W, W_v, W_vv / 2
        REAL ew0 = WW1[DV], ew1 = REAL(0), ew2 = REAL(0);   // W_u, W_uv
        REAL fw0 = WW2[DV], fw1 = REAL(0), fw2 = REAL(0);   // W_uu
        [[unroll]] for (int d = int(DV) - 1; d >= 0; --d) {
          hornerStep(c0, c1, c2, t, W0[d]);
          hornerStep(e0, e1, e2, t, W1[d]);
          hornerStep(f0, f1, f2, t, W2[d]);
          if (kRational) {
            hornerStep(cw0, cw1, cw2, t, WW0[d]);
            hornerStep(ew0, ew1, ew2, t, WW1[d]);
            hornerStep(fw0, fw1, fw2, t, WW2[d]);
          }
        }
        p[e] = c0;
        u[e] = kNeedT1 ? e0 : REAL3(0);
        v[e] = kNeedD1V ? c1 : REAL3(0);
        uu[e] = kWantDuu ? f0 : REAL3(0);
        uv[e] = kWantDuv ? e1 : REAL3(0);
        vv[e] = kWantDvv ? REAL(2) * c2 : REAL3(0);
        if (kRational) rationalSurface(p[e], u[e], v[e], uu[e], uv[e], vv[e], cw0, ew0, cw1, fw0, ew1, REAL(2) * cw2);
        u[e] *= ku;
        v[e] *= kv;
        uu[e] *= ku * ku;
        uv[e] *= ku * kv;
        vv[e] *= kv * kv;
        if (kAEB) {
          // docs/math.md §5.3 (evalAlphaEBPatch): weight derivative (r,q) = u-factor r x v-factor q,
          // only for the orders the requested fields need.
          BlendFactors fv = blendFactors(singularBlend(t));
          AlphaEBWeights w = alphaEBWeightsZero();
          cornerBlendV(H0, fv.f00, fv.f01, w.a00, w.L00);
          if (kNeedT1) cornerBlendV(H1, fv.f00, fv.f01, w.a10, w.L10);
          if (kWantDuu) cornerBlendV(H2, fv.f00, fv.f01, w.a20, w.L20);
          if (kNeedD1V) cornerBlendV(H0, fv.f10, fv.f11, w.a01, w.L01);
          if (kWantDuv) cornerBlendV(H1, fv.f10, fv.f11, w.a11, w.L11);
          if (kWantDvv) cornerBlendV(H0, fv.f20, fv.f21, w.a02, w.L02);
          alphaEBBlendPatch(w, p[e], u[e], v[e], uu[e], uv[e], vv[e]);
        }
        if (kWantNormal) {
          // An α = 1 patch corner makes Q_u or Q_v vanish exactly and lands here as degenerate.
          // Selects, not branches (llvmpipe would run a per-lane branch for every sample).
          REAL3 n = cross(u[e], v[e]);
          REAL len = length(n);
          bool fb = degenerateCrossLength(u[e], v[e], len);
          uint pt = row * pc.samplesV + b0 + e;
          fallback0 = fb && fallbackCount == 0u ? pt : fallback0;
          fallback1 = fb && fallbackCount == 1u ? pt : fallback1;
          fallback2 = fb && fallbackCount == 2u ? pt : fallback2;
          fallback3 = fb && fallbackCount == 3u ? pt : fallback3;
          fallbackCount += fb ? 1u : 0u;
          nn[e] = n / len;
        }
      }
      uint o = (row * pc.samplesV + b0) >> 2;
      if (kWantPoint) STORE_XYZ4_PLANE(outPoint, o, p[0], p[1], p[2], p[3])
      if (kWantDu) STORE_XYZ4_PLANE(outDu, o, u[0], u[1], u[2], u[3])
      if (kWantDv) STORE_XYZ4_PLANE(outDv, o, v[0], v[1], v[2], v[3])
      if (kWantDuu) STORE_XYZ4_PLANE(outDuu, o, uu[0], uu[1], uu[2], uu[3])
      if (kWantDuv) STORE_XYZ4_PLANE(outDuv, o, uv[0], uv[1], uv[2], uv[3])
      if (kWantDvv) STORE_XYZ4_PLANE(outDvv, o, vv[0], vv[1], vv[2], vv[3])
      if (kWantNormal) STORE_XYZ4(outNormal, o, nn[0], nn[1], nn[2], nn[3])
    }
  }

  // The fallback normals, as surface_eval.comp computes them (hornerBasis gives the basis_table.comp
  // values; surfaceNormal is the shared §5.3 code), overwriting the regular ones stored above. A loop
  // and not an if: lavapipe runs a divergent branch for every SIMD vector, while a loop body runs once
  // per invocation when no lane needs it, and again only while some lane still has points left.
  if (kWantNormal) {
    uint todo = fallbackCount <= 4u ? fallbackCount : rowsPer * runLen;
    for (uint f = 0; f < todo; ++f) {
      uint pt;  // output point: row * samplesV + b
      if (fallbackCount <= 4u) {
        pt = f == 0u ? fallback0 : f == 1u ? fallback1 : f == 2u ? fallback2 : fallback3;
      } else {
        uint kk = f / runLen;
        pt = (row0 + kk) * pc.samplesV + bRun + (f - kk * runLen);
      }
      uint row = pt / pc.samplesV, b = pt - row * pc.samplesV, a = pc.firstRow + row - item * pc.samplesU;
      REAL u = pc.samplesU > 1u ? REAL(a) / denU : REAL(0);
      REAL v = pc.samplesV > 1u ? REAL(b) / denV : REAL(0);
      Basis2 B;
      hornerBasis(i, j, u, v, B);
      PatchDerivs c;
      PatchDerivs q = evalPatch(B, i, j, u, v, c);
      REAL3 n = surfaceNormal(i, j, u, v, q, c);
      STORE_XYZ_SCALAR(outNormal, pt, n)
    }
  }
}
