#pragma once
// Small well-conditioned models shared by the GPU tests that change parameters and compare with
// the CPU (gpu_update_test, gpu_model_sync_test).
#include <shapespline/core/model.h>

namespace shapespline::test {

// An α-EB tube: rows x cols points, rows along x (open in u), each row a unit circle in y-z
// (closed in v) lifted by 0.1 per row; degree 5, λ = 0, α = 0.5 everywhere.
SurfaceModel alphaEBTube(int rows, int cols);

}  // namespace shapespline::test
