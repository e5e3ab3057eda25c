// Row-wise patch evaluation shared by tessellate_grid.comp and tess_adaptive_mesh.comp: a patch's
// net and bases are loaded once (loadPatchRows), each row u = const is contracted once (setupRow),
// and each sample of the row is one Horner pass in v (evalSample). The includer declares `pc` with
// the EvalPush net fields and the VertBuf `verts`, and includes surface_patch.glsl first; kAEB,
// MU, MV, DU, DV as in tessellate_grid.comp.
#ifndef SHAPESPLINE_PATCH_ROWS_GLSL
#define SHAPESPLINE_PATCH_ROWS_GLSL

// Point, Q_u, Q_v at v = t of the current row, branch-free. The row data: its u contraction in
// the power basis of v, W0[d] = Σ_s c_s,d Σ_r B_r(u) P[r][s] and W1[d] likewise with B_r'(u), where
// B_s(v) = Σ_d c_s,d v^d are the v basis coefficients (SpanBasis); the patch's corner V and α and
// their blend with the u factors of the row. A sample is then one Horner pass over d for the point, Q_v (its
// derivative) and Q_u, instead of evaluating every v basis function and contracting with them:
// 90 instead of 228 operations per sample at degree 5 (llvmpipe does not fuse multiply-adds). The
// rounding bound is the same, Σ |c_s,d| |P| ulps either way. Rational knot patches (RATIONAL): the
// same sums of the weights (gWW0, gWW1) ride along and the quotient rule of point_math.h turns the
// homogeneous values into the surface's. (Globals: a struct of arrays sized by specialization
// constants miscompiles.)
REAL3 gW0[DV + 1u], gW1[DV + 1u], gV[4];
REAL gWW0[DV + 1u], gWW1[DV + 1u];
REAL gAl[4];
CornerHalf gH0, gH1;  // the u halves of the α-EB corner weights of the row, u orders 0 and 1
REAL cv[MV][DV + 1u];  // v basis coefficients (PARAMS)

void evalSample(REAL t, out REAL3 p, out REAL3 du, out REAL3 dv) {
  p = gW0[DV];
  du = gW1[DV];
  dv = REAL3(0);
  REAL3 unused0 = REAL3(0), unused1 = REAL3(0), unused2 = REAL3(0);  // dead code after inlining
  REAL w = gWW0[DV], wv = REAL(0), wu = gWW1[DV], unusedW = REAL(0);
  [[unroll]] for (int d = int(DV) - 1; d >= 0; --d) {
    hornerStep(p, dv, unused0, t, gW0[d]);
    hornerStep(du, unused1, unused2, t, gW1[d]);
    if (RATIONAL != 0u) {
      hornerStep(w, wv, unusedW, t, gWW0[d]);
      hornerStep(wu, unusedW, unusedW, t, gWW1[d]);
    }
  }
  if (RATIONAL != 0u) {
    REAL3 none = REAL3(0);  // the second partials: dead code
    rationalSurface(p, du, dv, none, none, none, w, wu, wv, REAL(0), REAL(0), REAL(0));
  }
  if (kAEB) {
    // docs/math.md §5.3 (evalAlphaEBPatch) for Q, Q_u, Q_v, the u halves of the weights from the row.
    BlendFactors fv = blendFactors(singularBlend(t));
    AlphaEBWeights w = alphaEBWeightsZero();
    cornerBlendV(gH0, fv.f00, fv.f01, w.a00, w.L00);
    cornerBlendV(gH1, fv.f00, fv.f01, w.a10, w.L10);
    cornerBlendV(gH0, fv.f10, fv.f11, w.a01, w.L01);
    alphaEBBlendFirst(w, p, du, dv);
  }
}

// Per-patch data (per-lane gathers on llvmpipe: shared by all rows an invocation evaluates).
REAL3 gP[MU][MV];
REAL gPW[MU][MV];  // rational: the weights
REAL gCu[MU][DU + 1u];

void loadPatchRows(uint i, uint j) {
  uint base = netBase(i, j);
  [[unroll]] for (uint r = 0; r < MU; ++r)
    [[unroll]] for (uint s = 0; s < MV; ++s) {
      REAL4 h = net[base + r * pc.netCols + s];
      gP[r][s] = h.xyz;
      gPW[r][s] = RATIONAL != 0u ? h.w : REAL(0);
    }
  [[unroll]] for (uint r = 0; r < MU; ++r)
    [[unroll]] for (uint d = 0; d <= DU; ++d) gCu[r][d] = params[coefBaseU(i) + r * kCoefStride + d];
  [[unroll]] for (uint s = 0; s < MV; ++s)
    [[unroll]] for (uint d = 0; d <= DV; ++d) cv[s][d] = params[coefBaseV(j) + s * kCoefStride + d];
  if (kAEB) loadPatchCorners(i, j, gV, gAl);
}

// The row data of u = tu (see evalSample).
void setupRow(REAL tu) {
  REAL3 T0[MV], T1[MV];  // Σ_r B_r(u) P[r][s], Σ_r B_r'(u) P[r][s]
  REAL TW0[MV], TW1[MV];  // the same of the weights (rational)
  [[unroll]] for (uint s = 0; s < MV; ++s) {
    T0[s] = REAL3(0);
    T1[s] = REAL3(0);
    TW0[s] = REAL(0);
    TW1[s] = REAL(0);
  }
  [[unroll]] for (uint r = 0; r < MU; ++r) {
    REAL w0 = gCu[r][DU], dp = REAL(0), unused = REAL(0);
    [[unroll]] for (int d = int(DU) - 1; d >= 0; --d) hornerStep(w0, dp, unused, tu, gCu[r][d]);
    [[unroll]] for (uint s = 0; s < MV; ++s) {
      T0[s] += w0 * gP[r][s];
      T1[s] += dp * gP[r][s];
      if (RATIONAL != 0u) {
        TW0[s] += w0 * gPW[r][s];
        TW1[s] += dp * gPW[r][s];
      }
    }
  }
  [[unroll]] for (uint d = 0; d <= DV; ++d) {
    REAL3 w0 = REAL3(0), w1 = REAL3(0);
    REAL ww0 = REAL(0), ww1 = REAL(0);
    [[unroll]] for (uint s = 0; s < MV; ++s) {
      w0 += cv[s][d] * T0[s];
      w1 += cv[s][d] * T1[s];
      if (RATIONAL != 0u) {
        ww0 += cv[s][d] * TW0[s];
        ww1 += cv[s][d] * TW1[s];
      }
    }
    gW0[d] = w0;
    gW1[d] = w1;
    gWW0[d] = ww0;
    gWW1[d] = ww1;
  }
  if (kAEB) {
    BlendFactors fu = blendFactors(singularBlend(tu));
    gH0 = cornerBlendU(fu.f00, fu.f01, gAl, gV);
    gH1 = cornerBlendU(fu.f10, fu.f11, gAl, gV);
  }
}

// Samples of a row (or edge) whose Q_u x Q_v is degenerate take the full §5.3 rule
// (fullNormalAt), which is rare. The sample loop only notes them, with selects: a branch or loop
// inside it made llvmpipe spill the row data around it, and the whole loop ran ~5x slower. A loop
// after the sample loop redoes them: the first two noted, or all of the row's samples when more.
struct Fallbacks {
  uint count, first, second;
};
Fallbacks noFallbacks() { return Fallbacks(0u, 0u, 0u); }
void noteFallback(bool degenerate, uint index, inout Fallbacks f) {
  f.first = degenerate && f.count == 0u ? index : f.first;
  f.second = degenerate && f.count == 1u ? index : f.second;
  f.count += degenerate ? 1u : 0u;
}
// How many samples to redo for a row of `samples` samples, and the k-th of them (samples are
// numbered from `firstSample`).
uint fallbackCount(Fallbacks f, uint samples) { return f.count <= 2u ? f.count : samples; }
uint fallbackSample(Fallbacks f, uint k, uint firstSample) {
  return f.count <= 2u ? (k == 0u ? f.first : f.second) : firstSample + k;
}

#endif  // SHAPESPLINE_PATCH_ROWS_GLSL
