#version 450
// Knot-vector B-spline surfaces (docs/math.md §10.1, core/bspline.h evalBSplineSurface): point, partials
// up to order 2 with respect to the knot parameters and the unit normal (core/surface.h convention
// for plain surfaces: du x dv; degenerate -> moved 2^-12 towards the interval centre; then +z), for
// an Su x Sv grid on every non-empty interval pair (core/grid_sampler.h surfaceGridItems order) or
// a list (layout.h SAMPLES). Orders: BASIS_COUNT_U, BASIS_COUNT_V. 4 points per invocation.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "bspline.glsl"

layout(std430, binding = kBindingSamples) readonly buffer SampleBuf { ListSample samples[]; };
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

Sample evalSample(uint k) {
  int spanU, spanV, iu, iv;
  REAL x, y, lu, lv;
  if (pc.listMode != 0u) {
    ListSample s = samples[pc.firstItem + k];
    spanU = int(s.i);
    spanV = int(s.j);
    iu = int(s.intervalU);
    iv = int(s.intervalV);
    x = s.u;
    y = s.v;
    lu = s.localU;
    lv = s.localV;
  } else {
    // Row of the chunk, then row counted from the start of item firstItem (surface_eval.comp).
    uint row = k / pc.samplesV, b = k - row * pc.samplesV;
    uint g = pc.firstRow + row;
    uint item = g / pc.samplesU, a = g - item * pc.samplesU;
    uint lin = pc.firstItem + item;
    uint pu = lin / pc.itemsV, pv = lin - pu * pc.itemsV;
    uint recU = pc.intervalOffsetU + pu * kIntervalStride, recV = pc.intervalOffsetV + pv * kIntervalStride;
    gridKnotParameter(pc.knotOffsetU, recU, a, pc.samplesU, spanU, x, lu);
    gridKnotParameter(pc.knotOffsetV, recV, b, pc.samplesV, spanV, y, lv);
    iu = int(params[recU]);
    iv = int(params[recV]);
  }
  // knot_patch.glsl knotNormal's rule with one evalKnotPatch in a rolled loop, which keeps the
  // code small (a second inlined de Boor–Cox doubles llvmpipe's compile time).
  Sample o;
  [[dont_unroll]] for (uint pass = 0u; pass < 2u; ++pass) {
    if (pass == 1u) {
      knotsTowardCentre(iu, iv, lu, lv, x, y);
      spanU = iu;
      spanV = iv;
    }
    Sample s = evalKnotPatch(spanU, x, spanV, y);
    if (pass == 0u) o = s;
    if (!kWantNormal) break;
    REAL3 nn = cross(s.u, s.v);
    if (!degenerateCross(s.u, s.v, nn)) {
      o.n = normalize(nn);
      break;
    }
  }
  return o;
}

// One point at a time in a loop the compiler keeps rolled: de Boor–Cox of order up to 10 is large
// code, and four inlined copies (the uniform kernels' vec4 path) multiply llvmpipe compile time.
void main() {
  uint q = flatInvocation();
  uint total = pc.listMode != 0u ? pc.itemCount : pc.rowCount * pc.samplesV;
  uint k0 = q * kPointsPerInvocation;
  if (k0 >= total) return;
  uint n = min(kPointsPerInvocation, total - k0);
  [[dont_unroll]] for (uint e = 0; e < n; ++e) {
    Sample s = evalSample(k0 + e);
    if (kWantPoint) STORE_XYZ_SCALAR(outPoint, k0 + e, s.p)
    if (kWantDu) STORE_XYZ_SCALAR(outDu, k0 + e, s.u)
    if (kWantDv) STORE_XYZ_SCALAR(outDv, k0 + e, s.v)
    if (kWantDuu) STORE_XYZ_SCALAR(outDuu, k0 + e, s.uu)
    if (kWantDuv) STORE_XYZ_SCALAR(outDuv, k0 + e, s.uv)
    if (kWantDvv) STORE_XYZ_SCALAR(outDvv, k0 + e, s.vv)
    if (kWantNormal) STORE_XYZ_SCALAR(outNormal, k0 + e, s.n)
  }
}
