#pragma once
// All GPU evaluators (OpenSubdiv style), one per header: each holds the compiled pipelines of one precision and
// evaluates any GpuCurve / GpuSurface (gpu_model.h) of that precision. Kernels: shaders/*.comp,
// buffer layouts: shaders/layout.h, math: docs/math.md §1–§6 mirrored from host/core.
//
// Grid jobs (core/sample_grid.h) run chunk by chunk: a chunk is a whole number of spans/patches
// whose output planes each fit in EvaluatorOptions::maxPlaneBytes, or, for an item larger than
// that, a range of its rows (whole kernel invocations: a span of up to 256 samples is never cut),
// so device and host memory stay bounded whatever the job or grid size; the consumer sees each
// chunk once, in order, while the output buffers are mapped. Two output slots stream: the GPU computes chunk
// k+1 while the consumer reads chunk k, so device + host memory stay at 2 chunks of planes
// (2 x fields x maxPlaneBytes) however many points the job has. The evaluator keeps those planes
// for its next grid job (gpu/plane_pool.h); an evaluator is used by one thread at a time.
#include <shapespline/gpu/basis_table_evaluator.h>
#include <shapespline/gpu/curve_evaluator.h>
#include <shapespline/gpu/evaluator_options.h>
#include <shapespline/gpu/surface_evaluator.h>
