// Binding numbers, specialization-constant ids, push-constant blocks and SSBO element structs shared
// by the compute shaders and host/gpu. One source compiled as GLSL (SHAPESPLINE_GLSL, defined by
// common.glsl) and as C++ (the host mirrors below, with static_asserts on every size and offset).
//
// Only scalars and 4-vectors appear in buffer structs: std430 aligns vec3 to 16 bytes while glm's is
// 12, so a vec3 member would silently shift the host view.
//
// ---- Buffers (descriptor set 0) -----------------------------------------------------------------
//  NET     (REAL4)  patch net / span point list of core::Surface / core::Curve (xyz, w unused): patch
//                   (i,j) reads rows i + netOffsetU .. + m_u - 1, columns j + netOffsetV .. + m_v - 1.
//                   Uploaded once per model; only updateControlPoint() writes into it afterwards.
//  PARAMS  (REAL)   small parameter block: u basis coefficients at kParamCoefU (coef[r][d] at
//                   r*11 + d), v basis at kParamCoefV, α values at alphaOffset (row-major R x C),
//                   span-knot reciprocals 1/h_s at invHOffset (curves with span knots). λ/μ/α
//                   changes rewrite only this buffer.
//  VERTS   (REAL4)  α-EB vertex data written by alpha_eb_vertices.comp: V_ij at i*cols + j and
//                   node_ij at rows*cols + i*cols + j (docs/math.md §4.2, §5.2).
//  TABLE   (REAL)   basis table (basis_table.comp): entry of sample a of a direction at
//                   tableOffset + a*3*m + d*m + r = B_r^(d)(t_a), d = 0,1,2.
//  SAMPLES (ListSample) list mode: (span/patch i, patch j, local u, local v) per sample.
//                   Knot-vector B-splines (bspline_*_eval.comp): (i, j) = the knot spans, (u, v) =
//                   the knot parameters, and (intervalU, intervalV, localU, localV) = the knot
//                   interval pair and local parameters the sample was given in (normal shifts).
//  Knot-vector B-splines keep in PARAMS (from kParamHeader on): the knots of each direction and
//  one interval record per non-empty knot interval (kIntervalStride REALs: span index j, span
//  used at local t = 1 and the knot parameter there, both as core/bspline.h findKnotSpan picks
//  them for t_j + 1*(t_{j+1}-t_j)); NET is the plain control net (rows x cols, row-major).
//  Surfaces also keep one knot patch record per non-empty interval (kKnotPatchStride REALs: the
//  first control point index j - order + 1, t_j, h = t_{j+1} - t_j, then the interval's basis
//  in its local parameter as coef[r][d] at 3 + r*11 + d, core/bspline.h knotIntervalBasis), the
//  u records from params[kParamKnotPatchU] on, the v records from params[kParamKnotPatchV] (the
//  coefficient area of the header, which knot-vector models do not use otherwise): with the
//  specialization constant kSpecKnotPatches the uniform patch code (surface_patch.glsl,
//  patch_rows.glsl) evaluates interval pair (i, j) as patch (i, j), derivatives in the local
//  parameters.
//  OUTPUT  (REAL4)  one plane per Field (core/sample_grid.h), bound at kBindingOutput + field:
//                   tightly packed xyz, point k at REAL offsets 3k..3k+2 of the plane; the plane is
//                   addressed as REAL4 so that one invocation stores 4 consecutive points as three
//                   vec4 (x0y0z0x1 y1z1x2y2 z2x3y3z3). Point index inside a chunk: grid =
//                   item * Su*Sv + a*Sv + b (item = span or patch, row-major u outer) minus
//                   firstRow * Sv (a chunk of rows of one item); list = sample.
#ifndef SHAPESPLINE_SHADERS_LAYOUT_H
#define SHAPESPLINE_SHADERS_LAYOUT_H

#ifdef SHAPESPLINE_GLSL
#define uint32_t uint
#define SS_CONST(type, name, value) const type name = value
#else
#include <cstddef>
#include <cstdint>
namespace shapespline::gpu::layout {
#define SS_CONST(type, name, value) inline constexpr type name = value
#endif

// Bindings.
SS_CONST(uint32_t, kBindingNet, 0u);
SS_CONST(uint32_t, kBindingParams, 1u);
SS_CONST(uint32_t, kBindingVerts, 2u);
SS_CONST(uint32_t, kBindingTable, 3u);
SS_CONST(uint32_t, kBindingSamples, 4u);
SS_CONST(uint32_t, kBindingOutput, 5u);  // + Field index (Point 0, D1 1, D2 2, Du 3, ..., Normal 8)

// Specialization-constant ids.
SS_CONST(uint32_t, kSpecWorkgroupSize, 0u);
SS_CONST(uint32_t, kSpecBasisCountU, 1u);   // m of the u (or curve) basis
SS_CONST(uint32_t, kSpecPolyDegreeU, 2u);
SS_CONST(uint32_t, kSpecBasisCountV, 3u);
SS_CONST(uint32_t, kSpecPolyDegreeV, 4u);
SS_CONST(uint32_t, kSpecOutputMask, 5u);    // fieldBit(Field) bits (core/sample_grid.h)
SS_CONST(uint32_t, kSpecAlphaEB, 6u);       // 1: α-EB construction, 0: plain local family
SS_CONST(uint32_t, kSpecListMode, 7u);      // 1: SAMPLES list, 0: per-item grid from TABLE
SS_CONST(uint32_t, kSpecSurface, 8u);       // alpha_eb_vertices: 1 surface net, 0 curve polygon
SS_CONST(uint32_t, kSpecRunLength, 9u);     // surface_grid / curve_grid: samples per invocation
SS_CONST(uint32_t, kSpecUniformRates, 10u); // tessellate_grid: 1 when every patch has the same rates
SS_CONST(uint32_t, kSpecRational, 12u);     // bspline_*: 1 when NET holds homogeneous (w P, w) records
SS_CONST(uint32_t, kSpecKnotPatches, 13u);  // patch kernels: 1 when patch (i, j) is knot interval pair (i, j)
// tess_layout.h kTessSpecListSources is 11: ids are unique across both headers (kernels.cpp checks).

// Field indices (must equal core/sample_grid.h Field).
SS_CONST(uint32_t, kFieldPoint, 0u);
SS_CONST(uint32_t, kFieldD1, 1u);
SS_CONST(uint32_t, kFieldD2, 2u);
SS_CONST(uint32_t, kFieldDu, 3u);
SS_CONST(uint32_t, kFieldDv, 4u);
SS_CONST(uint32_t, kFieldDuu, 5u);
SS_CONST(uint32_t, kFieldDuv, 6u);
SS_CONST(uint32_t, kFieldDvv, 7u);
SS_CONST(uint32_t, kFieldNormal, 8u);

// PARAMS block layout.
SS_CONST(uint32_t, kCoefStride, 11u);        // kMaxPolyDegree + 1
SS_CONST(uint32_t, kMaxBasis, 10u);          // kMaxBasisCount
SS_CONST(uint32_t, kParamCoefU, 0u);
SS_CONST(uint32_t, kParamCoefV, 110u);       // kMaxBasis * kCoefStride
SS_CONST(uint32_t, kParamHeader, 220u);      // first free entry (α, 1/h)
SS_CONST(uint32_t, kNoOffset, 0xffffffffu);

SS_CONST(uint32_t, kIntervalStride, 4u);     // knot-vector interval record (see the header)
SS_CONST(uint32_t, kKnotPatchStride, 113u);  // knot patch record: 3 + kMaxBasis * kCoefStride
SS_CONST(uint32_t, kKnotPatchCoef, 3u);      // first coefficient of a knot patch record
SS_CONST(uint32_t, kParamKnotPatchU, 0u);    // knot-vector surfaces: offset of the u records
SS_CONST(uint32_t, kParamKnotPatchV, 1u);    // ... and of the v records

SS_CONST(uint32_t, kPointsPerInvocation, 4u);

#ifdef SHAPESPLINE_GLSL
#define SS_UINT uint
#else
#define SS_UINT uint32_t
#endif

// Push constants of curve_eval / surface_eval (curves: the v quantities are 1 / 0).
struct EvalPush {
  SS_UINT firstItem;     // grid: first span/patch of this chunk (0-based in the model's item list);
                         // list: first sample of this chunk
  SS_UINT itemCount;     // grid: spans/patches in this chunk; list: samples in this chunk
  SS_UINT itemsV;        // patches per row of the patch range (curves: 1)
  SS_UINT samplesU;      // grid samples per span / per patch along u
  SS_UINT samplesV;      // grid samples per patch along v (curves: 1)
  SS_UINT firstSpanU;    // model index of item row 0 (docs/math.md §1: c for open plain curves)
  SS_UINT firstSpanV;
  SS_UINT netCols;       // columns of NET (curves: 1 unused)
  SS_UINT netOffsetU;    // patch i reads NET row i + netOffsetU (span point offset for curves)
  SS_UINT netOffsetV;
  SS_UINT rows;          // α-EB: real vertex counts (α and V index wrap); curves: rows = N
  SS_UINT cols;
  SS_UINT alphaOffset;   // PARAMS index of α_00
  SS_UINT invHOffset;    // PARAMS index of 1/h of the first span, or kNoOffset
  SS_UINT tableOffsetV;  // TABLE index of the v table (u table at 0)
  // Grid: the chunk is rows [firstRow, firstRow + rowCount) counted from the first row of item
  // firstItem (a row: the Sv samples of one u sample of a patch, or one sample of a span), so an
  // item larger than a chunk goes in row ranges; whole items: firstRow 0, rowCount itemCount * Su.
  SS_UINT firstRow;
  SS_UINT rowCount;
  SS_UINT pad0, pad1, pad2;
};

// Push constants of bspline_curve_eval / bspline_surface_eval and their grid paths
// bspline_curve_grid / bspline_surface_grid (knot-vector B-splines, docs/math.md §10.1). The first
// five fields sit where EvalPush has them.
struct KnotEvalPush {
  SS_UINT firstItem;        // grid: first item (non-empty interval / interval pair); list: first sample
  SS_UINT itemCount;        // grid: items in this chunk; list: samples in this chunk
  SS_UINT itemsV;           // non-empty v intervals (surfaces; curves 1)
  SS_UINT samplesU;
  SS_UINT samplesV;
  SS_UINT netCols;          // control points per row (surfaces; curves 1)
  SS_UINT knotOffsetU;      // PARAMS index of t_0 of the u (curve) knot vector
  SS_UINT knotOffsetV;
  SS_UINT intervalOffsetU;  // PARAMS index of the first interval record of u
  SS_UINT intervalOffsetV;
  SS_UINT listMode;         // 1: SAMPLES list (a push constant here, so grid and list share a pipeline)
  SS_UINT firstRow;         // grid: row range of the chunk, as EvalPush
  SS_UINT rowCount;
  SS_UINT tableOffsetV;     // bspline_surface_grid: TABLE index of the v direction's entries
  SS_UINT pad3, pad4;
};

// Push constants of alpha_eb_vertices.
struct VertexPush {
  SS_UINT rows;          // real vertices along u (curves: N)
  SS_UINT cols;          // along v (curves: 1)
  SS_UINT netCols;       // columns of the extended net (curves: 1)
  SS_UINT alphaOffset;   // PARAMS index of α_00
};

// Push constants of basis_table.
struct TablePush {
  SS_UINT sampleCount;   // N parameter values t_a = a/(N-1) (N = 1: t = 0), or list count
  SS_UINT listMode;      // 1: parameters from SAMPLES[a].u instead of the uniform grid
  SS_UINT coefOffset;    // PARAMS index of the basis coefficients
  SS_UINT tableOffset;   // TABLE index of the first entry written
};

// One SAMPLES entry (see the header): intervalU/V and localU/V carry data for knot-vector
// B-spline surfaces only (0 elsewhere).
#ifdef SHAPESPLINE_GLSL
struct ListSample {
  uint i;
  uint j;
  uint intervalU;
  uint intervalV;
  REAL u;
  REAL v;
  REAL localU;
  REAL localV;
};
#else
// Host mirrors of ListSample for REAL = float and REAL = double.
struct ListSampleF {
  uint32_t i, j, intervalU, intervalV;
  float u, v, localU, localV;
};
struct ListSampleD {
  uint32_t i, j, intervalU, intervalV;
  double u, v, localU, localV;
};
static_assert(sizeof(EvalPush) == 80 && offsetof(EvalPush, tableOffsetV) == 56 && offsetof(EvalPush, rowCount) == 64);
static_assert(sizeof(KnotEvalPush) == 64 && offsetof(KnotEvalPush, samplesV) == offsetof(EvalPush, samplesV) &&
              offsetof(KnotEvalPush, itemsV) == offsetof(EvalPush, itemsV));
static_assert(sizeof(VertexPush) == 16 && offsetof(VertexPush, alphaOffset) == 12);
static_assert(sizeof(TablePush) == 16 && offsetof(TablePush, tableOffset) == 12);
static_assert(sizeof(KnotEvalPush) == 64 && offsetof(KnotEvalPush, listMode) == 40 && offsetof(KnotEvalPush, rowCount) == 48);
static_assert(sizeof(ListSampleF) == 32 && offsetof(ListSampleF, intervalU) == 8 && offsetof(ListSampleF, u) == 16 &&
              offsetof(ListSampleF, localU) == 24);
static_assert(sizeof(ListSampleD) == 48 && offsetof(ListSampleD, intervalU) == 8 && offsetof(ListSampleD, u) == 16 &&
              offsetof(ListSampleD, v) == 24 && offsetof(ListSampleD, localU) == 32 && offsetof(ListSampleD, localV) == 40);
static_assert(kParamCoefV == kMaxBasis * kCoefStride && kParamHeader == 2 * kMaxBasis * kCoefStride);
static_assert(kKnotPatchStride == kKnotPatchCoef + kMaxBasis * kCoefStride);

}  // namespace shapespline::gpu::layout
#endif

#undef SS_UINT
#undef SS_CONST
#endif  // SHAPESPLINE_SHADERS_LAYOUT_H
