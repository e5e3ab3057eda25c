// The triangles of the adaptive mesh (tess_layout.h) in core/tess_topology.cpp buildTessTopology's
// order: per patch the transition rings of sides 0..3, then its interior quads row by row. The
// mesh pass writes them where it already holds what they need: an edge invocation the rings of the
// sides along its edge, an interior-row invocation the quads between its rows (a pass of their own
// paid a binary search and a dozen integer divisions per quad, which llvmpipe does lane by lane).
// The includer declares PATCHES (patchRecords), EDGES (edges), QUADS (quadFirst), INDICES
// (outIndices) and `pc`, and includes tess_adaptive_grid.glsl.
#ifndef SHAPESPLINE_TESS_ADAPTIVE_TRIANGLES_GLSL
#define SHAPESPLINE_TESS_ADAPTIVE_TRIANGLES_GLSL

// Interior point (i, j), 0 < i < n, 0 < j < m, of a patch whose interior starts at vertex `first`.
uint interiorVertexOf(uint first, uint m, uint i, uint j) { return first + (i - 1u) * (m - 1u) + (j - 1u); }

void emitTriangle(inout uint cursor, uint p, uint q, uint r) {
  outIndices[cursor] = p;
  outIndices[cursor + 1u] = q;
  outIndices[cursor + 2u] = r;
  cursor += 3u;
}

// Side s of patch (a, b): its edge polyline (corner, edge points, corner, increasing parameter)
// zipped to the outermost interior row. The outer side advances when its next point comes first
// in parameter ((k+1)/e < (i+2)/L, compared exactly in integers), the inner one on ties.
// Counter-clockwise in (u, v): as emitted on sides 0 and 1, reversed on sides 2 and 3.
void ring(uint a, uint b, uint s) {
  uvec4 rec = patchRecords[a * pc.patchesV + b];
  uint n = rec.x, m = rec.y;
  uint before = 0u;  // triangles of the sides before s
  for (uint t = 0u; t < s; ++t) before += ringTriangles(edges[sideEdge(a, b, t)].x, (t & 1u) == 0u ? n : m);
  uint cursor = rec.w + 3u * before;
  bool alongU = s == 0u || s == 2u;
  uvec2 edge = edges[sideEdge(a, b, s)];
  uint e = edge.x;
  uint c0, c1;
  if (alongU) {
    uint bb = b + (s == 2u ? 1u : 0u);
    c0 = cornerIndex(a, bb);
    c1 = cornerIndex(a + 1u, bb);
  } else {
    uint aa = a + (s == 1u ? 1u : 0u);
    c0 = cornerIndex(aa, b);
    c1 = cornerIndex(aa, b + 1u);
  }
  uint L = alongU ? n : m;
  // The interior row or column next to the side: point k of it is interiorVertexOf(.., fixed or k).
  uint fixedIndex = s == 0u || s == 3u ? 1u : (alongU ? m - 1u : n - 1u);
  bool reversed = s >= 2u;
  uint k = 0u, i = 0u;
  while (k < e || i + 2u < L) {
    bool advanceOuter = i + 2u >= L || (k < e && (k + 1u) * L < (i + 2u) * e);
    uint o0 = k == 0u ? c0 : edge.y + k - 1u;
    uint in0 = alongU ? interiorVertexOf(rec.z, m, i + 1u, fixedIndex) : interiorVertexOf(rec.z, m, fixedIndex, i + 1u);
    uint in1 = alongU ? interiorVertexOf(rec.z, m, i + 2u, fixedIndex) : interiorVertexOf(rec.z, m, fixedIndex, i + 2u);
    uint q = advanceOuter ? (k + 1u == e ? c1 : edge.y + k) : in1;
    k += advanceOuter ? 1u : 0u;
    i += advanceOuter ? 0u : 1u;
    if (reversed) emitTriangle(cursor, o0, in0, q);
    else emitTriangle(cursor, o0, q, in0);
  }
}

// The quads between interior rows i and i + 1 of patch p (record rec), if i <= n - 2.
void quadRow(uint p, uvec4 rec, uint i) {
  uint m = rec.y;
  uint cursor = quadFirst[p] + 6u * (i - 1u) * (m - 2u);
  uint quads = i + 2u <= rec.x ? m - 2u : 0u;  // none below the last interior row (a bound, not an if)
  for (uint j = 1u; j <= quads; ++j) {
    uint q00 = interiorVertexOf(rec.z, m, i, j), q01 = q00 + 1u;
    uint q10 = q00 + (m - 1u), q11 = q10 + 1u;
    emitTriangle(cursor, q00, q10, q11);
    emitTriangle(cursor, q00, q11, q01);
  }
}

#endif  // SHAPESPLINE_TESS_ADAPTIVE_TRIANGLES_GLSL
