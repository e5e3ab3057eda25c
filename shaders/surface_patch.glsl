// Patch evaluation and the docs/math.md §5.3 normal convention shared by surface_eval.comp,
// surface_grid.comp and tessellate_grid.comp (the latter two for their rare fallback normals): the
// loops and buffer reads of host/core/surface.cpp evalTensorPatch / evalAlphaEBPatch / evalWithNormal
// around the formulas of point_math.h. The includer declares `pc` (EvalPush) and the
// VertBuf `verts` (binding 2) before including this file (after common.glsl).
#ifndef SHAPESPLINE_SURFACE_PATCH_GLSL
#define SHAPESPLINE_SURFACE_PATCH_GLSL

struct PatchDerivs {
  REAL3 p, u, v, uu, uv, vv;
};

struct Basis2 {
  REAL bu[kMaxBasis], du[kMaxBasis], ddu[kMaxBasis];
  REAL bv[kMaxBasis], dv[kMaxBasis], ddv[kMaxBasis];
};

// Knot-vector surfaces (KNOT_PATCHES, layout.h): patch (i, j) is non-empty knot interval pair
// (i, j), its data in the knot patch records of PARAMS.
uint knotPatchU(uint i) { return uint(params[kParamKnotPatchU]) + i * kKnotPatchStride; }
uint knotPatchV(uint j) { return uint(params[kParamKnotPatchV]) + j * kKnotPatchStride; }

// The net entry of patch row/column r,s: NET[(i + offU + r) * netCols + j + offV + s]; knot
// patches: rows and columns from the intervals' first control points.
uint netBase(uint i, uint j) {
  if (KNOT_PATCHES != 0u) return uint(params[knotPatchU(i)]) * pc.netCols + uint(params[knotPatchV(j)]);
  return (i + pc.netOffsetU) * pc.netCols + j + pc.netOffsetV;
}

// Where patch (i, j)'s u and v basis coefficients start in PARAMS: the header's (one basis for
// every patch of a uniform family), or the intervals' own.
uint coefBaseU(uint i) { return KNOT_PATCHES != 0u ? knotPatchU(i) + kKnotPatchCoef : kParamCoefU; }
uint coefBaseV(uint j) { return KNOT_PATCHES != 0u ? knotPatchV(j) + kKnotPatchCoef : kParamCoefV; }

// The global parameters of patch (i, j) at local (u, v), as a vertex's uv: i + u, j + v (in float,
// as core/tess_patches.cpp forms them), or the knot parameters t_i + u h_i, t_j + v h_j.
vec2 patchParameter(uint i, uint j, REAL u, REAL v) {
  if (KNOT_PATCHES != 0u) {
    uint ru = knotPatchU(i), rv = knotPatchV(j);
    return vec2(float(params[ru + 1u] + u * params[ru + 2u]), float(params[rv + 1u] + v * params[rv + 2u]));
  }
  return vec2(float(i) + float(u), float(j) + float(v));
}

// core/surface.cpp evalTensorPatch: contract along v first (3 row sums), then along u. Rational
// knot patches: the same sums of NET's (w P, w), then point_math.h's quotient rule.
PatchDerivs evalTensorPatch(in Basis2 B, uint base) {
  PatchDerivs o;
  o.p = REAL3(0); o.u = REAL3(0); o.v = REAL3(0); o.uu = REAL3(0); o.uv = REAL3(0); o.vv = REAL3(0);
  PatchDerivs w;  // the weight sums in .x (rational)
  w.p = REAL3(0); w.u = REAL3(0); w.v = REAL3(0); w.uu = REAL3(0); w.uv = REAL3(0); w.vv = REAL3(0);
  for (uint r = 0; r < BASIS_COUNT_U; ++r) {
    REAL3 s0 = REAL3(0), s1 = REAL3(0), s2 = REAL3(0), q0 = REAL3(0), q1 = REAL3(0), q2 = REAL3(0);
    uint row = base + r * pc.netCols;
    for (uint s = 0; s < BASIS_COUNT_V; ++s) {
      REAL4 h = net[row + s];
      accumulate3(s0, s1, s2, B.bv[s], B.dv[s], B.ddv[s], h.xyz);
      if (RATIONAL != 0u) accumulate3(q0, q1, q2, B.bv[s], B.dv[s], B.ddv[s], REAL3(h.w, 0, 0));
    }
    accumulateTensorRow(o.p, o.u, o.v, o.uu, o.uv, o.vv, B.bu[r], B.du[r], B.ddu[r], s0, s1, s2);
    if (RATIONAL != 0u) accumulateTensorRow(w.p, w.u, w.v, w.uu, w.uv, w.vv, B.bu[r], B.du[r], B.ddu[r], q0, q1, q2);
  }
  if (RATIONAL != 0u) rationalSurface(o.p, o.u, o.v, o.uu, o.uv, o.vv, w.p.x, w.u.x, w.v.x, w.uu.x, w.uv.x, w.vv.x);
  return o;
}

// Index of α-EB vertex (i, j), wrapped for closed directions. i <= rows and j <= cols always (a
// patch index + 1), so a compare replaces the modulo (an integer division is a per-lane scalar loop
// on llvmpipe).
uint vertexIndex(uint i, uint j) {
  return (i >= pc.rows ? i - pc.rows : i) * pc.cols + (j >= pc.cols ? j - pc.cols : j);
}
REAL alphaAt(uint i, uint j) { return params[pc.alphaOffset + vertexIndex(i, j)]; }

// V and α of the corners (i,j), (i,j+1), (i+1,j), (i+1,j+1) of α-EB patch (i, j).
void loadPatchCorners(uint i, uint j, out REAL3 V[4], out REAL al[4]) {
  V[0] = verts[vertexIndex(i, j)].xyz;         al[0] = alphaAt(i, j);
  V[1] = verts[vertexIndex(i, j + 1)].xyz;     al[1] = alphaAt(i, j + 1);
  V[2] = verts[vertexIndex(i + 1, j)].xyz;     al[2] = alphaAt(i + 1, j);
  V[3] = verts[vertexIndex(i + 1, j + 1)].xyz; al[3] = alphaAt(i + 1, j + 1);
}

// core/surface.cpp evalAlphaEBPatch (docs/math.md §5.2, §5.3): Q = C + a M, M = L - C, with the
// bilinear weights of the singular blend in u and v. c receives C.
PatchDerivs evalAlphaEBPatch(in Basis2 B, uint i, uint j, REAL u, REAL v, out PatchDerivs c) {
  c = evalTensorPatch(B, netBase(i, j));
  REAL3 V[4];
  REAL al[4];
  loadPatchCorners(i, j, V, al);
  AlphaEBWeights w = alphaEBWeights(singularBlend(u), singularBlend(v), al, V);
  PatchDerivs o = c;
  alphaEBBlendPatch(w, o.p, o.u, o.v, o.uu, o.uv, o.vv);
  return o;
}

PatchDerivs evalPatch(in Basis2 B, uint i, uint j, REAL u, REAL v, out PatchDerivs c) {
  if (ALPHA_EB != 0u) return evalAlphaEBPatch(B, i, j, u, v, c);
  c = evalTensorPatch(B, netBase(i, j));
  return c;
}

void hornerBasis(uint i, uint j, REAL u, REAL v, out Basis2 B) {
  evalSpanBasis(coefBaseU(i), BASIS_COUNT_U, POLY_DEGREE_U, u, B.bu, B.du, B.ddu);
  evalSpanBasis(coefBaseV(j), BASIS_COUNT_V, POLY_DEGREE_V, v, B.bv, B.dv, B.ddv);
}

// docs/math.md §5.3 at corner (di, dj) of α-EB patch (i, j) (di, dj in {0, 1}): when the vertex has
// α = 1, its diagonal limit normal (unnormalised) in n and true, unless that is degenerate.
bool alphaEBVertexNormal(uint i, uint j, uint di, uint dj, out REAL3 n) {
  n = REAL3(0);
  uint vi = i + di, vj = j + dj;
  if (alphaAt(vi, vj) != REAL(1)) return false;
  uint ni = i + 1u - di, nj = j + 1u - dj;  // neighbours along u and v inside the patch
  REAL3 P = net[netBase(vi + 1u, vj + 1u) - pc.netOffsetU * pc.netCols - pc.netOffsetV].xyz;
  REAL3 node = verts[pc.rows * pc.cols + vertexIndex(vi, vj)].xyz;
  REAL3 vU = verts[vertexIndex(ni, vj)].xyz, vV = verts[vertexIndex(vi, nj)].xyz;
  REAL aU = alphaAt(ni, vj), aV = alphaAt(vi, nj);
  REAL sU = di == 0u ? REAL(1) : REAL(-1), sV = dj == 0u ? REAL(1) : REAL(-1);
  REAL3 axisU, axisV;
  alphaEBCornerAxes(P, node, vU, aU, vV, aV, sU, sV, axisU, axisV);
  n = cross(axisU, axisV);
  return !degenerateCross(axisU, axisV, n);
}

// The docs/math.md §5.3 rendering convention, in the order of core/surface.h; never NaN.
REAL3 surfaceNormal(uint i, uint j, REAL u, REAL v, in PatchDerivs q, in PatchDerivs c) {
  if (ALPHA_EB != 0u && (u == REAL(0) || u == REAL(1)) && (v == REAL(0) || v == REAL(1))) {
    REAL3 n;
    if (alphaEBVertexNormal(i, j, u == REAL(1) ? 1u : 0u, v == REAL(1) ? 1u : 0u, n)) return normalize(n);
  }
  REAL3 n = cross(q.u, q.v);
  if (!degenerateCross(q.u, q.v, n)) return normalize(n);
  REAL us = towardCentre(u), vs = towardCentre(v);
  Basis2 B;
  hornerBasis(i, j, us, vs, B);
  PatchDerivs cs;
  PatchDerivs qs = evalPatch(B, i, j, us, vs, cs);
  n = cross(qs.u, qs.v);
  if (!degenerateCross(qs.u, qs.v, n)) return normalize(n);
  n = cross(c.u, c.v);
  if (!degenerateCross(c.u, c.v, n)) return normalize(n);
  return fixedAxisNormal();
}

// The §5.3 normal of patch (i, j) at local (u, v) from scratch (bases by Horner, as basis_table.comp
// gives them): for the rare samples whose row-wise Q_u x Q_v is degenerate.
REAL3 fullNormalAt(uint i, uint j, REAL u, REAL v) {
  Basis2 B;
  hornerBasis(i, j, u, v, B);
  PatchDerivs c;
  PatchDerivs q = evalPatch(B, i, j, u, v, c);
  return surfaceNormal(i, j, u, v, q, c);
}

#endif  // SHAPESPLINE_SURFACE_PATCH_GLSL
