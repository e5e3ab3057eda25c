#version 450
// Grid pass of the tessellator (shaders/tess_layout.h): one invocation evaluates row a of patch p's
// (n+1) x (m+1) grid, u = a/n, v = b/m: the point and the MATH.md §5.3 unit normal of tensor
// surfaces (§1, §6) and α-EB surfaces (§5.2). Interior samples are final vertices and are written
// interleaved straight into the vertex buffer; the perimeter samples go to BOUNDARY, from where
// tessellate_pack.comp builds the shared corner and edge vertices.
// The arithmetic is surface_grid.comp's (u contraction once per row, bases by Horner from the
// coefficients in registers, α-EB weights per sample); see there for the llvmpipe reasoning.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = 2) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = 3) readonly buffer PatchBuf { uvec4 patchRecords[]; };
layout(std430, binding = 4) readonly buffer RowBuf { uvec2 rowItems[]; };
layout(std430, binding = 5) writeonly buffer VertexOut { vec4 outVerts[]; };
layout(std430, binding = 6) buffer BoundaryBuf { REAL4 boundary[]; };

layout(push_constant) uniform PushBlock { TessGridPush pc; };

#include "surface_patch.glsl"

layout(constant_id = 9) const uint UNIFORM_RATES = 0;  // layout.h kSpecUniformRates
const bool kAEB = ALPHA_EB != 0u;
const bool kUniform = UNIFORM_RATES != 0u;
const uint MU = BASIS_COUNT_U;
const uint MV = BASIS_COUNT_V;
const uint DU = POLY_DEGREE_U;
const uint DV = POLY_DEGREE_V;

// Row state shared by the sample writers and the fallback pass. With uniform rates n and m come
// from push constants, so llvmpipe sees uniform loop bounds and branch conditions.
uint gN, gM, gInteriorFirst, gBoundaryFirst, gA;
vec2 gUV0;  // global (U, V) of the patch origin

bool innerRow() { return kUniform ? pc.edgeRows == 0u : gA > 0u && gA < gN; }
bool interiorSample(uint b) { return innerRow() && b > 0u && b < gM; }
uint interiorVertex(uint b) { return gInteriorFirst + (gA - 1u) * (gM - 1u) + (b - 1u); }
uint perimeterSlot(uint b) { return gBoundaryFirst + tessPerimeterSlot(gN, gM, gA, b); }

void writeSample(uint b, REAL3 p, REAL3 n, REAL tu, REAL tv) {
  if (interiorSample(b)) {
    uint k = interiorVertex(b);
    outVerts[2u * k] = vec4(vec3(p), float(n.x));
    outVerts[2u * k + 1u] = vec4(vec2(n.yz), gUV0 + vec2(float(tu), float(tv)));
  } else {
    uint s = perimeterSlot(b);
    boundary[2u * s] = REAL4(p, 0);
    boundary[2u * s + 1u] = REAL4(n, 0);
  }
}

void writeNormal(uint b, REAL3 n) {
  if (interiorSample(b)) {
    uint k = interiorVertex(b);
    outVerts[2u * k].w = float(n.x);
    outVerts[2u * k + 1u].xy = vec2(n.yz);
  } else {
    boundary[2u * perimeterSlot(b) + 1u] = REAL4(n, 0);
  }
}

void main() {
  uint q = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (q >= pc.invocations) return;
  // This invocation's rows: a0, a0 + step, ... (rowCount of them), all of one patch.
  uint patchIndex, a0, step = 1u, rowCount = 1u;
  if (kUniform) {
    gN = pc.rateN;
    gM = pc.rateM;
    if (pc.edgeRows == 0u) {
      uint blocks = (gN - 2u) / pc.rowsPerInvocation + 1u;
      patchIndex = q / blocks;
      a0 = 1u + (q - patchIndex * blocks) * pc.rowsPerInvocation;
      rowCount = min(pc.rowsPerInvocation, gN - a0);
    } else {
      patchIndex = q;
      a0 = 0u;
      step = gN;
      rowCount = 2u;
    }
    gInteriorFirst = pc.interiorFirst + patchIndex * (gN - 1u) * (gM - 1u);
    gBoundaryFirst = patchIndex * 2u * (gN + gM);
  } else {
    uvec2 item = rowItems[q];
    uvec4 rec = patchRecords[item.x];
    patchIndex = item.x;
    a0 = item.y;
    gN = rec.x;
    gM = rec.y;
    gInteriorFirst = rec.z;
    gBoundaryFirst = rec.w;
  }
  uint pa = patchIndex / pc.patchesV;
  uint i = pa + pc.firstSpanU, j = patchIndex - pa * pc.patchesV + pc.firstSpanV;
  gUV0 = vec2(float(i), float(j));
  uint base = netBase(i, j);

  // Per-invocation data (per-lane gathers on llvmpipe: shared by all rows of the invocation).
  REAL3 P[MU][MV];
  [[unroll]] for (uint r = 0; r < MU; ++r)
    [[unroll]] for (uint s = 0; s < MV; ++s) P[r][s] = net[base + r * pc.netCols + s].xyz;
  REAL cu[MU][DU + 1u], cv[MV][DV + 1u];
  [[unroll]] for (uint r = 0; r < MU; ++r)
    [[unroll]] for (uint d = 0; d <= DU; ++d) cu[r][d] = params[kParamCoefU + r * kCoefStride + d];
  [[unroll]] for (uint s = 0; s < MV; ++s)
    [[unroll]] for (uint d = 0; d <= DV; ++d) cv[s][d] = params[kParamCoefV + s * kCoefStride + d];
  REAL3 V[4];
  REAL al[4];
  if (kAEB) loadPatchCorners(i, j, V, al);

  for (uint row = 0u; row < rowCount; ++row) {
    gA = a0 + row * step;
    // u contraction of this row: T0 = Σ_r B_r(u) P[r][.], T1 = Σ_r B_r'(u) P[r][.].
    REAL tu = REAL(gA) / REAL(gN);
    REAL3 T0[MV], T1[MV];
    [[unroll]] for (uint s = 0; s < MV; ++s) {
      T0[s] = REAL3(0);
      T1[s] = REAL3(0);
    }
    [[unroll]] for (uint r = 0; r < MU; ++r) {
      REAL w0 = cu[r][DU], dp = REAL(0);
      [[unroll]] for (int d = int(DU) - 1; d >= 0; --d) {
        dp = dp * tu + w0;
        w0 = w0 * tu + cu[r][d];
      }
      [[unroll]] for (uint s = 0; s < MV; ++s) {
        T0[s] += w0 * P[r][s];
        T1[s] += dp * P[r][s];
      }
    }
    REAL3 su = kAEB ? singularBlend(tu) : REAL3(0);
    REAL fu0 = REAL(1) - su.x, fu1 = su.x;
    bool edgeRow = !innerRow();

    // Samples whose normal needs the full §5.3 convention (degenerate crosses): the first two are
    // remembered, more make the row redo all of its normals (as surface_grid.comp).
    uint fallbackCount = 0u, fallback0 = 0u, fallback1 = 0u;
    REAL denV = REAL(gM);
    // Groups of 4 samples (independent work for the SIMD units); the last group is partial.
    for (uint b0 = 0u; b0 <= gM; b0 += 4u) {
      [[unroll]] for (uint e = 0u; e < 4u; ++e) {
        uint b = min(b0 + e, gM);
        REAL t = REAL(b) / denV;
        REAL3 p = REAL3(0), du = REAL3(0), dv = REAL3(0);
        [[unroll]] for (uint s = 0; s < MV; ++s) {
          REAL c0 = cv[s][DV], dp = REAL(0);
          [[unroll]] for (int d = int(DV) - 1; d >= 0; --d) {
            dp = dp * t + c0;
            c0 = c0 * t + cv[s][d];
          }
          p += c0 * T0[s];
          du += c0 * T1[s];
          dv += dp * T0[s];
        }
        if (kAEB) {
          // MATH.md §5.3 (evalAlphaEBPatch): Q = C + A M, Q_u = C_u + A M_u + A_u M, Q_v likewise.
          REAL3 sv = singularBlend(t);
          REAL fv0 = REAL(1) - sv.x, fv1 = sv.x;
          REAL A00, A10, A01;
          REAL3 L00, L10, L01;
          cornerBlend(fu0, fu1, fv0, fv1, al, V, A00, L00);
          cornerBlend(-su.y, su.y, fv0, fv1, al, V, A10, L10);
          cornerBlend(fu0, fu1, -sv.y, sv.y, al, V, A01, L01);
          REAL3 M = L00 - p, Mu = L10 - du, Mv = L01 - dv;
          du = du + A00 * Mu + A10 * M;
          dv = dv + A00 * Mv + A01 * M;
          p = p + A00 * M;
        }
        REAL3 n = cross(du, dv);
        if (b0 + e <= gM) {
          // §5.3: an α = 1 patch corner takes the vertex's diagonal limit (cheap: a few loads), a
          // degenerate cross the full convention below (rare).
          bool degenerate = degenerateCross(du, dv, n);
          if (kAEB && edgeRow && (b == 0u || b == gM)) {
            REAL3 nc;
            if (alphaEBVertexNormal(i, j, gA == 0u ? 0u : 1u, b == 0u ? 0u : 1u, nc)) {
              n = nc;
              degenerate = false;
            }
          }
          if (degenerate) {  // redone below
            if (fallbackCount == 0u) fallback0 = b;
            else fallback1 = b;
            ++fallbackCount;
          }
          writeSample(b, p, normalize(n), tu, t);
        }
      }
    }

    // The fallback normals, as surface_eval.comp computes them. A loop, not an if: on llvmpipe a
    // loop body runs only while some lane still has points left.
    uint todo = fallbackCount <= 2u ? fallbackCount : gM + 1u;
    for (uint f = 0u; f < todo; ++f) {
      uint b = fallbackCount <= 2u ? (f == 0u ? fallback0 : fallback1) : f;
      REAL v = REAL(b) / denV;
      Basis2 B;
      hornerBasis(tu, v, B);
      PatchDerivs c;
      PatchDerivs qd = evalPatch(B, i, j, tu, v, c);
      writeNormal(b, surfaceNormal(i, j, tu, v, qd, c));
    }
  }
}
