// Shared GLSL of the evaluation kernels: precision switch, specialization constants, buffers and
// the raw kernels mirrored from host/core (same names, same operation order as the fp64 C++).
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

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint BASIS_COUNT_U = 4;
layout(constant_id = 2) const uint POLY_DEGREE_U = 3;
layout(constant_id = 3) const uint BASIS_COUNT_V = 4;
layout(constant_id = 4) const uint POLY_DEGREE_V = 3;
layout(constant_id = 5) const uint OUTPUT_MASK = 1;
layout(constant_id = 6) const uint ALPHA_EB = 0;
layout(constant_id = 7) const uint LIST_MODE = 0;
layout(constant_id = 8) const uint SURFACE = 0;

layout(std430, binding = 0) readonly buffer NetBuf { REAL4 net[]; };
layout(std430, binding = 1) readonly buffer ParamBuf { REAL params[]; };

// core/span_basis.cpp evalSpanBasis: simultaneous Horner for p, p', p''/2 in the local t.
// Coefficients coef[r][d] of the basis start at params[coefOffset].
void evalSpanBasis(uint coefOffset, uint count, uint degree, REAL t,
                   out REAL b[kMaxBasis], out REAL d1[kMaxBasis], out REAL d2[kMaxBasis]) {
  for (uint r = 0; r < count; ++r) {
    uint c = coefOffset + r * kCoefStride;
    REAL p = params[c + degree], dp = REAL(0), ddp = REAL(0);
    for (int d = int(degree) - 1; d >= 0; --d) {
      ddp = ddp * t + dp;
      dp = dp * t + p;
      p = p * t + params[c + uint(d)];
    }
    b[r] = p;
    d1[r] = dp;
    d2[r] = REAL(2) * ddp;
  }
}

// core/singular_blend.cpp singularBlend: S, S', S'' (docs/math.md §3). The three pieces are all
// evaluated and one selected (same arithmetic as the C++): llvmpipe runs every side of a
// per-lane branch anyway, and a select saves the mask bookkeeping.
REAL3 singularBlend(REAL t) {
  REAL3 lo = REAL3(REAL(4.5) * t * t * t, REAL(13.5) * t * t, REAL(27) * t);
  REAL3 mid = REAL3(REAL(0.5) + t * (REAL(-4.5) + t * (REAL(13.5) - REAL(9) * t)),
                    REAL(-4.5) + t * (REAL(27) - REAL(27) * t), REAL(27) - REAL(54) * t);
  REAL u = REAL(1) - t;
  REAL3 hi = REAL3(REAL(1) - REAL(4.5) * u * u * u, REAL(13.5) * u * u, REAL(-27) * u);
  return mix(mix(hi, mid, bvec3(t <= REAL(2.0 / 3.0))), lo, bvec3(t <= REAL(1.0 / 3.0)));
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
