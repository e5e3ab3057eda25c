#pragma once
// SurfaceTessellator: turns a GpuSurface (any construction: α-EB, extended B-spline, GB, UBP,
// GUBP, B-splines with or without knot vectors and weights) into a triangle mesh on the GPU,
// recorded into the caller's command buffer and written into the caller's vertex and index
// buffers, ready for vkCmdDrawIndexed. Its patch grid is gridItemsU() x gridItemsV(): the
// surface's patches, or the non-empty knot interval pairs of a knot-vector B-spline.
//
// Per rate configuration (constructor / setRates, host side, once): the topology of
// core/tess_topology.h (every unique vertex evaluated once: watertight, bitwise identical shared
// edges; per-patch and per-edge rates; transition rings, no T-junctions), the grid pass's patch and
// row records, the sources of the shared vertices and the uint32 triangle index buffer are built
// and uploaded.
// Per record(): (1) the α-EB vertex pass (alpha_eb_vertices.comp) from the current PARAMS,
// (2) only when some edge rate differs from its patch's rate: surface_eval.comp in list mode over
// the edge points that are not on their patch's grid, (3) tessellate_grid.comp: every patch's
// (n+1) x (m+1) grid, interior vertices straight into the target vertex buffer, perimeter samples
// into a scratch buffer, (4) tessellate_pack.comp: the corner and edge vertices from those,
// (5) the index copy into a target index buffer that has not received this configuration yet,
// (6) a barrier: shader/transfer writes -> VERTEX_ATTRIBUTE_READ | INDEX_READ at VERTEX_INPUT.
// Knot-vector surfaces: the grid pass evaluates interval pair (i, j) as patch (i, j) from its
// power-basis coefficients (shaders/layout.h knot patches; rational ones from the homogeneous net
// and the quotient rule), pass (2) uses bspline_surface_eval.comp. Vertex uv is the global parameter: patch index + local for uniform
// families, the knot parameters here.
// A λ / α / control-point change on the GpuSurface (setLambda, setAlpha(s), updateControlPoint)
// therefore shows at the next record() without re-uploading the net.
//
// Shared vertices: position from one canonical patch (the lower patch index); normal = normalised
// mean of the per-patch docs/math.md §5.3 normals of every patch containing the vertex. At regular points
// these agree (C² surface); at an α = 1 vertex it is the mean of the patches' diagonal limits.
//
// Synchronisation: record() starts with a barrier against earlier vertex-input reads and compute
// work in the same queue. The GpuSurface parameter setters write host-visible memory directly: call
// them only when no submitted command buffer that uses this surface is still executing.
// Limits: the vertex buffer must fit in maxStorageBufferRange (lavapipe: 128 MiB, about 4 M
// vertices); target vertexOffset must be a multiple of minStorageBufferOffsetAlignment.
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/core/tess_topology.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/context.h>
#include <shapespline/vk/pipeline.h>
#include <shapespline/shaders/tess_layout.h>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <utility>

namespace shapespline::gpu {

class KernelSet;

// Usage the caller's buffers need.
inline constexpr VkBufferUsageFlags kTessVertexBufferUsage =
    VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
inline constexpr VkBufferUsageFlags kTessIndexBufferUsage =
    VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

// Where record() writes: vertexCount() * 32 bytes at vertexOffset, indexCount() uint32 at indexOffset.
struct TessTargets {
  VkBuffer vertexBuffer = VK_NULL_HANDLE;
  VkDeviceSize vertexOffset = 0;
  VkBuffer indexBuffer = VK_NULL_HANDLE;
  VkDeviceSize indexOffset = 0;
};

struct TessellatorOptions {
  uint32_t workgroupSize = 64;
  // Write vertices as uint64 pairs of floats where the device has shaderInt64 (half the stores on
  // llvmpipe; the same bytes); off: plain vec4 stores.
  bool packedStores = true;
};

class SurfaceTessellator {
 public:
  // The surface must outlive the tessellator and share its context and precision (fp32 or fp64
  // evaluation; vertices are fp32 either way).
  SurfaceTessellator(std::shared_ptr<vk::Context> ctx, GpuSurface& surface, const TessRates& rates,
                     TessellatorOptions options = {});
  ~SurfaceTessellator();
  SurfaceTessellator(const SurfaceTessellator&) = delete;
  SurfaceTessellator& operator=(const SurfaceTessellator&) = delete;

  // The patch grid of `surface` with every patch and edge at `rate` segments.
  static TessRates uniformRates(const GpuSurface& surface, int rate);

  // New rate configuration: rebuilds topology, sample list and index buffer (host work + upload).
  // Waits for the device to be idle on this context's queue before freeing the old buffers.
  void setRates(const TessRates& rates);

  const TessTopology& topology() const { return topo_; }
  uint32_t vertexCount() const { return topo_.vertexCount; }
  uint32_t indexCount() const { return uint32_t(topo_.indices.size()); }
  VkDeviceSize vertexBytes() const;
  VkDeviceSize indexBytes() const { return VkDeviceSize(indexCount()) * 4; }
  // Increments with every setRates (index buffers are rebuilt only then).
  uint64_t configuration() const { return generation_; }

  // Records the tessellation into cmd (see the header comment). Throws std::invalid_argument for a
  // null vertex buffer or a misaligned vertex offset; indexBuffer may be null (indices not copied).
  void record(VkCommandBuffer cmd, const TessTargets& targets);
  // The same into the tessellator's own buffers (vertexBuffer(), indexBuffer()).
  void record(VkCommandBuffer cmd);
  const vk::Buffer& vertexBuffer() const { return ownVertices_; }
  const vk::Buffer& indexBuffer() const { return indices_; }

  // Vertex input description of the vertex layout (shaders/tess_layout.h): position, normal, uv at
  // locations firstLocation .. firstLocation + 2.
  static VkVertexInputBindingDescription vertexBinding(uint32_t binding = 0);
  static std::array<VkVertexInputAttributeDescription, 3> vertexAttributes(uint32_t binding = 0,
                                                                           uint32_t firstLocation = 0);

 private:
  struct TargetSets;
  TargetSets& targetSets(VkBuffer vertices, VkDeviceSize offset);
  const vk::ComputePipeline& gridPipeline();
  const vk::ComputePipeline& packPipeline();

  std::shared_ptr<vk::Context> ctx_;
  GpuSurface& surface_;
  std::unique_ptr<KernelSet> kernels_;
  TessTopology topo_;
  uint64_t generation_ = 0;
  uint32_t boundaryVertexCount_ = 0, listSampleCount_ = 0;
  tess_layout::TessGridPush gridPush_{};
  bool gridUniform_ = false;
  uint32_t gridPatchCount_ = 0;
  // Grid pass: patch and row records, perimeter scratch. Pack pass: sources, extra ranges, uv.
  // List pass (edge points off their patch's grid): samples and point/normal planes.
  vk::Buffer patchRecords_, rowItems_, boundary_, sources_, extra_, uvs_, listSamples_, points_, normals_;
  vk::Buffer indices_, ownVertices_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace shapespline::gpu
