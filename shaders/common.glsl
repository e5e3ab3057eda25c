// Shared GLSL of the evaluation kernels: precision switch, specialization constants, buffers, the
// per-point math of host/core/point_math.h (the same text core compiles as C++) and store macros.
// Compiled with REAL_IS_DOUBLE=1 for the fp64 variant (needs shaderFloat64).
#ifndef SHAPESPLINE_COMMON_GLSL
#define SHAPESPLINE_COMMON_GLSL

// PACKED_STORES=1 (the `_pk` variants, need shaderInt64): llvmpipe stores an SSBO value one scalar
// component per SIMD lane at a time, so fp32 output written as uint64 pairs of floats takes half
// the stores (the same bytes in memory). FLOAT4 is the store type of a vec4; PLANE4 that of a REAL4
// output plane (FLOAT4 when REAL is float). VERTEX: a tessellator vertex (tess_layout.h: two vec4),
// one 32-byte store when packed (one per-lane store loop instead of two).
#if defined(PACKED_STORES) && PACKED_STORES
#extension GL_ARB_gpu_shader_int64 : require
#define FLOAT4 u64vec2
#define PACK_FLOAT2(v) packUint2x32(floatBitsToUint(v))
#define TO_FLOAT4(v) u64vec2(PACK_FLOAT2((v).xy), PACK_FLOAT2((v).zw))
#define VERTEX u64vec4
#define STORE_VERTEX(buf, k, a, b) \
  buf[k] = u64vec4(PACK_FLOAT2((a).xy), PACK_FLOAT2((a).zw), PACK_FLOAT2((b).xy), PACK_FLOAT2((b).zw));
#else
#define FLOAT4 vec4
#define TO_FLOAT4(v) (v)
#define VERTEX vec4
#define STORE_VERTEX(buf, k, a, b) \
  {                                \
    buf[2u * (k)] = (a);           \
    buf[2u * (k) + 1u] = (b);      \
  }
#endif

#if defined(REAL_IS_DOUBLE) && REAL_IS_DOUBLE
#define REAL double
#define REAL3 dvec3
#define REAL4 dvec4
#define PLANE4 dvec4
#define TO_PLANE4(v) (v)
#else
#define REAL float
#define REAL3 vec3
#define REAL4 vec4
#define PLANE4 FLOAT4
#define TO_PLANE4(v) TO_FLOAT4(v)
#endif
#define SHAPESPLINE_GLSL 1
#include "layout.h"

layout(local_size_x_id = kSpecWorkgroupSize) in;
// This invocation's index over the whole dispatch: gpu::KernelSet::dispatch folds more than
// maxComputeWorkGroupCount[0] groups into y (65,535 on lavapipe: a 2048² α-EB net's vertex pass),
// so every kernel it dispatches counts through y too.
uint flatInvocation() {
  return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
}
layout(constant_id = kSpecBasisCountU) const uint BASIS_COUNT_U = 4;
layout(constant_id = kSpecPolyDegreeU) const uint POLY_DEGREE_U = 3;
layout(constant_id = kSpecBasisCountV) const uint BASIS_COUNT_V = 4;
layout(constant_id = kSpecPolyDegreeV) const uint POLY_DEGREE_V = 3;
layout(constant_id = kSpecOutputMask) const uint OUTPUT_MASK = 1;
layout(constant_id = kSpecAlphaEB) const uint ALPHA_EB = 0;
// Knot-vector kernels: NET holds homogeneous (w P, w) records of a rational B-spline (§10.8).
layout(constant_id = kSpecRational) const uint RATIONAL = 0;
layout(constant_id = kSpecKnotPatches) const uint KNOT_PATCHES = 0;
layout(constant_id = kSpecListMode) const uint LIST_MODE = 0;
layout(constant_id = kSpecSurface) const uint SURFACE = 0;

layout(std430, binding = kBindingNet) readonly buffer NetBuf { REAL4 net[]; };
layout(std430, binding = kBindingParams) readonly buffer ParamBuf { REAL params[]; };

#include "point_math.h"

// evalSpanBasis of core/span_basis.cpp on the coefficients coef[r][d] at params[coefOffset].
void evalSpanBasis(uint coefOffset, uint count, uint degree, REAL t,
                   out REAL b[kMaxBasis], out REAL d1[kMaxBasis], out REAL d2[kMaxBasis]) {
  for (uint r = 0; r < count; ++r) {
    uint c = coefOffset + r * kCoefStride;
    REAL p = params[c + degree], dp = REAL(0), ddp = REAL(0);
    for (int d = int(degree) - 1; d >= 0; --d) hornerStep(p, dp, ddp, t, params[c + uint(d)]);
    b[r] = p;
    d1[r] = dp;
    d2[r] = REAL(2) * ddp;
  }
}

// Stores value (xyz of point k) into a packed xyz plane viewed as REAL4[].
#define STORE_XYZ_SCALAR(plane, k, value)           \
  {                                                 \
    uint s_ = 3u * (k);                             \
    plane[s_ >> 2][s_ & 3u] = (value).x;            \
    plane[(s_ + 1u) >> 2][(s_ + 1u) & 3u] = (value).y; \
    plane[(s_ + 2u) >> 2][(s_ + 2u) & 3u] = (value).z; \
  }
// Four consecutive points q*4 .. q*4+3 as three stores into a REAL4 array (CONVERT = identity)
// or a PLANE4 array (STORE_XYZ4_PLANE).
#define STORE_XYZ4_AS(plane, q, v0, v1, v2, v3, CONVERT)             \
  {                                                                  \
    plane[3u * (q)] = CONVERT(REAL4((v0).xyz, (v1).x));              \
    plane[3u * (q) + 1u] = CONVERT(REAL4((v1).yz, (v2).xy));         \
    plane[3u * (q) + 2u] = CONVERT(REAL4((v2).z, (v3).xyz));         \
  }
#define STORE_XYZ4(plane, q, v0, v1, v2, v3) STORE_XYZ4_AS(plane, q, v0, v1, v2, v3, )
#define STORE_XYZ4_PLANE(plane, q, v0, v1, v2, v3) STORE_XYZ4_AS(plane, q, v0, v1, v2, v3, TO_PLANE4)

#endif  // SHAPESPLINE_COMMON_GLSL
