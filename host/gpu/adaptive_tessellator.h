#pragma once
// AdaptiveTessellator: screen-space adaptive tessellation of a GpuSurface driven by the GPU. Each
// record() chooses every patch's rates from the camera and a pixel tolerance, lays the mesh out,
// evaluates its vertices and writes its indices and a VkDrawIndexedIndirectCommand, all in the
// caller's command buffer: no read-back and no host work per frame (docs/tessellation.md).
//
// Passes of record(), in one command buffer:
//  (1) the α-EB vertex pass (as SurfaceTessellator);
//  (2) rates (tess_adaptive_rates.comp, one invocation per patch): the exact screen-space second
//      derivatives of the projected patch on a probe grid (evaluated row-wise) give the rates
//      (n, m) for which the piecewise-linear mesh stays within the tolerance (the bound is stated
//      in docs/tessellation.md); integer rates in [2, maxRate], with hysteresis against the
//      previous frame's rates (kept on the GPU); patches entirely outside the frustum take rate 2;
//  (3) layout (tess_adaptive_layout.comp, one workgroup): edge rates = the max of the two patches'
//      rates along the edge (so both sides of an edge read one rate: crack-free by construction),
//      prefix sums of vertex, index and row counts, the indirect draw command and the indirect
//      dispatch of the interior rows;
//  (4) mesh (tess_adaptive_mesh.comp): every corner, edge point and interior point once, shared
//      ones from their canonical patch with the normalised mean normal (as SurfaceTessellator);
//      edges along their edge and interiors by rows (shaders/patch_rows.glsl); each edge
//      invocation writes the transition rings of the patch sides along it, each interior-row
//      invocation the quads between its rows (tess_adaptive_triangles.glsl);
//  (5) a barrier: shader writes -> VERTEX_ATTRIBUTE_READ | INDEX_READ | INDIRECT_COMMAND_READ.
// The mesh of a frame is exactly buildTessTopology(rates) of core/tess_topology.h (same vertex
// numbering, same triangles), with the vertex layout of shaders/tess_layout.h.
//
// Synchronisation and setters as SurfaceTessellator: record() starts with a barrier against
// earlier vertex-input, indirect and compute reads in the same queue; GpuSurface setters only when
// no submitted command buffer that uses the surface is executing.
#include <shapespline/core/tess_topology.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/shaders/tess_layout.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/context.h>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace shapespline::vk {
class PassTimer;  // vk/timestamps.h (profiling only; not an installed header)
}  // namespace shapespline::vk

namespace shapespline::gpu {

// The view a frame is tessellated for: clip = viewProj * (model-space position, 1), Vulkan clip
// conventions (as render::Camera::viewProj()), column-major as GLM stores it.
struct AdaptiveView {
  std::array<float, 16> viewProj{};
  float viewportWidth = 0.0f, viewportHeight = 0.0f;  // pixels
};

struct AdaptiveOptions {
  float tolerancePx = 1.0f;  // screen-space distance bound between mesh and surface, > 0
  int maxRate = 64;          // rates are clamped to [2, maxRate]; buffers are sized for maxRate
  // A rate is raised as soon as the bound needs it and lowered only when the needed rate r falls
  // so far that ceil(r * (1 + hysteresis)) is below it; 0 follows the needed rate exactly.
  float hysteresis = 0.25f;
  int probeRate = 4;         // (probeRate + 1)^2 second-derivative samples per patch
  float safety = 1.25f;      // the sampled second-derivative maxima are multiplied by this
  bool cull = true;          // patches outside the frustum take rate 2
};

// Per-frame figures written by the GPU (read back only on request).
struct AdaptiveStats {
  uint32_t vertexCount = 0, indexCount = 0;
  uint32_t culledPatches = 0;   // outside the frustum
  uint32_t clampedPatches = 0;  // needed more than maxRate (the bound does not hold there)
  uint32_t nearPatches = 0;     // crossing the camera plane (rate maxRate)
};

class AdaptiveTessellator {
 public:
  // The surface must outlive the tessellator and share its context (fp32 or fp64 evaluation;
  // vertices are fp32 either way). Knot-vector B-splines: the patches are the non-empty knot
  // interval pairs (shaders/layout.h knot patches), rational or not. Throws std::invalid_argument
  // for a bad option (naming it and its rule), std::length_error when maxRate's
  // worst-case mesh exceeds the device's storage-buffer range or 2^32 indices.
  AdaptiveTessellator(std::shared_ptr<vk::Context> ctx, GpuSurface& surface, AdaptiveOptions options = {});
  ~AdaptiveTessellator();
  AdaptiveTessellator(const AdaptiveTessellator&) = delete;
  AdaptiveTessellator& operator=(const AdaptiveTessellator&) = delete;

  const AdaptiveOptions& options() const { return options_; }
  // tolerancePx, hysteresis, safety, cull and probeRate take effect at the next record(); a
  // different maxRate reallocates (waits for the queue to be idle). Throws as the constructor.
  void setOptions(const AdaptiveOptions& options);
  // Forgets the previous frame's rates: the next record() takes the needed rates without hysteresis.
  void resetRates();

  // Records passes (1)-(5) for `view` into cmd (see the header comment). With a timer, the passes
  // are timed on the GPU (profiling: timer->passes() once the submission has completed).
  void record(VkCommandBuffer cmd, const AdaptiveView& view, vk::PassTimer* timer = nullptr);
  // Binds vertexBuffer() (binding 0) and indexBuffer() and draws the last recorded mesh with
  // vkCmdDrawIndexedIndirect; inside a render pass whose pipeline uses vertexBinding().
  void recordDraw(VkCommandBuffer cmd) const;

  const vk::Buffer& vertexBuffer() const { return vertices_; }
  const vk::Buffer& indexBuffer() const { return indices_; }
  // One VkDrawIndexedIndirectCommand at offset 0.
  const vk::Buffer& indirectBuffer() const { return indirect_; }
  uint32_t maxVertexCount() const { return maxVertices_; }
  uint32_t maxIndexCount() const { return maxIndices_; }
  int patchesU() const { return patchesU_; }
  int patchesV() const { return patchesV_; }

  // Inspection (tests, bench, the viewer's counters): waits for the queue to be idle and reads the
  // last recorded frame back. Not for the frame loop.
  AdaptiveStats stats() const;
  TessRates rates() const;  // patch rates of the last frame (edges: the max of their patches)
  struct Mesh {
    TessRates rates;
    std::vector<tess_layout::TessVertex> vertices;
    std::vector<uint32_t> indices;
  };
  Mesh mesh() const;

 private:
  void allocate();
  struct Impl;
  std::shared_ptr<vk::Context> ctx_;
  GpuSurface& surface_;
  AdaptiveOptions options_;
  int patchesU_ = 0, patchesV_ = 0;
  bool closedU_ = false, closedV_ = false;
  uint32_t maxVertices_ = 0, maxIndices_ = 0;
  vk::Buffer vertices_, indices_, indirect_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace shapespline::gpu
