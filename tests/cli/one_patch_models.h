#pragma once
// The smallest models of the memory-bound tests (tests/cli/memory_bound_test.cpp: the bytes do not
// depend on where the rows are cut; tests/memory/cli_rss_test.cpp: peak RSS), as model JSON text.

namespace shapespline::test {

// One bicubic patch (uniform B-spline, 4 x 4 net) and one cubic span (4 points).
inline constexpr const char* kOnePatch =
    R"({"kind": "surface", "construction": "bspline", "order": 4, "points": [)"
    R"([[0,0,0],[0,1,0.5],[0,2,0],[0,3,0.2]], [[1,0,0.5],[1,1,1.5],[1,2,0.5],[1,3,0]],)"
    R"([[2,0,0],[2,1,0.5],[2,2,2],[2,3,0.5]], [[3,0,-0.5],[3,1,0],[3,2,0.5],[3,3,1.5]]]})";
inline constexpr const char* kOneSpan =
    R"({"kind": "curve", "construction": "bspline", "order": 4, "points": [[0,0,0],[1,2,0.5],[2,-1,0],[3,1,1]]})";

}  // namespace shapespline::test
