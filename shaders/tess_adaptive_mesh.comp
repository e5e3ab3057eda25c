#version 450
// Mesh pass of the adaptive tessellator (tess_layout.h): every corner, edge point and interior
// point of the frame's layout once, numbered as core/tess_topology.cpp, and the triangles
// (tess_adaptive_triangles.glsl). A shared vertex takes its position from its canonical patch
// (the lower patch index, as SurfaceTessellator) and the normalised mean of the docs/math.md §5.3
// normals of every patch that contains it, summed in the topology's order; one evaluation per
// vertex, so both patches of an edge reference bitwise the same vertex. Dispatches
// (AdaptivePush.mode, one pipeline each): corners, one invocation each; u-edges and v-edges, one
// invocation per edge, its points evaluated along the edge with each patch loaded once, then the
// transition rings of the patch sides along it; interior rows, an indirect dispatch the layout
// pass sized, one invocation per block of interior rows of a patch (found by binary search in
// ROWS), evaluated row-wise as tessellate_grid.comp does (patch_rows.glsl), then the quads between
// those rows.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "tess_layout.h"

layout(std430, binding = kBindingVerts) readonly buffer VertBuf { REAL4 verts[]; };
layout(std430, binding = kAdaptBindingPatches) readonly buffer PatchBuf { uvec4 patchRecords[]; };
layout(std430, binding = kAdaptBindingEdges) readonly buffer EdgeBuf { uvec2 edges[]; };
layout(std430, binding = kAdaptBindingFrame) readonly buffer FrameBuf { uint frame[]; };
layout(std430, binding = kAdaptBindingRows) readonly buffer RowBuf { uint rowFirst[]; };
layout(std430, binding = kAdaptBindingQuads) readonly buffer QuadBuf { uint quadFirst[]; };
layout(std430, binding = kAdaptBindingIndices) writeonly buffer IndexOut { uint outIndices[]; };
// Not writeonly: an edge invocation parks the neighbour's normals in its own vertices first.
layout(std430, binding = kAdaptBindingVertices) buffer VertexOut { vec4 outVerts[]; };
layout(push_constant) uniform PushBlock { AdaptivePush pc; };
layout(constant_id = kSpecAdaptMode) const uint MODE = 0u;  // = pc.mode, a constant per pipeline

#include "surface_patch.glsl"
#include "tess_adaptive_grid.glsl"
#include "tess_adaptive_triangles.glsl"

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
  hornerBasis(i, j, u, v, B);
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
  vec2 uv = patchParameter(a + pc.firstSpanU, b + pc.firstSpanV, u, v);
  outVerts[2u * k] = vec4(p, n.x);
  outVerts[2u * k + 1u] = vec4(n.yz, uv);
}

// Replaces the normal of vertex k.
void storeNormal(uint k, vec3 n) {
  outVerts[2u * k].w = n.x;
  outVerts[2u * k + 1u].xy = n.yz;
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

// Column-wise evaluation (v = const, u varies), the transpose of patch_rows.glsl's setupRow /
// evalSample on the patch loadPatchRows loaded: the v contraction once per column in the power
// basis of u, X0[d] = Σ_r cu_r,d Σ_s B_s(v) P[r][s] and X1[d] likewise with B_s'(v); a sample is
// one Horner pass in u. α-EB: the v factors once, the corner weights per sample. Rational: the
// weights' sums alongside (gXW0, gXW1), then the quotient rule.
REAL3 gX0[DU + 1u], gX1[DU + 1u];
REAL gXW0[DU + 1u], gXW1[DU + 1u];
BlendFactors gFv;

void setupColumn(REAL tv) {
  REAL3 T0[MU], T1[MU];
  REAL TW0[MU], TW1[MU];
  [[unroll]] for (uint r = 0; r < MU; ++r) {
    T0[r] = REAL3(0);
    T1[r] = REAL3(0);
    TW0[r] = REAL(0);
    TW1[r] = REAL(0);
  }
  [[unroll]] for (uint s = 0; s < MV; ++s) {
    REAL w0 = cv[s][DV], dp = REAL(0), unused = REAL(0);
    [[unroll]] for (int d = int(DV) - 1; d >= 0; --d) hornerStep(w0, dp, unused, tv, cv[s][d]);
    [[unroll]] for (uint r = 0; r < MU; ++r) {
      T0[r] += w0 * gP[r][s];
      T1[r] += dp * gP[r][s];
      if (RATIONAL != 0u) {
        TW0[r] += w0 * gPW[r][s];
        TW1[r] += dp * gPW[r][s];
      }
    }
  }
  [[unroll]] for (uint d = 0; d <= DU; ++d) {
    REAL3 w0 = REAL3(0), w1 = REAL3(0);
    REAL ww0 = REAL(0), ww1 = REAL(0);
    [[unroll]] for (uint r = 0; r < MU; ++r) {
      w0 += gCu[r][d] * T0[r];
      w1 += gCu[r][d] * T1[r];
      if (RATIONAL != 0u) {
        ww0 += gCu[r][d] * TW0[r];
        ww1 += gCu[r][d] * TW1[r];
      }
    }
    gX0[d] = w0;
    gX1[d] = w1;
    gXW0[d] = ww0;
    gXW1[d] = ww1;
  }
  if (kAEB) gFv = blendFactors(singularBlend(tv));
}

void evalColumnSample(REAL t, out REAL3 p, out REAL3 du, out REAL3 dv) {
  p = gX0[DU];
  du = REAL3(0);
  dv = gX1[DU];
  REAL3 unused0 = REAL3(0), unused1 = REAL3(0), unused2 = REAL3(0);
  REAL w = gXW0[DU], wu = REAL(0), wv = gXW1[DU], unusedW = REAL(0);
  [[unroll]] for (int d = int(DU) - 1; d >= 0; --d) {
    hornerStep(p, du, unused0, t, gX0[d]);
    hornerStep(dv, unused1, unused2, t, gX1[d]);
    if (RATIONAL != 0u) {
      hornerStep(w, wu, unusedW, t, gXW0[d]);
      hornerStep(wv, unusedW, unusedW, t, gXW1[d]);
    }
  }
  if (RATIONAL != 0u) {
    REAL3 none = REAL3(0);  // the second partials: dead code
    rationalSurface(p, du, dv, none, none, none, w, wu, wv, REAL(0), REAL(0), REAL(0));
  }
  if (kAEB) {
    BlendFactors fu = blendFactors(singularBlend(t));
    AlphaEBWeights w = alphaEBWeightsZero();
    cornerBlend(fu.f00, fu.f01, gFv.f00, gFv.f01, gAl, gV, w.a00, w.L00);
    cornerBlend(fu.f10, fu.f11, gFv.f00, gFv.f01, gAl, gV, w.a10, w.L10);
    cornerBlend(fu.f00, fu.f01, gFv.f10, gFv.f11, gAl, gV, w.a01, w.L01);
    alphaEBBlendFirst(w, p, du, dv);
  }
}

// Point and Q_u x Q_v normal of the current edge at t: along u (v fixed: a column) or along v (u
// fixed: a row); `degenerate` when the normal needs the full rule (Fallbacks).
void edgeSample(bool alongU, REAL t, out REAL3 p, out vec3 n, out bool degenerate) {
  REAL3 du, dv;
  if (alongU) evalColumnSample(t, p, du, dv);
  else evalSample(t, p, du, dv);
  REAL3 cr = cross(du, dv);
  REAL len = length(cr);
  degenerate = degenerateCrossLength(du, dv, len);
  n = vec3(cr / len);
}

void setupEdge(bool alongU, uint a, uint b, REAL fixedLocal) {
  loadPatchRows(a + pc.firstSpanU, b + pc.firstSpanV);
  if (alongU) setupColumn(fixedLocal);
  else setupRow(fixedLocal);
}

// Edge x (u-edges, then v-edges; alongU is a constant of the mode): its e - 1 points from the
// owner patch, evaluated along the edge with the patch loaded once; the normal averaged with the
// patch on the other side where there is one (its normals, evaluated first the same way, wait in
// the point's vertex slot).
void edgePoints(uint x, bool alongU) {
  uvec2 rec = edges[x];
  uint e = rec.x, first = rec.y;
  uint eu = uEdgeCount();
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
  REAL den = REAL(e);
  // The local (u, v) of edge point k in the owner (fixedLocal) or the neighbour (1).
#define EDGE_UV(k, fixed) (alongU ? REAL(k) / den : (fixed)), (alongU ? (fixed) : REAL(k) / den)
  for (uint f = 0u; f < (shared_ ? 1u : 0u); ++f) {
    setupEdge(alongU, oa, ob, REAL(1));
    Fallbacks fallbacks = noFallbacks();
    for (uint k = 1u; k < e; ++k) {
      REAL3 p;
      vec3 n1;
      bool degenerate;
      edgeSample(alongU, REAL(k) / den, p, n1, degenerate);
      noteFallback(degenerate, k, fallbacks);
      outVerts[2u * (first + k - 1u)] = vec4(n1, 0.0);
    }
    for (uint g = 0u; g < fallbackCount(fallbacks, e - 1u); ++g) {
      uint k = fallbackSample(fallbacks, g, 1u);
      outVerts[2u * (first + k - 1u)] = vec4(fullNormalAt(oa + pc.firstSpanU, ob + pc.firstSpanV, EDGE_UV(k, REAL(1))), 0.0);
    }
  }
  setupEdge(alongU, a, b, fixedLocal);
  Fallbacks fallbacks = noFallbacks();
  for (uint k = 1u; k < e; ++k) {
    REAL3 p;
    vec3 n0;
    bool degenerate;
    edgeSample(alongU, REAL(k) / den, p, n0, degenerate);
    noteFallback(degenerate, k, fallbacks);
    vec3 parked = outVerts[2u * (first + k - 1u)].xyz;  // the neighbour's normal (when shared)
    vec3 n = shared_ ? meanNormal(n0 + parked, n0, 2u) : n0;
    store(first + k - 1u, a, b, EDGE_UV(k, fixedLocal), vec3(p), n);
  }
  // Degenerate owner normals: both sides' normals again from scratch (the parked one is overwritten).
  for (uint g = 0u; g < fallbackCount(fallbacks, e - 1u); ++g) {
    uint k = fallbackSample(fallbacks, g, 1u);
    vec3 n0 = vec3(fullNormalAt(a + pc.firstSpanU, b + pc.firstSpanV, EDGE_UV(k, fixedLocal)));
    vec3 n = n0;
    for (uint f = 0u; f < (shared_ ? 1u : 0u); ++f) n = meanNormal(n0 + normalOf(oa, ob, EDGE_UV(k, REAL(1))), n0, 2u);
    storeNormal(first + k - 1u, n);
  }
#undef EDGE_UV
}

// Row block t of patch p: interior rows i = 1 + t R .. (R = rowsPerBlock(m), tess_adaptive_grid.glsl),
// u = i/n, v = j/m for 0 < j < m, evaluated row-wise (the patch loaded once for the block); a
// sample whose derivatives are degenerate takes the full §5.3 rule after its row (Fallbacks).
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
    Fallbacks fallbacks = noFallbacks();
    for (uint j = 1u; j < m; ++j) {
      REAL v = REAL(j) / REAL(m);
      REAL3 p, du, dv;
      evalSample(v, p, du, dv);
      REAL3 cr = cross(du, dv);
      REAL len = length(cr);
      noteFallback(degenerateCrossLength(du, dv, len), j, fallbacks);
      store(first + j - 1u, a, b, u, v, vec3(p), vec3(cr / len));
    }
    uint todo = fallbackCount(fallbacks, m - 1u);
    for (uint f = 0u; f < todo; ++f) {
      uint j = fallbackSample(fallbacks, f, 1u);
      storeNormal(first + j - 1u, vec3(fullNormalAt(mi, mj, u, REAL(j) / REAL(m))));
    }
    quadRow(patchIndex, rec, i);
  }
}

// The transition rings of the patch sides along edge x: for a u-edge at v-boundary bb, side 0 of
// the patch after it and side 2 of the one before; for a v-edge at u-boundary aa, sides 3 and 1.
void edgeRings(uint x, bool alongU) {
  if (alongU) {
    uint BV = boundariesV();
    uint a = x / BV, bb = x - a * BV;
    if (bb < pc.patchesV) ring(a, bb, 0u);
    if (bb > 0u || pc.closedV != 0u) ring(a, (bb + pc.patchesV - 1u) % pc.patchesV, 2u);
  } else {
    uint y = x - uEdgeCount();
    uint aa = y / pc.patchesV, b = y - aa * pc.patchesV;
    if (aa < pc.patchesU) ring(aa, b, 3u);
    if (aa > 0u || pc.closedU != 0u) ring((aa + pc.patchesU - 1u) % pc.patchesU, b, 1u);
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
#define ROW_FIRST(x) rowFirst[x]

void main() {
  uint k = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  if (MODE == kAdaptModeCorners) {
    if (k < cornerCount()) corner(k);
    return;
  }
  if (MODE == kAdaptModeEdgesU) {
    if (k < uEdgeCount()) {
      edgePoints(k, true);
      edgeRings(k, true);
    }
    return;
  }
  if (MODE == kAdaptModeEdgesV) {
    if (k < vEdgeCount()) {
      edgePoints(uEdgeCount() + k, false);
      edgeRings(uEdgeCount() + k, false);
    }
    return;
  }
  if (k >= frame[kAdaptFrameRowCount]) return;
  uint p;
  LAST_AT_MOST(p, pc.patchesU * pc.patchesV, ROW_FIRST, k)
  interiorRows(p, k - rowFirst[p]);
}
