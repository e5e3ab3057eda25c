#version 450
// Vertex pass of the adaptive tessellator (tess_layout.h): every corner, edge point and interior
// point of the frame's layout once, numbered as core/tess_topology.cpp. A shared vertex takes its
// position from its canonical patch (the lower patch index, as SurfaceTessellator) and the
// normalised mean of the docs/math.md §5.3 normals of every patch that contains it, summed in the
// topology's order; one evaluation per vertex, so both patches of an edge reference bitwise the
// same vertex. Two indirect dispatches the layout pass sized (AdaptivePush.mode): the shared
// vertices, one invocation each, which find their edge by binary search in the layout's sorted
// first-vertex records; the interior vertices, one invocation per block of interior rows of a
// patch, evaluated row-wise as tessellate_grid.comp does (patch_rows.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = kAdaptBindingPatches) readonly buffer PatchBuf { uvec4 patchRecords[]; };
layout(std430, binding = kAdaptBindingEdges) readonly buffer EdgeBuf { uvec2 edges[]; };
layout(std430, binding = kAdaptBindingFrame) readonly buffer FrameBuf { uint frame[]; };
layout(std430, binding = kAdaptBindingRows) readonly buffer RowBuf { uint rowFirst[]; };
layout(std430, binding = kAdaptBindingVertices) writeonly buffer VertexOut { vec4 outVerts[]; };
layout(push_constant) uniform PushBlock { AdaptivePush pc; };
layout(constant_id = kSpecAdaptMode) const uint MODE = 0u;  // = pc.mode, a constant per pipeline

#include "surface_patch.glsl"
#include "tess_adaptive_grid.glsl"

const bool kAEB = ALPHA_EB != 0u;
const uint MU = BASIS_COUNT_U;
const uint MV = BASIS_COUNT_V;
const uint DU = POLY_DEGREE_U;
const uint DV = POLY_DEGREE_V;
#include "patch_rows.glsl"

// Point and unit normal of patch (a, b) of the tessellated range at local (u, v): Q_u x Q_v, and
// the full §5.3 rule (surfaceNormal) where that is degenerate or at an α-EB patch corner. The rule
// runs in a loop, not an if: on llvmpipe an if's body runs whether or not a lane takes it, a
// loop's only while some lane does.
void evalPointNormal(uint a, uint b, REAL u, REAL v, out vec3 p, out vec3 n) {
  uint i = a + pc.firstSpanU, j = b + pc.firstSpanV;
  Basis2 B;
  hornerBasis(u, v, B);
  PatchDerivs c;
  PatchDerivs q = evalPatch(B, i, j, u, v, c);
  p = vec3(q.p);
  REAL3 cr = cross(q.u, q.v);
  REAL len = length(cr);
  bool corner = ALPHA_EB != 0u && (u == REAL(0) || u == REAL(1)) && (v == REAL(0) || v == REAL(1));
  bool full = corner || degenerateCrossLength(q.u, q.v, len);
  n = full ? vec3(0) : vec3(cr / len);
  for (uint f = 0u; f < (full ? 1u : 0u); ++f) n = vec3(surfaceNormal(i, j, u, v, q, c));
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

// Point k of edge x (u-edges, then v-edges), at k/e, 0 < k < e, from the owner patch, the normal
// averaged with the patch on the other side where there is one.
void edgePoint(uint x, uint k) {
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
  REAL t = REAL(k) / REAL(e);
  REAL u = alongU ? t : fixedLocal, v = alongU ? fixedLocal : t;
  vec3 p, n0;
  evalPointNormal(a, b, u, v, p, n0);
  vec3 n = n0;
  if (shared_) n = meanNormal(n0 + normalOf(oa, ob, alongU ? t : REAL(1), alongU ? REAL(1) : t), n0, 2u);
  store(rec.y + k - 1u, a, b, u, v, p, n);
}

// Row block t of patch p: interior rows i = 1 + t R .. (R = rowsPerBlock(m), tess_adaptive_grid.glsl),
// u = i/n, v = j/m for 0 < j < m, evaluated row-wise (the patch loaded once for the block); a
// sample whose derivatives are degenerate takes the full §5.3 rule, in a loop as above.
void interiorRows(uint patchIndex, uint t) {
  uvec4 rec = patchRecords[patchIndex];
  uint n = rec.x, m = rec.y;
  uint a = patchIndex / pc.patchesV, b = patchIndex - a * pc.patchesV;
  uint mi = a + pc.firstSpanU, mj = b + pc.firstSpanV;
  loadPatchRows(mi, mj);
  uint R = rowsPerBlock(m), i0 = 1u + t * R, i1 = min(i0 + R, n);
  for (uint i = i0; i < i1; ++i) {
    REAL u = REAL(i) / REAL(n);
    setupRow(u);
    uint first = rec.z + (i - 1u) * (m - 1u);
    for (uint j = 1u; j < m; ++j) {
      REAL v = REAL(j) / REAL(m);
      REAL3 p, du, dv;
      evalSample(v, p, du, dv);
      REAL3 cr = cross(du, dv);
      REAL len = length(cr);
      bool degenerate = degenerateCrossLength(du, dv, len);
      vec3 normal = degenerate ? vec3(0) : vec3(cr / len);
      for (uint f = 0u; f < (degenerate ? 1u : 0u); ++f) {
        Basis2 B;
        hornerBasis(u, v, B);
        PatchDerivs c;
        PatchDerivs q = evalPatch(B, mi, mj, u, v, c);
        normal = vec3(surfaceNormal(mi, mj, u, v, q, c));
      }
      store(first + j - 1u, a, b, u, v, vec3(p), normal);
    }
  }
}

// The last of `count` sorted firsts that is <= k.
#define LAST_AT_MOST(result, count, FIRST, k) \
  {                                           \
    uint lo_ = 0u, hi_ = (count) - 1u;        \
    while (lo_ < hi_) {                       \
      uint mid_ = (lo_ + hi_ + 1u) / 2u;      \
      if (FIRST(mid_) <= (k)) lo_ = mid_;     \
      else hi_ = mid_ - 1u;                   \
    }                                         \
    result = lo_;                             \
  }
#define EDGE_FIRST(x) edges[x].y
#define ROW_FIRST(x) rowFirst[x]

void main() {
  uint k = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  if (MODE == kAdaptModeShared) {
    if (k >= frame[kAdaptFrameSharedCount]) return;
    if (k < cornerCount()) {
      corner(k);
      return;
    }
    uint x;
    LAST_AT_MOST(x, uEdgeCount() + vEdgeCount(), EDGE_FIRST, k)
    edgePoint(x, k - edges[x].y + 1u);
    return;
  }
  if (k >= frame[kAdaptFrameRowCount]) return;
  uint p;
  LAST_AT_MOST(p, pc.patchesU * pc.patchesV, ROW_FIRST, k)
  interiorRows(p, k - rowFirst[p]);
}
