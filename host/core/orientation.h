#pragma once
// Which way a closed surface faces: the sign of the volume its du x dv-oriented triangles enclose.
#include <shapespline/core/surface.h>

namespace shapespline {

// Signed volume enclosed by the triangles of `samples` x `samples` points per patch, wound
// counter-clockwise in (u, v) (front-facing towards du x dv), by the divergence theorem: the sum
// of p0 . (p1 x p2) / 6. Positive when du x dv points outwards. Meaningful for surfaces closed in
// u and v (a torus); CPU fp64.
double signedVolume(const Surface& surface, int samples = 5);

}  // namespace shapespline
