#include <shapespline/gpu/adaptive_tessellator.h>

#include <shapespline/vk/timestamps.h>

#include <shapespline/gpu/kernel_runs.h>
#include <shapespline/gpu/kernels.h>
#include <shapespline/shaders/layout.h>
#include <shapespline/vk/pipeline.h>
#include <shapespline/vk/submit.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace shapespline::gpu {
namespace tl = tess_layout;

namespace {

constexpr VkDeviceSize kFrameBytes = tl::kAdaptFrameWords * 4;

std::string field(const char* name) { return std::string("AdaptiveOptions.") + name; }

void checkOptions(const AdaptiveOptions& o) {
  auto fail = [](const char* name, double value, const char* rule) {
    throw std::invalid_argument(field(name) + " = " + std::to_string(value) + ": " + rule);
  };
  if (!(o.tolerancePx > 0.0f) || !std::isfinite(o.tolerancePx)) fail("tolerancePx", o.tolerancePx, "must be a finite number > 0");
  if (o.maxRate < 2 || o.maxRate > 4096) fail("maxRate", o.maxRate, "must lie in [2, 4096]");
  if (!(o.hysteresis >= 0.0f && o.hysteresis <= 4.0f)) fail("hysteresis", o.hysteresis, "must lie in [0, 4]");
  if (o.probeRate < 2 || o.probeRate > 64) fail("probeRate", o.probeRate, "must lie in [2, 64]");
  if (!(o.safety >= 1.0f && o.safety <= 100.0f)) fail("safety", o.safety, "must lie in [1, 100]");
}

// Worst-case sizes of a patch grid at one rate everywhere (what the buffers must hold).
struct Capacity {
  uint64_t vertices = 0, indices = 0;
};

Capacity capacityAt(int patchesU, int patchesV, bool closedU, bool closedV, int rate) {
  const uint64_t PU = uint64_t(patchesU), PV = uint64_t(patchesV), R = uint64_t(rate);
  const uint64_t BU = closedU ? PU : PU + 1, BV = closedV ? PV : PV + 1;
  const uint64_t edges = PU * BV + BU * PV, patches = PU * PV;
  Capacity c;
  c.vertices = BU * BV + edges * (R - 1) + patches * (R - 1) * (R - 1);
  // Per patch: four rings of R + (R - 2) triangles and 2 (R - 2)^2 quad triangles.
  c.indices = 3 * patches * (4 * (2 * R - 2) + 2 * (R - 2) * (R - 2));
  return c;
}

}  // namespace

struct AdaptiveTessellator::Impl {
  std::unique_ptr<KernelSet> kernels;
  vk::Buffer view, rates, patches, edges, quads, rows;
  vk::DescriptorSet rateSet, layoutSet, meshSet, vertexPassSet;
  bool resetPending = true;
};

AdaptiveTessellator::AdaptiveTessellator(std::shared_ptr<vk::Context> ctx, GpuSurface& surface, AdaptiveOptions options)
    : ctx_(std::move(ctx)), surface_(surface), options_(options), impl_(std::make_unique<Impl>()) {
  checkOptions(options_);
  patchesU_ = int(surface.gridItemsU());  // knot vectors: the non-empty intervals (knot patches)
  patchesV_ = int(surface.gridItemsV());
  closedU_ = surface.model().closedU;
  closedV_ = surface.model().closedV;
  impl_->kernels = std::make_unique<KernelSet>(ctx_, surface.precision(), 64, false);
  allocate();
}

AdaptiveTessellator::~AdaptiveTessellator() = default;

void AdaptiveTessellator::allocate() {
  vk::Context& ctx = *ctx_;
  const Capacity cap = capacityAt(patchesU_, patchesV_, closedU_, closedV_, options_.maxRate);
  const VkDeviceSize range = ctx.limits().maxStorageBufferRange;
  const uint64_t vertexBytes = cap.vertices * tl::kTessVertexStride, indexBytes = cap.indices * 4;
  if (vertexBytes > range || indexBytes > range || cap.indices >= (uint64_t(1) << 32))
    throw std::length_error("AdaptiveTessellator: " + field("maxRate") + " = " + std::to_string(options_.maxRate) +
                            " needs up to " + std::to_string(cap.vertices) + " vertices (" + std::to_string(vertexBytes) +
                            " bytes) and " + std::to_string(cap.indices) + " indices for " + std::to_string(patchesU_) +
                            " x " + std::to_string(patchesV_) + " patches; the device's maxStorageBufferRange is " +
                            std::to_string(range) + " bytes: lower maxRate");
  if (impl_->rates.handle() != VK_NULL_HANDLE) ctx.waitIdle();  // the old buffers may be in use
  maxVertices_ = uint32_t(cap.vertices);
  maxIndices_ = uint32_t(cap.indices);
  const size_t patches = size_t(patchesU_) * patchesV_;
  const size_t edges = size_t(patchesU_) * (closedV_ ? patchesV_ : patchesV_ + 1) +
                       size_t(closedU_ ? patchesU_ : patchesU_ + 1) * patchesV_;
  auto local = [&](VkDeviceSize bytes, VkBufferUsageFlags usage, const char* label) {
    return vk::Buffer::create(ctx, std::max<VkDeviceSize>(bytes, 64), usage, vk::MemoryUse::DeviceLocal, label);
  };
  vertices_ = local(vertexBytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | vk::kStorageUsage, "adaptive.vertices");
  indices_ = local(indexBytes, VK_BUFFER_USAGE_INDEX_BUFFER_BIT | vk::kStorageUsage, "adaptive.indices");
  indirect_ = local(kFrameBytes, VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | vk::kStorageUsage, "adaptive.frame");
  impl_->view = local(sizeof(tl::AdaptiveViewBlock), vk::kStorageUsage, "adaptive.view");
  impl_->rates = local(patches * 8, vk::kStorageUsage, "adaptive.rates");
  impl_->patches = local(patches * 16, vk::kStorageUsage, "adaptive.patches");
  impl_->edges = local(edges * 8, vk::kStorageUsage, "adaptive.edges");
  impl_->quads = local(patches * 4, vk::kStorageUsage, "adaptive.quads");
  impl_->rows = local(patches * 4, vk::kStorageUsage, "adaptive.rows");
  for (vk::DescriptorSet* set : {&impl_->rateSet, &impl_->layoutSet, &impl_->meshSet})
    *set = vk::DescriptorSet();
  impl_->resetPending = true;
}

void AdaptiveTessellator::setOptions(const AdaptiveOptions& options) {
  checkOptions(options);
  const bool realloc = options.maxRate != options_.maxRate;
  options_ = options;
  if (realloc) allocate();
}

void AdaptiveTessellator::resetRates() { impl_->resetPending = true; }

void AdaptiveTessellator::record(VkCommandBuffer cmd, const AdaptiveView& view, vk::PassTimer* timer) {
  if (!(view.viewportWidth >= 1.0f && view.viewportHeight >= 1.0f && std::isfinite(view.viewportWidth) &&
        std::isfinite(view.viewportHeight)))
    throw std::invalid_argument("AdaptiveView: viewport " + std::to_string(view.viewportWidth) + " x " +
                                std::to_string(view.viewportHeight) + " must be at least 1 x 1 pixels");
  for (float x : view.viewProj)
    if (!std::isfinite(x)) throw std::invalid_argument("AdaptiveView.viewProj: every entry must be finite");
  KernelSet& k = *impl_->kernels;
  const bool aeb = surface_.alphaEB();
  SpecValues evalSpec = basisSpec(surface_.basisU(), surface_.basisV());
  evalSpec[layout::kSpecAlphaEB] = aeb ? 1u : 0u;
  if (surface_.knotVector()) {
    evalSpec[layout::kSpecKnotPatches] = 1u;
    evalSpec[layout::kSpecRational] = surface_.rational() ? 1u : 0u;
  }
  // One pipeline per mode (tess_layout.h kSpecAdaptMode); the sets are made for the mode-0 ones
  // (same layouts).
  auto withMode = [](SpecValues spec, uint32_t mode) {
    spec[tl::kSpecAdaptMode] = mode;
    return spec;
  };
  const vk::ComputePipeline& ratesPatchPipe = k.pipeline(Kernel::AdaptiveRates, withMode(evalSpec, tl::kAdaptModeRates));
  const vk::ComputePipeline& layoutPipe = k.pipeline(Kernel::AdaptiveLayout, {});
  const vk::ComputePipeline& cornersPipe = k.pipeline(Kernel::AdaptiveMesh, withMode(evalSpec, tl::kAdaptModeCorners));
  const vk::ComputePipeline& edgesUPipe = k.pipeline(Kernel::AdaptiveMesh, withMode(evalSpec, tl::kAdaptModeEdgesU));
  const vk::ComputePipeline& edgesVPipe = k.pipeline(Kernel::AdaptiveMesh, withMode(evalSpec, tl::kAdaptModeEdgesV));
  const vk::ComputePipeline& rowsPipe = k.pipeline(Kernel::AdaptiveMesh, withMode(evalSpec, tl::kAdaptModeRows));
  auto makeSet = [&](vk::DescriptorSet& set, const vk::ComputePipeline& pipe) {
    if (set.handle()) return;
    set = vk::DescriptorSet::create(*ctx_, pipe);
    for (uint32_t b = 0; b < kBindingCount; ++b) set.bind(b, k.dummy());
    set.bind(layout::kBindingNet, surface_.netBuffer())
        .bind(layout::kBindingParams, surface_.paramBuffer())
        .bind(layout::kBindingVerts, surface_.vertexBuffer())
        .bind(tl::kAdaptBindingView, impl_->view)
        .bind(tl::kAdaptBindingRates, impl_->rates)
        .bind(tl::kAdaptBindingPatches, impl_->patches)
        .bind(tl::kAdaptBindingEdges, impl_->edges)
        .bind(tl::kAdaptBindingFrame, indirect_)
        .bind(tl::kAdaptBindingVertices, vertices_)
        .bind(tl::kAdaptBindingIndices, indices_)
        .bind(tl::kAdaptBindingQuads, impl_->quads)
        .bind(tl::kAdaptBindingRows, impl_->rows);
  };
  makeSet(impl_->rateSet, ratesPatchPipe);
  makeSet(impl_->layoutSet, layoutPipe);
  makeSet(impl_->meshSet, cornersPipe);

  // Earlier frames read the mesh (vertex input, indirect) and wrote our buffers: WAR/WAW.
  vk::memoryBarrier(cmd,
                VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
  auto mark = [&](const char* pass) {
    if (timer) timer->mark(cmd, pass);
  };
  if (timer) timer->reset(cmd);
  tl::AdaptiveViewBlock block{};
  std::copy(view.viewProj.begin(), view.viewProj.end(), block.viewProj);
  block.viewport[0] = view.viewportWidth;
  block.viewport[1] = view.viewportHeight;
  block.viewport[2] = options_.tolerancePx;
  block.viewport[3] = options_.safety;
  block.tuning[0] = options_.hysteresis;
  block.limits[0] = uint32_t(options_.maxRate);
  block.limits[1] = uint32_t(options_.probeRate);
  block.limits[2] = options_.cull ? 1u : 0u;
  block.limits[3] = ctx_->limits().maxComputeWorkGroupCount[0];
  vkCmdUpdateBuffer(cmd, impl_->view.handle(), 0, sizeof(block), &block);
  vkCmdFillBuffer(cmd, indirect_.handle(), 0, kFrameBytes, 0);
  if (impl_->resetPending) {
    vkCmdFillBuffer(cmd, impl_->rates.handle(), 0, VK_WHOLE_SIZE, 0);
    impl_->resetPending = false;
  }
  vk::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);

  mark("clear");
  // (1) α-EB nodes and V from the current PARAMS.
  if (aeb) recordAlphaEBVertices(k, surface_, true, cmd, impl_->vertexPassSet);
  mark("alpha-eb vertices");

  tl::AdaptivePush push{};
  push.patchesU = uint32_t(patchesU_);
  push.patchesV = uint32_t(patchesV_);
  push.closedU = closedU_ ? 1u : 0u;
  push.closedV = closedV_ ? 1u : 0u;
  setSurfaceNetFields(push, surface_);
  const uint64_t wg = k.workgroupSize();
  const uint64_t patches = uint64_t(patchesU_) * patchesV_;
  auto bind = [&](const vk::ComputePipeline& pipe, const vk::DescriptorSet& set, uint32_t mode) {
    push.mode = mode;
    pipe.bind(cmd, set.handle());
    pipe.push(cmd, push);
  };
  auto run = [&](const vk::ComputePipeline& pipe, const vk::DescriptorSet& set, uint32_t mode, uint64_t invocations) {
    bind(pipe, set, mode);
    k.dispatch(cmd, invocations);
  };
  auto runIndirect = [&](const vk::ComputePipeline& pipe, const vk::DescriptorSet& set, uint32_t mode, uint32_t word) {
    bind(pipe, set, mode);
    vkCmdDispatchIndirect(cmd, indirect_.handle(), VkDeviceSize(word) * 4);
  };
  // (2) rates: per patch, its probes and rates.
  run(ratesPatchPipe, impl_->rateSet, tl::kAdaptModeRates, patches);
  vk::computeBarrier(cmd);
  mark("rates");
  // (3) layout; its counts size the indirect dispatches.
  run(layoutPipe, impl_->layoutSet, 0, wg);
  vk::memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
  mark("layout");
  // (4) the mesh: corners, u-edges (+ rings), v-edges (+ rings), one invocation each (counts of the
  // patch grid); interior row blocks (+ quads), sized by the layout.
  const uint64_t boundsU = closedU_ ? uint64_t(patchesU_) : uint64_t(patchesU_) + 1;
  const uint64_t boundsV = closedV_ ? uint64_t(patchesV_) : uint64_t(patchesV_) + 1;
  run(cornersPipe, impl_->meshSet, tl::kAdaptModeCorners, boundsU * boundsV);
  mark("mesh: corners");
  run(edgesUPipe, impl_->meshSet, tl::kAdaptModeEdgesU, uint64_t(patchesU_) * boundsV);
  mark("mesh: u-edges + rings");
  run(edgesVPipe, impl_->meshSet, tl::kAdaptModeEdgesV, boundsU * uint64_t(patchesV_));
  mark("mesh: v-edges + rings");
  runIndirect(rowsPipe, impl_->meshSet, tl::kAdaptModeRows, tl::kAdaptFrameRowDispatch);
  mark("mesh: interior rows + quads");
  // (5) The mesh and the draw command to vertex input and indirect reads (and to copies out).
  vk::memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_INPUT_BIT |
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT |
                    VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
}

void AdaptiveTessellator::recordDraw(VkCommandBuffer cmd) const {
  const VkBuffer vb = vertices_.handle();
  const VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
  vkCmdBindIndexBuffer(cmd, indices_.handle(), 0, VK_INDEX_TYPE_UINT32);
  vkCmdDrawIndexedIndirect(cmd, indirect_.handle(), 0, 1, sizeof(VkDrawIndexedIndirectCommand));
}

namespace {

// Copies `bytes` of src into a host-visible buffer and returns them (waits for the queue).
template <typename T>
std::vector<T> readBack(vk::Context& ctx, const vk::Buffer& src, size_t count) {
  std::vector<T> out(count);
  if (count == 0) return out;
  ctx.waitIdle();
  src.downloadSpan(std::span<T>(out));
  return out;
}

}  // namespace

AdaptiveStats AdaptiveTessellator::stats() const {
  const std::vector<uint32_t> f = readBack<uint32_t>(*ctx_, indirect_, tl::kAdaptFrameWords);
  AdaptiveStats s;
  s.indexCount = f[0];
  s.vertexCount = f[tl::kAdaptFrameVertexCount];
  s.culledPatches = f[tl::kAdaptFrameCulled];
  s.clampedPatches = f[tl::kAdaptFrameClamped];
  s.nearPatches = f[tl::kAdaptFrameNear];
  return s;
}

TessRates AdaptiveTessellator::rates() const {
  const size_t patches = size_t(patchesU_) * patchesV_;
  const std::vector<uint32_t> r = readBack<uint32_t>(*ctx_, impl_->rates, 2 * patches);
  TessRates out;
  out.patchesU = patchesU_;
  out.patchesV = patchesV_;
  out.closedU = closedU_;
  out.closedV = closedV_;
  out.rateU.resize(patches);
  out.rateV.resize(patches);
  for (size_t p = 0; p < patches; ++p) {
    out.rateU[p] = int(r[2 * p]);
    out.rateV[p] = int(r[2 * p + 1]);
  }
  return out;
}

AdaptiveTessellator::Mesh AdaptiveTessellator::mesh() const {
  Mesh m;
  m.rates = rates();
  const AdaptiveStats s = stats();
  m.vertices = readBack<tl::TessVertex>(*ctx_, vertices_, s.vertexCount);
  m.indices = readBack<uint32_t>(*ctx_, indices_, s.indexCount);
  return m;
}

}  // namespace shapespline::gpu
