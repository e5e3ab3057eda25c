#version 450
// Closest points on a surface or a part (docs/math.md "Closest points"): one invocation per query
// walks the projection tree (projection_layout.h), nearest child first, and runs Newton on every
// cell whose bound is nearer than the best point so far, as part/closest_points.cpp does on the
// CPU: the same start, steps, border sides, trim loops, loop pieces, second looks and tie rule.
// What differs: a stack instead of a heap (the same pieces are searched, in another order), loop
// pieces in list order, and a search that outgrows its fixed stack or its loop budget flagged for
// the host to redo. The host finishes each hit (normal, sign) with the CPU's code.
//
// The loop budget: llvmpipe ends every loop of a workgroup once the workgroup has run 65,535 loop
// iterations in all (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS, one counter for all its loops), and the
// results are then wrong. So Horner's loops run over the tree's largest degrees (POLY_DEGREE_U/V,
// the patches padded with zeros), constant counts the compiler unrolls; every other loop counts its
// iterations in `iterations`, and a query past pc.loopBudget is flagged for the host, which runs
// workgroups of 8 there with a budget of an eighth (gpu/closest_point_search.cpp).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"
#include "projection_layout.h"

#if defined(REAL_IS_DOUBLE) && REAL_IS_DOUBLE
#define REAL2 dvec2
const double kNone = 1e300;
#else
#define REAL2 vec2
const float kNone = 3.0e38;
#endif

layout(std430, binding = kProjBindingInts) readonly buffer IntBuf { uint ints[]; };
layout(std430, binding = kProjBindingQueries) readonly buffer QueryBuf { REAL4 queries[]; };
layout(std430, binding = kProjBindingHitReals) writeonly buffer HitRealBuf { REAL hitReals[]; };
layout(std430, binding = kProjBindingHitInts) writeonly buffer HitIntBuf { uint hitInts[]; };
layout(push_constant) uniform PushBlock { ProjectionPush pc; };

const int kMaxNewtonSteps = 60;
const int kMaxHalvings = 40;
const REAL kFocalFraction = REAL(1);
const uint kMaxLeaves = 4u;
uint iterations = 0u;

REAL3 real3At(uint k) { return REAL3(params[k], params[k + 1u], params[k + 2u]); }

REAL boxDistance2(uint k, REAL3 q) {
  REAL3 d = max(max(real3At(k) - q, q - real3At(k + 3u)), REAL3(0));
  return dot(d, d);
}

// The larger of a leaf's box distance and its cell's oriented box distance (leafBound on the CPU).
REAL leafBound(uint leaf, REAL3 q) {
  REAL box = boxDistance2(pc.leafReals + 6u * leaf, q);
  uint c = pc.cellReals + kProjCellReals * ints[pc.leafInts + leaf];
  REAL3 d = q - real3At(c + kCellMiddle);
  REAL sum = REAL(0);
  [[unroll]] for (uint k = 0u; k < 3u; ++k) {
    REAL t = dot(d, real3At(c + kCellAxes + 3u * k)), lo = params[c + kCellLo + k], hi = params[c + kCellHi + k];
    REAL out_ = t < lo ? lo - t : (t > hi ? t - hi : REAL(0));
    sum += out_ * out_;
  }
  return max(box, sum);
}

struct LocalPoint {
  REAL3 p, u, v, uu, uv, vv;
};

// A tree patch at local (u, v): the centred power form by Horner's rule (evaluatePatch on the CPU).
LocalPoint evaluatePatch(uint patchId, REAL u, REAL v) {
  uint pi = pc.patchInts + 4u * patchId;
  uint first = ints[pi + 2u];
  REAL su = u - REAL(0.5), sv = v - REAL(0.5);
  const uint rowLength = POLY_DEGREE_V + 1u;
  REAL4 p = REAL4(0), pu = REAL4(0), puu = REAL4(0), pv = REAL4(0), puv = REAL4(0), pvv = REAL4(0);
  [[unroll]] for (int d = int(POLY_DEGREE_U); d >= 0; --d) {
    uint row = first + uint(d) * rowLength;
    REAL4 r = REAL4(0), r1 = REAL4(0), r2 = REAL4(0);
    [[unroll]] for (int e = int(POLY_DEGREE_V); e >= 0; --e) {
      r2 = r2 * sv + r1;
      r1 = r1 * sv + r;
      r = r * sv + net[row + uint(e)];
    }
    puu = puu * su + pu;
    pu = pu * su + p;
    p = p * su + r;
    puv = puv * su + pv;
    pv = pv * su + r1;
    pvv = pvv * su + r2;
  }
  puu *= REAL(2);
  pvv *= REAL(2);
  LocalPoint e = LocalPoint(p.xyz, pu.xyz, pv.xyz, puu.xyz, puv.xyz, pvv.xyz);
  if (ints[pi + 3u] != 0u) rationalSurface(e.p, e.u, e.v, e.uu, e.uv, e.vv, p.w, pu.w, pv.w, puu.w, puv.w, pvv.w);
  return e;
}

// The interval of `count` whose [breaks[a], breaks[a + 1]) holds x (the last one for its end).
uint intervalOf(uint firstBreak, uint intervals, REAL x) {
  uint first = 0u;
  for (int bit = findMSB(intervals); bit >= 0; --bit) {
    ++iterations;
    uint next = first + (1u << uint(bit));
    if (next < intervals && params[firstBreak + next] <= x) first = next;
  }
  return first;
}

// A face at face-relative (U, V), clamped into its domain, with partials in U and V (evaluateGlobal).
LocalPoint evaluateGlobal(uint face, REAL2 uv) {
  uint fi = pc.faceInts + kProjFaceInts * face, fr = pc.faceReals + kProjFaceReals * face;
  REAL U = clamp(uv.x, REAL(0), params[fr]), V = clamp(uv.y, REAL(0), params[fr + 1u]);
  uint countU = ints[fi + kFaceCountU], countV = ints[fi + kFaceCountV];
  uint breaksU = ints[fi + kFaceBreaks], breaksV = breaksU + countU + 1u;
  uint a = intervalOf(breaksU, countU, U), b = intervalOf(breaksV, countV, V);
  REAL u0 = params[breaksU + a], hu = params[breaksU + a + 1u] - u0;
  REAL v0 = params[breaksV + b], hv = params[breaksV + b + 1u] - v0;
  LocalPoint e = evaluatePatch(ints[ints[fi + kFacePatchTable] + a * countV + b], (U - u0) / hu, (V - v0) / hv);
  e.u /= hu;
  e.v /= hv;
  e.uu /= hu * hu;
  e.uv /= hu * hv;
  e.vv /= hv * hv;
  return e;
}

// A curve on a face that Newton runs along: a side of a patch (kind 0: u or v fixed), or a trim
// loop segment lifted onto its face (kind 1: (U, V) = a + t ab).
struct Segment {
  uint kind, patchId, face;
  bool alongV;
  REAL fixed_;
  REAL2 a, ab;
};

void evalSegment(Segment s, REAL t, out REAL3 p, out REAL3 d1, out REAL3 d2) {
  if (s.kind == 0u) {
    LocalPoint l = s.alongV ? evaluatePatch(s.patchId, s.fixed_, t) : evaluatePatch(s.patchId, t, s.fixed_);
    p = l.p;
    d1 = s.alongV ? l.v : l.u;
    d2 = s.alongV ? l.vv : l.uu;
  } else {
    LocalPoint e = evaluateGlobal(s.face, s.a + t * s.ab);
    p = e.p;
    d1 = e.u * s.ab.x + e.v * s.ab.y;
    d2 = e.uu * (s.ab.x * s.ab.x) + REAL(2) * e.uv * (s.ab.x * s.ab.y) + e.vv * (s.ab.y * s.ab.y);
  }
}

// Newton along a segment over [lo, hi] from x (newtonOnSegment). Returns the squared distance.
REAL newtonOnSegment(REAL3 q, Segment s, REAL lo, REAL hi, inout REAL x, out REAL3 foot) {
  REAL stepTolerance = params[kProjStepTolerance];
  REAL3 p, d1, d2;
  evalSegment(s, x, p, d1, d2);
  REAL3 r = p - q;
  REAL f = dot(r, r);
  bool running = true;
  for (int step = 0; step < kMaxNewtonSteps && running; ++step) {
    ++iterations;
    REAL g = dot(d1, r);
    REAL curvature = dot(d1, d1) + dot(d2, r);
    REAL h = curvature > REAL(0) ? curvature : dot(d1, d1);
    REAL dx = h > REAL(0) ? -g / h : (g > REAL(0) ? lo - x : hi - x);
    bool trusted = curvature > REAL(0) && abs(dx) < params[kProjTrustedStep];
    if ((x <= lo && g > REAL(0)) || (x >= hi && g < REAL(0)) || g == REAL(0) || abs(dx) < stepTolerance) {
      running = false;
    } else {
      REAL xn = x, fn = f;
      REAL3 pn, d1n, d2n;
      int halvings = 0;
      bool halving = true;
      while (halving) {
        ++iterations;
        xn = clamp(x + dx, lo, hi);
        evalSegment(s, xn, pn, d1n, d2n);
        fn = dot(pn - q, pn - q);
        halving = !(fn <= f || trusted || ++halvings > kMaxHalvings || abs(dx) < stepTolerance);
        dx *= REAL(0.5);
      }
      if (fn > f && !trusted) {
        running = false;
      } else {
        REAL moved = abs(xn - x);
        x = xn;
        p = pn;
        d1 = d1n;
        d2 = d2n;
        r = pn - q;
        f = fn;
        running = moved >= stepTolerance;
      }
    }
  }
  foot = p;
  return f;
}

// Newton on |S - q|^2 over a patch's local rectangle lo..hi from x (newtonOnPatch).
REAL newtonOnPatch(uint patchId, REAL2 lo, REAL2 hi, REAL3 q, inout REAL2 x, out LocalPoint e, out bool settled) {
  REAL stepTolerance = params[kProjStepTolerance];
  e = evaluatePatch(patchId, x.x, x.y);
  REAL3 r = e.p - q;
  REAL f = dot(r, r);
  bool running = true;
  for (int step = 0; step < kMaxNewtonSteps && running; ++step) {
    ++iterations;
    REAL2 g = REAL2(dot(e.u, r), dot(e.v, r));
    REAL a00 = dot(e.u, e.u), a01 = dot(e.u, e.v), a11 = dot(e.v, e.v);
    REAL h00 = a00 + dot(e.uu, r), h01 = a01 + dot(e.uv, r), h11 = a11 + dot(e.vv, r);
    bool curvesUp = h00 > REAL(0) && h00 * h11 - h01 * h01 > REAL(0);
    if (!curvesUp) {
      h00 = a00;
      h01 = a01;
      h11 = a11;
    }
    // A parameter on its bound with the gradient pushing outwards stays there; so does one on its
    // bound that the step would push out.
    bvec2 held = bvec2((x.x <= lo.x && g.x > REAL(0)) || (x.x >= hi.x && g.x < REAL(0)),
                       (x.y <= lo.y && g.y > REAL(0)) || (x.y >= hi.y && g.y < REAL(0)));
    REAL2 dx = REAL2(0);
    bool again = true;
    [[unroll]] for (int pass = 0; pass < 2; ++pass) if (again) {
      REAL det = h00 * h11 - h01 * h01;
      dx = REAL2(0);
      if (!held[0] && !held[1] && det > REAL(0)) {
        dx = REAL2(-(h11 * g.x - h01 * g.y) / det, -(h00 * g.y - h01 * g.x) / det);
      } else if (!held[0] && h00 > REAL(0) && (held[1] || det <= REAL(0))) {
        dx.x = -g.x / h00;
      } else if (!held[1] && h11 > REAL(0)) {
        dx.y = -g.y / h11;
      } else if (!held[0] || !held[1]) {
        // Singular (a pole): a gradient step across the piece.
        REAL gx = held[0] ? REAL(0) : g.x, gy = held[1] ? REAL(0) : g.y;
        REAL norm = sqrt(gx * gx + gy * gy);
        if (norm > REAL(0)) dx = REAL2(-gx / norm * (hi.x - lo.x), -gy / norm * (hi.y - lo.y));
      }
      again = false;
      [[unroll]] for (int k = 0; k < 2; ++k)
        if (!held[k] && ((x[k] <= lo[k] && dx[k] < REAL(0)) || (x[k] >= hi[k] && dx[k] > REAL(0)))) {
          held[k] = true;
          again = true;
        }
    }
    // Up to the rectangle's border, no further, landing on it exactly.
    REAL reach = REAL(1), border = REAL(0);
    int stops = -1;
    [[unroll]] for (int k = 0; k < 2; ++k) {
      REAL to = x[k] + dx[k];
      REAL bound = to < lo[k] ? lo[k] : (to > hi[k] ? hi[k] : to);
      if (bound != to && (bound - x[k]) / dx[k] < reach) {
        reach = (bound - x[k]) / dx[k];
        stops = k;
        border = bound;
      }
    }
    dx *= reach;
    REAL stepLength = max(abs(dx.x), abs(dx.y));
    bool trusted = curvesUp && !held.x && !held.y && stops < 0 && stepLength < params[kProjTrustedStep];
    if (stepLength < stepTolerance) {
      running = false;
    } else {
      REAL2 xn = x;
      REAL fn = f;
      LocalPoint en = e;
      int halvings = 0;
      bool halving = true;
      while (halving) {
        ++iterations;
        xn = clamp(x + dx, lo, hi);
        if (halvings == 0 && stops >= 0) xn[stops] = border;
        en = evaluatePatch(patchId, xn.x, xn.y);
        fn = dot(en.p - q, en.p - q);
        halving = !(fn <= f || trusted || ++halvings > kMaxHalvings || max(abs(dx.x), abs(dx.y)) < stepTolerance);
        dx *= REAL(0.5);
      }
      if (fn > f && !trusted) {
        running = false;
      } else {
        REAL moved = max(abs(xn.x - x.x), abs(xn.y - x.y));
        x = xn;
        e = en;
        r = en.p - q;
        f = fn;
        running = moved >= stepTolerance;
      }
    }
  }
  REAL h00 = dot(e.u, e.u) + dot(e.uu, r), h01 = dot(e.u, e.v) + dot(e.uv, r), h11 = dot(e.v, e.v) + dot(e.vv, r);
  settled = h00 > REAL(0) && h00 * h11 - h01 * h01 > REAL(0);
  return f;
}

// Distance from p to the segment [a, b] (core/trim_classifier.cpp distanceToSegment).
REAL distanceToSegment(REAL2 p, REAL2 a, REAL2 b) {
  REAL2 ab = b - a;
  REAL len2 = dot(ab, ab);
  REAL t = len2 > REAL(0) ? clamp(dot(p - a, ab) / len2, REAL(0), REAL(1)) : REAL(0);
  return length(p - (a + t * ab));
}

// Inside the face's trim loops (core/trim_classifier.cpp: even-odd, the tolerance band inside).
bool insideLoops(uint face, REAL2 p) {
  uint fi = pc.faceInts + kProjFaceInts * face, fr = pc.faceReals + kProjFaceReals * face;
  uint edgeFirst = ints[fi + kFaceTrimEdges], edgeCount = ints[fi + kFaceTrimEdges + 1u];
  if (edgeCount == 0u) return true;
  uint slabs = ints[fi + kFaceSlabs], slabStart = ints[fi + kFaceSlabs + 1u], slabEdges = ints[fi + kFaceSlabEdges];
  REAL v0 = params[fr + 2u], height = params[fr + 3u], tolerance = params[fr + 4u];
  uint s = uint(clamp(floor((p.y - v0) / height), REAL(0), REAL(slabs - 1u)));
  bool odd = false, onLoop = false;
  for (uint k = ints[slabStart + s]; k < ints[slabStart + s + 1u]; ++k) {
    ++iterations;
    uint e = pc.edgeReals + 4u * (edgeFirst + ints[slabEdges + k]);
    REAL2 a = REAL2(params[e], params[e + 1u]), b = REAL2(params[e + 2u], params[e + 3u]);
    if (distanceToSegment(p, a, b) <= tolerance) onLoop = true;
    if ((a.y <= p.y) != (b.y <= p.y)) {
      REAL u = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
      if (u > p.x) odd = !odd;
    }
  }
  return onLoop || odd;
}

struct Candidate {
  REAL d2;
  REAL3 point;
  REAL2 uv;  // face-relative global parameters
  uint face;
  bool boundary;
  uint i, j;
  REAL2 local;
  REAL3 du, dv;
};

Candidate noCandidate() {
  return Candidate(kNone, REAL3(0), REAL2(0), 0u, false, 0u, 0u, REAL2(0), REAL3(0), REAL3(0));
}

void solveRun(REAL3 q, uint run, out Candidate out_) {
  uint rr = pc.runReals + kProjRunReals * run;
  Segment s;
  s.kind = 1u;
  s.patchId = 0u;
  s.face = ints[pc.runInts + run];
  s.alongV = false;
  s.fixed_ = REAL(0);
  s.a = REAL2(params[rr], params[rr + 1u]);
  s.ab = REAL2(params[rr + 2u], params[rr + 3u]);
  REAL t0 = params[rr + 4u], t1 = params[rr + 5u];
  REAL t = REAL(0.5) * (t0 + t1);
  REAL3 foot;
  REAL f = newtonOnSegment(q, s, t0, t1, t, foot);
  uint fr = pc.faceReals + kProjFaceReals * s.face;
  REAL2 uv = clamp(s.a + t * s.ab, REAL2(0), REAL2(params[fr], params[fr + 1u]));
  out_ = Candidate(f, foot, uv, s.face, true, 0u, 0u, REAL2(0), REAL3(0), REAL3(0));
}

// The nearest point on the cell's loop pieces within bestD2 (kept in out_ if nearer).
void solveRuns(REAL3 q, uint cell, REAL bestD2, inout Candidate out_) {
  uint ci = pc.cellInts + kProjCellInts * cell;
  for (uint k = ints[ci + 4u]; k < ints[ci + 5u]; ++k) {
    ++iterations;
    uint run = ints[pc.runListInts + k];
    REAL d2 = boxDistance2(pc.runReals + kProjRunReals * run + 6u, q);
    if (d2 <= bestD2 && d2 <= out_.d2) {
      Candidate c;
      solveRun(q, run, c);
      if (c.d2 < out_.d2) out_ = c;
    }
  }
}

// Newton on cell `cell` over the local rectangle `range` (u0, u1, v0, v1): from where q falls on the
// cell's parallelogram, or from the rectangle's middle (`fromMiddle`); border sides searched where
// Newton ended on them, or all of them (`everySide`); outside the loops, the loop pieces instead.
bool solveCell(REAL3 q, uint cell, REAL4 range, bool fromMiddle, bool everySide, REAL bestD2, out Candidate out_) {
  uint ci = pc.cellInts + kProjCellInts * cell, cr = pc.cellReals + kProjCellReals * cell;
  uint face = ints[ci], patchId = ints[ci + 1u], borders = ints[ci + 6u];
  REAL2 lo = REAL2(range.x, range.z), hi = REAL2(range.y, range.w);
  REAL2 x = REAL2(0.5);
  if (!fromMiddle) {
    REAL3 d = q - real3At(cr + kCellMiddle), au = real3At(cr + kCellAlongU), av = real3At(cr + kCellAlongV);
    REAL a = dot(au, au), b = dot(au, av), c = dot(av, av), det = a * c - b * b;
    if (det > REAL(0)) {
      REAL pu = dot(d, au), pv = dot(d, av);
      x = clamp(REAL2(REAL(0.5) + (c * pu - b * pv) / det, REAL(0.5) + (a * pv - b * pu) / det), REAL2(0), REAL2(1));
    }
  }
  x = lo + x * (hi - lo);
  REAL2 start = x;
  LocalPoint e;
  bool settled;
  REAL f = newtonOnPatch(patchId, lo, hi, q, x, e, settled);
  // A side of the rectangle on the domain's border: it is a side of the cell that lies on it.
  REAL4 cellRange = REAL4(params[cr + kCellRange], params[cr + kCellRange + 1u], params[cr + kCellRange + 2u],
                          params[cr + kCellRange + 3u]);
  REAL tiny2 = params[kProjOnSurface2];
  for (uint side = 0u; side < 4u && f > tiny2; ++side) {
    ++iterations;
    bool alongV = side < 2u;
    REAL fixed_ = range[side];
    bool onBorder = (borders & (1u << side)) != 0u && fixed_ == cellRange[side];
    if (onBorder && (everySide || (alongV ? x.x : x.y) == fixed_)) {
      Segment s;
      s.kind = 0u;
      s.patchId = patchId;
      s.face = face;
      s.alongV = alongV;
      s.fixed_ = fixed_;
      s.a = REAL2(0);
      s.ab = REAL2(0);
      REAL t = alongV ? start.y : start.x;
      REAL3 foot;
      REAL fb = newtonOnSegment(q, s, alongV ? lo.y : lo.x, alongV ? hi.y : hi.x, t, foot);
      if (fb < f) {
        f = fb;
        x = alongV ? REAL2(fixed_, t) : REAL2(t, fixed_);
        e.p = foot;
        e.u = REAL3(0);
        e.v = REAL3(0);
      }
    }
  }
  REAL2 uv = REAL2(params[cr + kCellGlobal] + params[cr + kCellGlobal + 1u] * x.x,
                   params[cr + kCellGlobal + 2u] + params[cr + kCellGlobal + 3u] * x.y);
  if (insideLoops(face, uv)) {
    out_ = Candidate(f, e.p, uv, face, false, ints[ci + 2u], ints[ci + 3u], x, e.u, e.v);
    return settled;
  }
  out_ = noCandidate();
  solveRuns(q, cell, bestD2, out_);
  return settled;
}

Candidate best;

bool better(Candidate c) {
  if (c.d2 != best.d2) return c.d2 < best.d2;
  if (c.d2 >= kNone) return false;
  uint a = ints[pc.faceInts + kProjFaceInts * c.face + kFaceId];
  uint b = ints[pc.faceInts + kProjFaceInts * best.face + kFaceId];
  if (a != b) return a < b;
  if (c.uv.x != best.uv.x) return c.uv.x < best.uv.x;
  return c.uv.y < best.uv.y;
}

// No farther than the best point so far plus `slack` (negative: nearer by at least -slack).
bool within(REAL d2, REAL slack) {
  if (best.d2 >= kNone) return true;
  REAL reach = sqrt(best.d2) + slack;
  return reach >= REAL(0) && d2 <= reach * reach;
}

bool nearCentreOfCurvature(uint cell, REAL3 q, REAL d2) {
  uint cr = pc.cellReals + kProjCellReals * cell;
  REAL3 normal = cross(real3At(cr + kCellAlongU), real3At(cr + kCellAlongV));
  bool above = dot(q - real3At(cr + kCellMiddle), normal) >= REAL(0);
  return params[cr + kCellBends + (above ? 0u : 1u)] * sqrt(d2) >= kFocalFraction;
}

REAL4 cellRangeOf(uint cell) {
  uint cr = pc.cellReals + kProjCellReals * cell + kCellRange;
  return REAL4(params[cr], params[cr + 1u], params[cr + 2u], params[cr + 3u]);
}

REAL4 quarterOf(REAL4 r, uint k) {
  REAL um = REAL(0.5) * (r.x + r.y), vm = REAL(0.5) * (r.z + r.w);
  return REAL4((k & 1u) == 0u ? r.x : um, (k & 1u) == 0u ? um : r.y, (k & 2u) == 0u ? r.z : vm, (k & 2u) == 0u ? vm : r.w);
}

// A doubtful cell's second look: Newton in each quarter from its middle, every border side
// searched, and in the quarters of a quarter that is doubtful too (kSecondLookDepth = 2).
void secondLook(REAL3 q, uint cell) {
  REAL4 whole = cellRangeOf(cell);
  for (uint a = 0u; a < 4u; ++a) {
    ++iterations;
    REAL4 quarter = quarterOf(whole, a);
    Candidate c;
    bool settled = solveCell(q, cell, quarter, true, true, best.d2, c);
    if (better(c)) best = c;
    if (!settled || nearCentreOfCurvature(cell, q, c.d2))
      for (uint b = 0u; b < 4u; ++b) {
        ++iterations;
        Candidate c2;
        solveCell(q, cell, quarterOf(quarter, b), true, true, best.d2, c2);
        if (better(c2)) best = c2;
      }
  }
}

// One query's search: its hit written at `query`.
void search(uint query) {
  REAL3 q = queries[query].xyz;
  best = noCandidate();
  REAL solved = -params[kProjTolerance];
  uint flags = 0u;

  uint stack[kProjStackDepth];
  REAL stackBound[kProjStackDepth];
  int top = 0;
  stack[0] = 0u;
  stackBound[0] = boxDistance2(pc.nodeReals, q);
  top = 1;
  uint doubtful[kProjDoubtful];
  REAL doubtfulBound[kProjDoubtful];
  uint doubtfulCount = 0u;
  while (top > 0) {
    ++iterations;
    --top;
    uint node = stack[top];
    if (within(stackBound[top], solved)) {
      uint ni = pc.nodeInts + 4u * node;
      uint count = ints[ni + 1u];
      if (count == 0u) {
        // Children nearest first: the farther pushed first.
        uint near_ = node + 1u, far_ = ints[ni + 2u];
        REAL dNear = boxDistance2(pc.nodeReals + 6u * near_, q), dFar = boxDistance2(pc.nodeReals + 6u * far_, q);
        if (dFar < dNear) {
          uint n = near_;
          near_ = far_;
          far_ = n;
          REAL d = dNear;
          dNear = dFar;
          dFar = d;
        }
        if (top + 2 > int(kProjStackDepth)) {
          flags |= kHitRedo;
          top = 0;
        } else {
          if (within(dFar, solved)) {
            stack[top] = far_;
            stackBound[top++] = dFar;
          }
          if (within(dNear, solved)) {
            stack[top] = near_;
            stackBound[top++] = dNear;
          }
        }
      } else if (count > kMaxLeaves) {
        flags |= kHitRedo;
        top = 0;
      } else {
        // The node's leaves nearest bound first, while their bound is near enough.
        uint first = ints[ni];
        uint order[kMaxLeaves];
        REAL bound[kMaxLeaves];
        for (uint k = 0u; k < count; ++k) {
          ++iterations;
          REAL b = leafBound(first + k, q);
          uint at = k;
          while (at > 0u && bound[at - 1u] > b) {
            ++iterations;
            bound[at] = bound[at - 1u];
            order[at] = order[at - 1u];
            --at;
          }
          bound[at] = b;
          order[at] = first + k;
        }
        bool open_ = true;
        for (uint k = 0u; k < count; ++k) {
          ++iterations;
          open_ = open_ && within(bound[k], solved);
          if (open_) {
            uint cell = ints[pc.leafInts + order[k]];
            Candidate c;
            bool settled = solveCell(q, cell, cellRangeOf(cell), false, false, best.d2, c);
            if (better(c)) best = c;
            if (!settled || nearCentreOfCurvature(cell, q, c.d2)) {
              if (doubtfulCount < kProjDoubtful) {
                doubtful[doubtfulCount] = cell;
                doubtfulBound[doubtfulCount++] = bound[k];
              } else if (best.d2 > params[kProjOnSurface2]) {
                secondLook(q, cell);  // the list is full: look now
              }
            }
          }
        }
      }
    }
  }
  if ((flags & kHitRedo) == 0u && best.d2 > params[kProjOnSurface2])
    for (uint k = 0u; k < doubtfulCount; ++k) {
      ++iterations;
      if (within(doubtfulBound[k], solved)) secondLook(q, doubtful[k]);
    }

  if (iterations > pc.loopBudget) flags |= kHitRedo;
  if (best.d2 < kNone) flags |= kHitFound;
  if (best.boundary) flags |= kHitBoundary;
  uint hr = kProjHitReals * query, hi = kProjHitInts * query;
  hitReals[hr] = best.d2 < kNone ? best.d2 : REAL(0);
  hitReals[hr + 1u] = best.point.x;
  hitReals[hr + 2u] = best.point.y;
  hitReals[hr + 3u] = best.point.z;
  hitReals[hr + 4u] = best.uv.x;
  hitReals[hr + 5u] = best.uv.y;
  hitReals[hr + 6u] = best.local.x;
  hitReals[hr + 7u] = best.local.y;
  hitReals[hr + 8u] = best.du.x;
  hitReals[hr + 9u] = best.du.y;
  hitReals[hr + 10u] = best.du.z;
  hitReals[hr + 11u] = best.dv.x;
  hitReals[hr + 12u] = best.dv.y;
  hitReals[hr + 13u] = best.dv.z;
  hitReals[hr + 14u] = REAL(0);
  hitReals[hr + 15u] = REAL(0);
  hitInts[hi] = best.face;
  hitInts[hi + 1u] = best.i;
  hitInts[hi + 2u] = best.j;
  hitInts[hi + 3u] = flags;
}

void main() {
  uint query = flatInvocation();
  if (query < pc.queryCount) search(query);
}
