#version 450
// α-EB vertex pass (docs/math.md §4.2, §5.2): node = C(0) (curve) or C_ij(0,0) (surface) from the extended
// polygon/net and the basis coefficients, and V = P + ((1-α)/α)(P - node), one invocation per
// vertex. Runs on the GPU so that a λ or α change re-uploads only PARAMS, never the net.
// B_r(0) is the constant coefficient coef[r][0] (Horner at t = 0 returns it exactly). b_3(0) = 0 for
// every Xu-Wang degree, so only P_{j-1..j+1} enter: reading the fourth point would run one past the
// extended net at the last vertex of an open direction (as in core/curve.cpp, core/surface.cpp).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(std430, binding = kBindingVerts) writeonly buffer VertBuf { REAL4 verts[]; };
layout(push_constant) uniform PushBlock { VertexPush pc; };

const uint kNodePoints = 3u;

void main() {
  uint idx = flatInvocation();
  uint count = pc.rows * pc.cols;
  if (idx >= count) return;
  uint i = idx / pc.cols, j = idx - i * pc.cols;
  REAL3 node = REAL3(0), P;
  if (SURFACE != 0u) {
    // Same order as evalTensorPatch at (0,0): v first, then u.
    for (uint r = 0; r < kNodePoints; ++r) {
      REAL3 s0 = REAL3(0);
      for (uint s = 0; s < kNodePoints; ++s)
        s0 += params[kParamCoefV + s * kCoefStride] * net[(i + r) * pc.netCols + j + s].xyz;
      node += params[kParamCoefU + r * kCoefStride] * s0;
    }
    P = net[(i + 1u) * pc.netCols + j + 1u].xyz;
  } else {
    for (uint r = 0; r < kNodePoints; ++r) node += params[kParamCoefU + r * kCoefStride] * net[i + r].xyz;
    P = net[i + 1u].xyz;
  }
  REAL alpha = params[pc.alphaOffset + idx];
  verts[idx] = REAL4(alphaEBVertex(P, node, alpha), 0);
  verts[count + idx] = REAL4(node, 0);
}
