#pragma once
// Internal to host/gpu: the grid and list runs that the curve and surface evaluators share (the
// α-EB vertex pass, basis tables, the chunk loop streaming through a vk::SubmitRing, list chunks)
// and the push-constant blocks of a model.
#include <shapespline/core/sample_grid.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/gpu/kernels.h>
#include <shapespline/gpu/knot_grid_table.h>
#include <shapespline/shaders/layout.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/pipeline.h>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <optional>
#include <vector>

namespace shapespline::gpu {

class PlanePool;

// A descriptor set of `pipe` with every binding at the dummy buffer (validation wants a valid
// descriptor for bindings a variant does not use).
vk::DescriptorSet makeSet(KernelSet& k, const vk::ComputePipeline& pipe);
// Records the α-EB vertex pass (alpha_eb_vertices.comp: nodes and V points from the current PARAMS)
// of `m` and a compute barrier. `set` (the model's NET, PARAMS, VERTS) is made on first use; the
// caller keeps it alive until the command buffer has run.
void recordAlphaEBVertices(KernelSet& k, const GpuModel& m, bool surface, VkCommandBuffer cmd, vk::DescriptorSet& set);
// A buffer of `reals` REALs rounded up to whole REAL4 (the shaders' REAL4 view covers every value).
size_t realBufferBytes(const KernelSet& k, size_t reals);
vk::Buffer realBuffer(KernelSet& k, size_t reals, vk::MemoryUse use, const char* label);

// Constants of basis_table.comp for one basis.
SpecValues basisTableSpec(const SpanBasis& b);

// Throws std::invalid_argument when the evaluator and the model have different precisions.
void checkPrecision(const KernelSet& k, const GpuModel& m);

// Records basis_table.comp for one direction (coefficients at coefOffset) into `table`.
void recordTable(KernelSet& k, const GpuModel& m, const SpanBasis& b, uint32_t coefOffset, uint32_t samples,
                 uint32_t tableOffset, const vk::Buffer& table, VkCommandBuffer cmd,
                 std::vector<vk::DescriptorSet>& keep);

// Push constants of a model (items and samples left to the caller).
layout::EvalPush curvePush(const GpuCurve& c);
layout::KnotEvalPush knotPush(const GpuModel& m, uint32_t itemsV, uint32_t netCols);

template <class Push>
struct GridJob {
  Kernel kernel;
  bool surface;
  bool knotVector;  // no device-built basis table: see knotTable
  FieldMask allowed;
  Push push;  // model part filled in; chunk part set per chunk
  size_t itemTotal;
  // Knot vectors: the host-built TABLE of bspline_*_grid.comp, or null for bspline_*_eval.comp
  // (de Boor-Cox per point).
  const KnotGridTable* knotTable = nullptr;
};

// The knot grid job of `m` on `grid`: bspline_*_grid.comp with its table where
// knotGridTable builds one within the device's buffer range and 64 MiB, else bspline_*_eval.comp.
// `table` keeps the table for the job's life.
GridJob<layout::KnotEvalPush> knotGridJob(const KernelSet& k, const GpuCurve& c, const GridSpec& grid,
                                          std::optional<KnotGridTable>& table);
GridJob<layout::KnotEvalPush> knotGridJob(const KernelSet& k, const GpuSurface& s, const GridSpec& grid,
                                          std::optional<KnotGridTable>& table);

// A knot-vector surface's grid job on surface_grid.comp, each non-empty interval pair evaluated as
// a patch from its power-basis coefficients (shaders/layout.h knot patches; rational: homogeneous
// sums and the quotient rule), where
// that gives the CPU's values: samplesV a multiple of 4 and every interior knot as smooth as the
// highest partial asked (where a partial jumps, the CPU evaluates an interval's last sample on the
// next interval, which bspline_surface_grid.comp's table does too). Otherwise nullopt.
std::optional<GridJob<layout::EvalPush>> knotPatchGridJob(const GpuSurface& s, const GridSpec& grid, FieldMask fields);

// A grid job chunk by chunk (gpu/chunk_plan.h), two chunks in flight: the consumer reads chunk k
// while the GPU computes k+1. Instantiated for layout::EvalPush and layout::KnotEvalPush.
template <class Push>
void runGrid(KernelSet& k, PlanePool& pool, GpuModel& m, const GridJob<Push>& job, const GridSpec& grid,
             FieldMask fields, const ChunkConsumer& consumer, size_t maxPlaneBytes);

// List mode: packed SAMPLES (gpu/list_packing.h) -> planes of every field in `fields`, read back
// as doubles (3 per sample, empty for fields not asked).
template <class Push>
std::vector<std::vector<double>> runList(KernelSet& k, GpuModel& m, Kernel kernel, bool surface, FieldMask fields,
                                         Push push, const std::vector<layout::ListSampleD>& samples,
                                         size_t maxPlaneBytes);

}  // namespace shapespline::gpu
