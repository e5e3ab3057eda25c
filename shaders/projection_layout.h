// The tables of closest_points.comp (docs/math.md "Closest points", on the GPU): a projection tree
// (host/part/projection_tree.h) flattened into one array of REALs (PARAMS), one of uints (INTS) and
// the patches' centred power forms (NET, REAL4), by part/projection_tables.cpp. One source compiled
// as GLSL and as C++, as layout.h is. Every position is relative to the tree's centre (origin), so
// that fp32 keeps the digits of a part far from 0; every face's parameters are relative to the
// low corner of its domain for the same reason.
//
// REALs (params[]):
//   header      kProjHeaderReals: tolerance, diagonal, step tolerance (local units), on-surface
//               distance (squared), trusted Newton step (local units)
//   node n      at pc.nodeReals + 6n: box lo, hi
//   leaf k      at pc.leafReals + 6k: box lo, hi
//   cell c      at pc.cellReals + kProjCellReals c: see kCell* below
//   run r       at pc.runReals + kProjRunReals r: loop point a (face-relative), the segment's
//               vector ab, t0, t1, box lo, hi
//   face f      at pc.faceReals + kProjFaceReals f: domain size U, V (from the low corner), the trim
//               classifier's v0 and slab height, its tolerance
//   trim edges  at pc.edgeReals + 4e: a, b (face-relative)
//   breaks      each face's patch boundaries in U then V (face-relative), at the offsets its INTS give
// INTs (ints[]):
//   node n      at pc.nodeInts + 4n: first leaf, leaf count (0: an inner node: its children are
//               n + 1 and the right child), right child, 0
//   leaf k      at pc.leafInts + k: its cell
//   cell c      at pc.cellInts + kProjCellInts c: face, patch, model patch i, j, first and end of
//               its runs in the run list, border sides (bit s: side s lies on the domain's border:
//               0 u = u0, 1 u = u1, 2 v = v0, 3 v = v1), 0
//   patch p     at pc.patchInts + 4p: degree n, m, first coefficient (NET index), rational; every
//               patch's coefficients padded with zeros to the tree's largest degrees (NET holds
//               (degreeU + 1) x (degreeV + 1) per patch, row-major by the power of u), which the
//               kernel takes as POLY_DEGREE_U / POLY_DEGREE_V
//   run list    at pc.runListInts: run indices, cell by cell
//   run r       at pc.runInts + r: its face
//   face f      at pc.faceInts + kProjFaceInts f: see kFace* below
// Results: one ProjectionHit per query (RESULT), REALs and uints apart (RESULT_REALS, RESULT_INTS).
#ifndef SHAPESPLINE_SHADERS_PROJECTION_LAYOUT_H
#define SHAPESPLINE_SHADERS_PROJECTION_LAYOUT_H

#ifdef SHAPESPLINE_GLSL
#ifndef uint32_t
#define uint32_t uint
#endif
#define PL_CONST(type, name, value) const type name = value
#define PL_UINT uint
#else
#include <cstddef>
#include <cstdint>
namespace shapespline::gpu::projection_layout {
#define PL_CONST(type, name, value) inline constexpr type name = value
#define PL_UINT uint32_t
#endif

// Bindings (set 0): the tables share NET and PARAMS with layout.h's numbering.
PL_CONST(uint32_t, kProjBindingCoefficients, 0u);  // = layout.h kBindingNet
PL_CONST(uint32_t, kProjBindingReals, 1u);         // = kBindingParams
PL_CONST(uint32_t, kProjBindingInts, 2u);
PL_CONST(uint32_t, kProjBindingQueries, 3u);   // REAL4 per query (xyz relative to the origin)
PL_CONST(uint32_t, kProjBindingHitReals, 4u);  // kProjHitReals REALs per query
PL_CONST(uint32_t, kProjBindingHitInts, 5u);   // kProjHitInts uints per query
PL_CONST(uint32_t, kProjBindingCount, 6u);

PL_CONST(uint32_t, kProjHeaderReals, 5u);
PL_CONST(uint32_t, kProjTolerance, 0u);
PL_CONST(uint32_t, kProjDiagonal, 1u);
PL_CONST(uint32_t, kProjStepTolerance, 2u);
PL_CONST(uint32_t, kProjOnSurface2, 3u);
PL_CONST(uint32_t, kProjTrustedStep, 4u);

PL_CONST(uint32_t, kProjCellReals, 34u);
PL_CONST(uint32_t, kCellRange, 0u);    // u0, u1, v0, v1 in the patch's local parameters
PL_CONST(uint32_t, kCellGlobal, 4u);   // U = a + b u, V = c + d v (face-relative): a, b, c, d
PL_CONST(uint32_t, kCellMiddle, 8u);   // the corners' parallelogram: middle, alongU, alongV
PL_CONST(uint32_t, kCellAlongU, 11u);
PL_CONST(uint32_t, kCellAlongV, 14u);
PL_CONST(uint32_t, kCellBends, 17u);   // bendsUp, bendsDown
PL_CONST(uint32_t, kCellAxes, 19u);    // the oriented box: three axes, then lo[3], hi[3]
PL_CONST(uint32_t, kCellLo, 28u);
PL_CONST(uint32_t, kCellHi, 31u);
PL_CONST(uint32_t, kProjCellInts, 8u);

PL_CONST(uint32_t, kProjRunReals, 12u);

PL_CONST(uint32_t, kProjFaceReals, 5u);
PL_CONST(uint32_t, kProjFaceInts, 10u);
PL_CONST(uint32_t, kFaceTrimEdges, 0u);   // first trim edge (global), count (0: no loops)
PL_CONST(uint32_t, kFaceSlabs, 2u);       // slab count, INTS offset of slab starts (slabs + 1)
PL_CONST(uint32_t, kFaceSlabEdges, 4u);   // INTS offset of the slab edge lists (edge indices of the face)
PL_CONST(uint32_t, kFaceBreaks, 5u);      // REALS offset of the U breaks (count U + 1, then V's count V + 1)
PL_CONST(uint32_t, kFaceCountU, 6u);      // patches (non-empty intervals) along U
PL_CONST(uint32_t, kFaceCountV, 9u);      // ... along V
PL_CONST(uint32_t, kFacePatchTable, 7u);  // INTS offset of the tree patch of each (a, b), row-major
PL_CONST(uint32_t, kFaceId, 8u);          // the face's id (ties go to the lower id)

// Hit: what the search found for one query, the fields of part::ClosestPoints' candidate.
PL_CONST(uint32_t, kProjHitReals, 16u);  // d2, point xyz, U, V (face-relative), local u, v, du xyz, dv xyz, 0, 0
PL_CONST(uint32_t, kProjHitInts, 4u);    // face (tree index), model patch i, j, flags
PL_CONST(uint32_t, kHitFound, 1u);       // a point inside the loops was found
PL_CONST(uint32_t, kHitBoundary, 2u);    // on a trim loop
PL_CONST(uint32_t, kHitRedo, 4u);        // past the kernel's stack or loop budget: the host redoes it
PL_CONST(uint32_t, kProjStackDepth, 64u);
PL_CONST(uint32_t, kProjDoubtful, 16u);

struct ProjectionPush {
  PL_UINT nodeReals, leafReals, cellReals, runReals, faceReals, edgeReals;
  PL_UINT nodeInts, leafInts, cellInts, patchInts, runListInts, runInts, faceInts;
  PL_UINT queryCount;  // queries in this dispatch
  PL_UINT loopBudget;  // loop iterations a query may run before it is flagged kHitRedo
  PL_UINT pad0;
};

#ifndef SHAPESPLINE_GLSL
static_assert(sizeof(ProjectionPush) == 64);
}  // namespace shapespline::gpu::projection_layout
#endif

#undef PL_UINT
#undef PL_CONST
#endif  // SHAPESPLINE_SHADERS_PROJECTION_LAYOUT_H
