#pragma once
// Small well-conditioned models shared by tests: the GPU tests that change parameters and compare
// with the CPU (gpu_update_test, gpu_model_sync_test), and the CPU sampler's chunking and record tests.
#include <shapespline/core/model.h>

namespace shapespline::test {

// An α-EB tube: rows x cols points, rows along x (open in u), each row a unit circle in y-z
// (closed in v) lifted by 0.1 per row; degree 5, λ = 0, α = 0.5 everywhere.
SurfaceModel alphaEBTube(int rows, int cols);

// An open n x n net of `family`: point (i, j) near (i, j, sin 0.9i cos 0.7j), each coordinate
// moved by up to 0.3 (a fixed seed), all times `scale`; α drawn from [0.05, 1) when `alpha`.
SurfaceModel wavyNet(FamilySpec family, int n, bool alpha, double scale = 1.0);

// The quadratic NURBS circle of 9 control points (the square's corners and edge midpoints, the
// corners weighted √2/2, knots 0,0,0,¼,¼,½,½,¾,¾,1,1,1; docs/math.md §10.8): exactly the circle of
// `radius` about the origin, 2-D.
CurveModel nurbsCircle(double radius);
// The torus of revolution of that circle: tube radius r at distance R from the z axis,
// P_ij = ((R + r d_j.x) c_i.x, (R + r d_j.x) c_i.y, r d_j.y), w_ij = w_i w_j (9 x 9 net).
SurfaceModel nurbsTorus(double R, double r);

}  // namespace shapespline::test
