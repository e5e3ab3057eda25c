#pragma once
// Test nets whose normals need the docs/math.md §5.3 fallbacks, shared by the evaluator and tessellator
// tests.
#include <shapespline/core/model.h>

namespace shapespline::test {

// A 7 x 5 Xu–Wang degree-4 net whose first four rows sit at the origin: patch row 0 collapses to
// a point (every normal is the fixed axis) and the u = 0 row of patch row 1 is a pole (Q_v = 0:
// the shifted rule). Whole grid rows need the fallback.
SurfaceModel collapsedRowsNet();

}  // namespace shapespline::test
