#version 450
// Grid pass of the tessellator (shaders/tess_layout.h): one invocation evaluates one or more rows a
// of patch p's (n+1) x (m+1) grid, u = a/n, v = b/m: the point and the docs/math.md §5.3 unit normal of tensor
// surfaces (§1, §6) and α-EB surfaces (§5.2). Interior samples are final vertices and are written
// interleaved straight into the vertex buffer; the perimeter samples go to BOUNDARY, from where
// tessellate_pack.comp builds the shared corner and edge vertices.
// The arithmetic is surface_grid.comp's (u contraction once per row, bases by Horner from the
// coefficients in registers, α-EB weights per sample); see there for the llvmpipe reasoning.
// variant: packed-stores (vertices stored as uint64 pairs of floats; common.glsl)
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = kTessGridBindingPatches) readonly buffer PatchBuf { uvec4 patchRecords[]; };
layout(std430, binding = kTessGridBindingRows) readonly buffer RowBuf { uvec2 rowItems[]; };
layout(std430, binding = kTessGridBindingVertices) writeonly buffer VertexOut { VERTEX outVerts[]; };
// A perimeter sample is (p, 0, n, 0): in the packed fp32 variant one 32-byte store, like a vertex.
#if defined(PACKED_STORES) && PACKED_STORES && !(defined(REAL_IS_DOUBLE) && REAL_IS_DOUBLE)
layout(std430, binding = kTessGridBindingBoundary) writeonly buffer BoundaryBuf { VERTEX boundary[]; };
#define STORE_PERIMETER(s, p, n) STORE_VERTEX(boundary, s, vec4(p, 0), vec4(n, 0))
#else
layout(std430, binding = kTessGridBindingBoundary) writeonly buffer BoundaryBuf { REAL4 boundary[]; };
#define STORE_PERIMETER(s, p, n)        \
  {                                     \
    boundary[2u * (s)] = REAL4(p, 0);   \
    boundary[2u * (s) + 1u] = REAL4(n, 0); \
  }
#endif

layout(push_constant) uniform PushBlock { TessGridPush pc; };

#include "surface_patch.glsl"

layout(constant_id = kSpecUniformRates) const uint UNIFORM_RATES = 0;
const bool kAEB = ALPHA_EB != 0u;
const bool kUniform = UNIFORM_RATES != 0u;
const uint MU = BASIS_COUNT_U;
const uint MV = BASIS_COUNT_V;
const uint DU = POLY_DEGREE_U;
const uint DV = POLY_DEGREE_V;

// Row state shared by the sample writers and the fallback pass. With uniform rates n and m come
// from push constants, so llvmpipe sees uniform loop bounds and branch conditions.
uint gN, gM, gInteriorFirst, gBoundaryFirst, gA;
uint gI, gJ;  // the model patch

bool innerRow() { return kUniform ? pc.edgeRows == 0u : gA > 0u && gA < gN; }
bool interiorSample(uint b) { return innerRow() && b > 0u && b < gM; }
uint interiorVertex(uint b) { return gInteriorFirst + (gA - 1u) * (gM - 1u) + (b - 1u); }
uint perimeterSlot(uint b) { return gBoundaryFirst + tessPerimeterSlot(gN, gM, gA, b); }

void writeInterior(uint b, REAL3 p, REAL3 n, REAL tu, REAL tv) {
  uint k = interiorVertex(b);
  STORE_VERTEX(outVerts, k, vec4(vec3(p), float(n.x)), vec4(vec2(n.yz), patchParameter(gI, gJ, tu, tv)))
}

void writePerimeter(uint b, REAL3 p, REAL3 n) {
  uint s = perimeterSlot(b);
  STORE_PERIMETER(s, p, n)
}


#include "patch_rows.glsl"

void main() {
  uint q = flatInvocation();
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
  gI = i;
  gJ = j;
  loadPatchRows(i, j);
  REAL denV = REAL(gM);
  for (uint row = 0u; row < rowCount; ++row) {
    gA = a0 + row * step;
    REAL tu = REAL(gA) / REAL(gN);
    setupRow(tu);
    Fallbacks fallbacks = noFallbacks();

    // Interior samples b = 1 .. m-1 of an inner row (none for rows 0 and n), in groups of 4; the
    // last group repeats sample m-1 (the same value stored twice) instead of branching.
    uint interiorEnd = innerRow() ? gM : 1u;
    for (uint b0 = 1u; b0 < interiorEnd; b0 += 4u) {
      [[unroll]] for (uint e = 0u; e < 4u; ++e) {
        uint b = min(b0 + e, gM - 1u);
        REAL t = REAL(b) / denV;
        REAL3 p, du, dv;
        evalSample(t, p, du, dv);
        REAL3 n = cross(du, dv);
        REAL len = length(n);
        noteFallback(degenerateCrossLength(du, dv, len), b, fallbacks);
        writeInterior(b, p, n / len, tu, t);
      }
    }
    // Perimeter samples: b = 0 and m of an inner row, every b of rows 0 and n.
    uint perimeterCount = innerRow() ? 2u : gM + 1u;
    for (uint k = 0u; k < perimeterCount; ++k) {
      uint b = innerRow() ? k * gM : k;
      REAL t = REAL(b) / denV;
      REAL3 p, du, dv;
      evalSample(t, p, du, dv);
      REAL3 n = cross(du, dv);
      REAL len = length(n);
      noteFallback(degenerateCrossLength(du, dv, len), b, fallbacks);
      writePerimeter(b, p, n / len);
    }

    // The fallback normals, as surface_eval.comp computes them, overwriting those stored above. A
    // loop, not an if: on llvmpipe a loop body runs only while some lane still has points left.
    uint todo = fallbackCount(fallbacks, gM + 1u);
    for (uint f = 0u; f < todo; ++f) {
      uint b = fallbackSample(fallbacks, f, 0u);
      REAL v = REAL(b) / denV;
      REAL3 n = fullNormalAt(i, j, tu, v);
      // The whole sample again, point from the same arithmetic as above (a packed vertex has no
      // normal-only store); only in this rare loop, so the branch costs the sample loops nothing.
      REAL3 p, du, dv;
      evalSample(v, p, du, dv);
      if (interiorSample(b)) {
        writeInterior(b, p, n, tu, v);
      } else {
        writePerimeter(b, p, n);
      }
    }
  }
}
