#pragma once
// Options shared by the GPU evaluators (gpu/curve_evaluator.h, gpu/surface_evaluator.h,
// gpu/basis_table_evaluator.h).
#include <cstddef>
#include <cstdint>

namespace shapespline::gpu {

struct EvaluatorOptions {
  uint32_t workgroupSize = 64;                 // spec constant of every kernel
  // Bytes per output plane and chunk (items larger than this go in row ranges; only one granule
  // of rows, at most 16 rows of a patch or 64 samples of a span, may exceed it). Small planes stay
  // resident between chunks: 64 MiB planes cost ~1e5 first-touch page faults per 15 M-point job on
  // lavapipe and halved its throughput (measured 2–4 MiB: 113–124 vs 27–59 Mpts/s fp32).
  size_t maxPlaneBytes = size_t(4) << 20;
  // Store fp32 output planes as uint64 pairs where the device has shaderInt64 (half the stores on
  // llvmpipe; the same bytes). Off: the plain float stores every device runs (tests cover both).
  bool packedStores = true;
};

}  // namespace shapespline::gpu
