// Patch evaluation and the docs/math.md §5.3 normal convention shared by surface_eval.comp and
// surface_grid.comp (the latter for its rare fallback normals). Mirrors host/core/surface.cpp
// (evalTensorPatch, evalAlphaEBPatch, normals). The includer declares `pc` (EvalPush) and the
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

// The net entry of patch row/column r,s: NET[(i + offU + r) * netCols + j + offV + s].
uint netBase(uint i, uint j) { return (i + pc.netOffsetU) * pc.netCols + j + pc.netOffsetV; }

// core/surface.cpp evalTensorPatch: contract along v first (3 row sums), then along u.
PatchDerivs evalTensorPatch(in Basis2 B, uint base) {
  PatchDerivs o;
  o.p = REAL3(0); o.u = REAL3(0); o.v = REAL3(0); o.uu = REAL3(0); o.uv = REAL3(0); o.vv = REAL3(0);
  for (uint r = 0; r < BASIS_COUNT_U; ++r) {
    REAL3 s0 = REAL3(0), s1 = REAL3(0), s2 = REAL3(0);
    uint row = base + r * pc.netCols;
    for (uint s = 0; s < BASIS_COUNT_V; ++s) {
      REAL3 P = net[row + s].xyz;
      s0 += B.bv[s] * P;
      s1 += B.dv[s] * P;
      s2 += B.ddv[s] * P;
    }
    o.p += B.bu[r] * s0;
    o.u += B.du[r] * s0;
    o.uu += B.ddu[r] * s0;
    o.v += B.bu[r] * s1;
    o.uv += B.du[r] * s1;
    o.vv += B.bu[r] * s2;
  }
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

// One weight derivative of docs/math.md §5.3 (evalAlphaEBPatch order): w = u-factor x v-factor per corner.
void cornerBlend(REAL fu0, REAL fu1, REAL fv0, REAL fv1, in REAL al[4], in REAL3 V[4], out REAL a, out REAL3 L) {
  REAL w00 = fu0 * fv0, w01 = fu0 * fv1, w10 = fu1 * fv0, w11 = fu1 * fv1;
  a = w00 * al[0] + w01 * al[1] + w10 * al[2] + w11 * al[3];
  L = w00 * V[0] + w01 * V[1] + w10 * V[2] + w11 * V[3];
}

// cornerBlend split in its u half (once per grid row) and v half (per sample): for the v = 0 side
// (corners 0, 2) and the v = 1 side (corners 1, 3), α and V blended with the u factors.
struct CornerHalf {
  REAL a0, a1;
  REAL3 L0, L1;
};
CornerHalf cornerBlendU(REAL fu0, REAL fu1, in REAL al[4], in REAL3 V[4]) {
  CornerHalf h;
  h.a0 = fu0 * al[0] + fu1 * al[2];
  h.a1 = fu0 * al[1] + fu1 * al[3];
  h.L0 = fu0 * V[0] + fu1 * V[2];
  h.L1 = fu0 * V[1] + fu1 * V[3];
  return h;
}
void cornerBlendV(in CornerHalf h, REAL fv0, REAL fv1, out REAL a, out REAL3 L) {
  a = fv0 * h.a0 + fv1 * h.a1;
  L = fv0 * h.L0 + fv1 * h.L1;
}

// core/surface.cpp evalAlphaEBPatch (docs/math.md §5.2, §5.3): Q = C + a M, M = L - C, with the
// bilinear weights of the singular blend in u and v. base receives C.
PatchDerivs evalAlphaEBPatch(in Basis2 B, uint i, uint j, REAL u, REAL v, out PatchDerivs c) {
  c = evalTensorPatch(B, netBase(i, j));
  REAL3 V[4];
  REAL al[4];
  loadPatchCorners(i, j, V, al);
  REAL3 su = singularBlend(u), sv = singularBlend(v);
  // u-factor pairs of order 0,1,2: (1-S, S), (-S', S'), (-S'', S'').
  REAL fu0[3] = REAL[3](REAL(1) - su.x, -su.y, -su.z), fu1[3] = REAL[3](su.x, su.y, su.z);
  REAL fv0[3] = REAL[3](REAL(1) - sv.x, -sv.y, -sv.z), fv1[3] = REAL[3](sv.x, sv.y, sv.z);
  REAL a[3][3];
  REAL3 L[3][3];
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q + r < 3; ++q) {
      REAL w00 = fu0[r] * fv0[q], w01 = fu0[r] * fv1[q], w10 = fu1[r] * fv0[q], w11 = fu1[r] * fv1[q];
      a[r][q] = w00 * al[0] + w01 * al[1] + w10 * al[2] + w11 * al[3];
      L[r][q] = w00 * V[0] + w01 * V[1] + w10 * V[2] + w11 * V[3];
    }
  REAL3 M = L[0][0] - c.p, Mu = L[1][0] - c.u, Mv = L[0][1] - c.v;
  REAL3 Muu = L[2][0] - c.uu, Muv = L[1][1] - c.uv, Mvv = L[0][2] - c.vv;
  PatchDerivs o;
  o.p = c.p + a[0][0] * M;
  o.u = c.u + a[0][0] * Mu + a[1][0] * M;
  o.v = c.v + a[0][0] * Mv + a[0][1] * M;
  o.uu = c.uu + a[0][0] * Muu + REAL(2) * a[1][0] * Mu + a[2][0] * M;
  o.uv = c.uv + a[0][0] * Muv + a[1][0] * Mv + a[0][1] * Mu + a[1][1] * M;
  o.vv = c.vv + a[0][0] * Mvv + REAL(2) * a[0][1] * Mv + a[0][2] * M;
  return o;
}

PatchDerivs evalPatch(in Basis2 B, uint i, uint j, REAL u, REAL v, out PatchDerivs c) {
  if (ALPHA_EB != 0u) return evalAlphaEBPatch(B, i, j, u, v, c);
  c = evalTensorPatch(B, netBase(i, j));
  return c;
}

void hornerBasis(REAL u, REAL v, out Basis2 B) {
  evalSpanBasis(kParamCoefU, BASIS_COUNT_U, POLY_DEGREE_U, u, B.bu, B.du, B.ddu);
  evalSpanBasis(kParamCoefV, BASIS_COUNT_V, POLY_DEGREE_V, v, B.bv, B.dv, B.ddv);
}

// core/surface.cpp degenerateCross (docs/math.md §5.3 thresholds) of a x b = n, |n| = len. No
// short-circuit: a branch-free expression (llvmpipe would run each side of a per-lane branch with masks).
bool degenerateCrossLength(REAL3 a, REAL3 b, REAL len) {
  bool zeroA = all(equal(a, REAL3(0))), zeroB = all(equal(b, REAL3(0)));
  // !(>=) so that NaN counts as degenerate, as in the C++.
  bool small = !(len >= REAL(1e-12) * length(a) * length(b)) || len == REAL(0) || isinf(len);
  return any(bvec3(zeroA, zeroB, small));
}
bool degenerateCross(REAL3 a, REAL3 b, REAL3 n) { return degenerateCrossLength(a, b, length(n)); }

// core/surface.cpp alphaEBCornerNormal: diagonal limit at an α = 1 vertex (docs/math.md §5.3).
REAL3 alphaEBCornerNormal(REAL3 p, REAL3 node, REAL3 vU, REAL aU, REAL3 vV, REAL aV, REAL sU, REAL sV) {
  REAL3 Au = vU - p + (REAL(1) - aU) * (node - p);
  REAL3 Av = vV - p + (REAL(1) - aV) * (node - p);
  return cross(sU * Au, sV * Av);
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
  REAL3 Au = vU - P + (REAL(1) - aU) * (node - P);
  REAL3 Av = vV - P + (REAL(1) - aV) * (node - P);
  REAL sU = di == 0u ? REAL(1) : REAL(-1), sV = dj == 0u ? REAL(1) : REAL(-1);
  n = alphaEBCornerNormal(P, node, vU, aU, vV, aV, sU, sV);
  return !degenerateCross(sU * Au, sV * Av, n);
}

// The docs/math.md §5.3 rendering convention, in the order of core/surface.h; never NaN.
REAL3 surfaceNormal(uint i, uint j, REAL u, REAL v, in PatchDerivs q, in PatchDerivs c) {
  if (ALPHA_EB != 0u && (u == REAL(0) || u == REAL(1)) && (v == REAL(0) || v == REAL(1))) {
    REAL3 n;
    if (alphaEBVertexNormal(i, j, u == REAL(1) ? 1u : 0u, v == REAL(1) ? 1u : 0u, n)) return normalize(n);
  }
  REAL3 n = cross(q.u, q.v);
  if (!degenerateCross(q.u, q.v, n)) return normalize(n);
  const REAL delta = REAL(1.0 / 4096.0);
  REAL us = u < REAL(0.5) ? u + delta : (u > REAL(0.5) ? u - delta : u);
  REAL vs = v < REAL(0.5) ? v + delta : (v > REAL(0.5) ? v - delta : v);
  Basis2 B;
  hornerBasis(us, vs, B);
  PatchDerivs cs;
  PatchDerivs qs = evalPatch(B, i, j, us, vs, cs);
  n = cross(qs.u, qs.v);
  if (!degenerateCross(qs.u, qs.v, n)) return normalize(n);
  n = cross(c.u, c.v);
  if (!degenerateCross(c.u, c.v, n)) return normalize(n);
  return REAL3(0, 0, 1);
}

#endif  // SHAPESPLINE_SURFACE_PATCH_GLSL
