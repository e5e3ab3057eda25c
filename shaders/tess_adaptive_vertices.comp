#version 450
// Vertex pass of the adaptive tessellator (tess_layout.h): every corner, edge point and interior
// point of the frame's layout once, numbered as core/tess_topology.cpp. A shared vertex takes its
// position from its canonical patch (the lower patch index, as SurfaceTessellator) and the
// normalised mean of the docs/math.md §5.3 normals of every patch that contains it, summed in the
// topology's order; one evaluation per vertex, so both patches of an edge reference bitwise the
// same vertex. Dispatches (AdaptivePush.mode): corners, one invocation each; edges, one workgroup
// each; interiors, one workgroup per patch.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = kAdaptBindingPatches) readonly buffer PatchBuf { uvec4 patchRecords[]; };
layout(std430, binding = kAdaptBindingEdges) readonly buffer EdgeBuf { uvec2 edges[]; };
layout(std430, binding = kAdaptBindingVertices) writeonly buffer VertexOut { vec4 outVerts[]; };
layout(push_constant) uniform PushBlock { AdaptivePush pc; };

#include "surface_patch.glsl"
#include "tess_adaptive_grid.glsl"

// Point and unit normal of patch (a, b) of the tessellated range at local (u, v).
void evalPointNormal(uint a, uint b, REAL u, REAL v, out vec3 p, out vec3 n) {
  uint i = a + pc.firstSpanU, j = b + pc.firstSpanV;
  Basis2 B;
  hornerBasis(u, v, B);
  PatchDerivs c;
  PatchDerivs q = evalPatch(B, i, j, u, v, c);
  p = vec3(q.p);
  n = vec3(surfaceNormal(i, j, u, v, q, c));
}

vec3 normalOf(uint a, uint b, REAL u, REAL v) {
  vec3 p, n;
  evalPointNormal(a, b, u, v, p, n);
  return n;
}

// tessellate_pack.comp's mean: opposite patch normals (a fold) cancel, then the canonical one.
vec3 meanNormal(vec3 sum, vec3 canonical, uint samples) {
  float len = length(sum);
  return len > 1e-6 * float(samples) ? sum / len : canonical;
}

void store(uint k, uint a, uint b, REAL u, REAL v, vec3 p, vec3 n) {
  vec2 uv = vec2(float(a + pc.firstSpanU) + float(u), float(b + pc.firstSpanV) + float(v));
  outVerts[2u * k] = vec4(p, n.x);
  outVerts[2u * k + 1u] = vec4(n.yz, uv);
}

// The patch and local coordinate that own patch-grid boundary `boundary` (the lower patch index).
void owner(uint boundary, uint patches, out uint patchIndex, out REAL local) {
  patchIndex = min(boundary, patches - 1u);
  local = boundary == patchIndex ? REAL(0) : REAL(1);
}

void corner(uint k) {
  uint BV = boundariesV();
  uint ca = k / BV, cb = k - ca * BV;
  uint a0, b0;
  REAL u0, v0;
  owner(ca, pc.patchesU, a0, u0);
  owner(cb, pc.patchesV, b0, v0);
  vec3 p, n0;
  evalPointNormal(a0, b0, u0, v0, p, n0);
  vec3 sum = n0;
  uint samples = 1u;
  // The other patches with this corner, (ca-1|ca) x (cb-1|cb) wrapped, in the topology's order.
  for (int da = -1; da <= 0; ++da)
    for (int db = -1; db <= 0; ++db) {
      int a = int(ca) + da, b = int(cb) + db;
      if (pc.closedU != 0u) a = (a + int(pc.patchesU)) % int(pc.patchesU);
      if (pc.closedV != 0u) b = (b + int(pc.patchesV)) % int(pc.patchesV);
      if (a < 0 || a >= int(pc.patchesU) || b < 0 || b >= int(pc.patchesV)) continue;
      REAL u = (uint(a) == ca % pc.patchesU && ca < pc.patchesU) ? REAL(0) : REAL(1);
      REAL v = (uint(b) == cb % pc.patchesV && cb < pc.patchesV) ? REAL(0) : REAL(1);
      if (uint(a) == a0 && uint(b) == b0 && u == u0 && v == v0) continue;
      sum += normalOf(uint(a), uint(b), u, v);
      ++samples;
    }
  store(k, a0, b0, u0, v0, p, meanNormal(sum, n0, samples));
}

// Edge x (u-edges, then v-edges): its points k/e, 0 < k < e, from the owner patch, the normal
// averaged with the patch on the other side where there is one.
void edge(uint x) {
  uvec2 rec = edges[x];
  uint e = rec.x;
  uint eu = uEdgeCount();
  bool alongU = x < eu;
  uint a, b, oa, ob;
  REAL fixedLocal;
  bool shared_;
  if (alongU) {
    uint BV = boundariesV();
    a = x / BV;
    uint bb = x - a * BV;
    owner(bb, pc.patchesV, b, fixedLocal);
    shared_ = (bb > 0u && bb < pc.patchesV) || pc.closedV != 0u;
    oa = a;
    ob = (bb + pc.patchesV - 1u) % pc.patchesV;
  } else {
    uint y = x - eu;
    uint aa = y / pc.patchesV;
    b = y - aa * pc.patchesV;
    owner(aa, pc.patchesU, a, fixedLocal);
    shared_ = (aa > 0u && aa < pc.patchesU) || pc.closedU != 0u;
    oa = (aa + pc.patchesU - 1u) % pc.patchesU;
    ob = b;
  }
  for (uint k = 1u + gl_LocalInvocationID.x; k < e; k += gl_WorkGroupSize.x) {
    REAL t = REAL(k) / REAL(e);
    REAL u = alongU ? t : fixedLocal, v = alongU ? fixedLocal : t;
    vec3 p, n0;
    evalPointNormal(a, b, u, v, p, n0);
    vec3 n = n0;
    if (shared_) {
      n = meanNormal(n0 + normalOf(oa, ob, alongU ? t : REAL(1), alongU ? REAL(1) : t), n0, 2u);
    }
    store(rec.y + k - 1u, a, b, u, v, p, n);
  }
}

void interior(uint patchIndex) {
  uvec4 rec = patchRecords[patchIndex];
  uint n = rec.x, m = rec.y;
  uint a = patchIndex / pc.patchesV, b = patchIndex - a * pc.patchesV;
  uint count = (n - 1u) * (m - 1u);
  for (uint q = gl_LocalInvocationID.x; q < count; q += gl_WorkGroupSize.x) {
    uint i = 1u + q / (m - 1u), j = 1u + q % (m - 1u);
    REAL u = REAL(i) / REAL(n), v = REAL(j) / REAL(m);
    vec3 p, nn;
    evalPointNormal(a, b, u, v, p, nn);
    store(rec.z + q, a, b, u, v, p, nn);
  }
}

void main() {
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (pc.mode == kAdaptModeCorners) {
    uint k = group * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
    if (k < cornerCount()) corner(k);
  } else if (pc.mode == kAdaptModeEdges) {
    if (group < uEdgeCount() + vEdgeCount()) edge(group);
  } else if (group < pc.patchesU * pc.patchesV) {
    interior(group);
  }
}
