#include <shapespline/gpu/tessellator.h>

#include <shapespline/core/tess_patches.h>
#include <shapespline/gpu/kernel_runs.h>
#include <shapespline/gpu/kernels.h>
#include <shapespline/gpu/list_packing.h>
#include <shapespline/shaders/layout.h>
#include "shaders/tessellate_pack_comp.h"
#include "shaders/tessellate_pack_comp_f64.h"
#include "shaders/tessellate_pack_comp_f64_pk.h"
#include "shaders/tessellate_pack_comp_pk.h"
#include <shapespline/shaders/tess_layout.h>
#include <shapespline/vk/error.h>
#include <shapespline/vk/pipeline.h>
#include <shapespline/vk/pipeline_table.h>
#include <shapespline/vk/submit.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace shapespline::gpu {
namespace tl = tess_layout;

struct SurfaceTessellator::TargetSets {
  vk::DescriptorSet grid, pack;
};

struct SurfaceTessellator::Impl {
  const vk::ComputePipeline* pack[2] = {};  // without / with list-mode sources (the context's)
  vk::DescriptorSet vertexPassSet, listSet;
  std::map<std::pair<VkBuffer, VkDeviceSize>, TargetSets> targetSets;
  std::map<std::pair<VkBuffer, VkDeviceSize>, uint64_t> indexGeneration;
};

namespace {

vk::Buffer storage(vk::Context& ctx, VkDeviceSize bytes, const char* label,
                   VkBufferUsageFlags extra = 0) {
  return vk::Buffer::create(ctx, std::max<VkDeviceSize>(bytes, 64), vk::kStorageUsage | extra,
                            vk::MemoryUse::DeviceLocal, label);
}

template <typename T>
vk::Buffer uploaded(vk::Context& ctx, const std::vector<T>& values, const char* label, VkBufferUsageFlags extra = 0) {
  vk::Buffer b = storage(ctx, values.size() * sizeof(T), label, extra);
  if (!values.empty()) b.uploadSpan(std::span<const T>(values));
  return b;
}

// Uniform rates: each grid-pass invocation takes as many inner rows of its patch as leaves at least
// this many invocations (the per-invocation start-up, measured on llvmpipe, costs more than the
// lanes lost to a short last block).
constexpr uint32_t kMinGridInvocations = 256;

uint32_t rowsPerInvocation(uint32_t innerRows, uint32_t patches) {
  const uint32_t blocks = std::clamp((kMinGridInvocations + patches - 1) / patches, 1u, std::max(innerRows, 1u));
  return std::max(1u, (innerRows + blocks - 1) / blocks);
}

// Host side of the grid pass: per patch (n, m, first interior vertex, first perimeter slot), per
// invocation (patch, row).
struct GridPlan {
  std::vector<uint32_t> patches;  // 4 per patch
  std::vector<uint32_t> rows;     // 2 per row
  uint32_t perimeterSlots = 0;
  bool uniform = false;  // every patch has the same rates: the kernel derives all of the above
};

GridPlan planGrid(const TessTopology& t) {
  GridPlan g;
  const TessRates& r = t.rates;
  for (int a = 0; a < r.patchesU; ++a)
    for (int b = 0; b < r.patchesV; ++b) {
      const uint32_t n = uint32_t(std::max(r.patchRateU(a, b), 2)), m = uint32_t(std::max(r.patchRateV(a, b), 2));
      const uint32_t p = uint32_t(a * r.patchesV + b);
      g.patches.insert(g.patches.end(), {n, m, t.interiorFirst[p], g.perimeterSlots});
      g.perimeterSlots += 2 * (n + m);
      for (uint32_t row = 1; row < n; ++row) g.rows.insert(g.rows.end(), {p, row});
    }
  // Rows 0 and n after all inner rows (tess_layout.h ROWS).
  for (uint32_t p = 0; p < uint32_t(r.patchesU * r.patchesV); ++p) g.rows.insert(g.rows.end(), {p, 0u, p, g.patches[4 * p]});
  g.uniform = true;
  for (size_t p = 0; p < g.patches.size(); p += 4)
    g.uniform = g.uniform && g.patches[p] == g.patches[0] && g.patches[p + 1] == g.patches[1] &&
                g.patches[p + 2] == g.patches[2] + (p / 4) * (g.patches[0] - 1) * (g.patches[1] - 1);
  return g;
}

// Where the pack pass finds a sample: the grid pass's slot when the sample lies on its patch's
// grid, else a new list-mode sample (an edge whose rate differs from the patch's).
class SourceMap {
 public:
  SourceMap(const TessTopology& t, const GridPlan& g) : topo_(t), plan_(g) {}

  uint32_t operator()(const TessSample& s) {
    const size_t p = size_t(s.a) * topo_.rates.patchesV + s.b;
    const uint32_t n = plan_.patches[4 * p], m = plan_.patches[4 * p + 1];
    // Grid points are i/n; any other edge point k/e is at least 1/e >= 1/4096 of a step away.
    const double fa = s.u * n, fb = s.v * m, ia = std::round(fa), ib = std::round(fb);
    if (std::abs(fa - ia) < 1e-6 && std::abs(fb - ib) < 1e-6) {
      const uint32_t a = uint32_t(ia), b = uint32_t(ib);
      if (a != 0 && a != n && b != 0 && b != m)
        throw std::logic_error("SurfaceTessellator: a shared vertex lies inside its patch");
      return plan_.patches[4 * p + 3] + tess_layout::tessPerimeterSlot(n, m, a, b);
    }
    return listed(s);
  }

  std::vector<TessSample> list;

 private:
  uint32_t listed(const TessSample& s) {
    list.push_back(s);
    return uint32_t(list.size() - 1) | tl::kTessListSource;
  }

  const TessTopology& topo_;
  const GridPlan& plan_;
};

}  // namespace

SurfaceTessellator::SurfaceTessellator(std::shared_ptr<vk::Context> ctx, GpuSurface& surface, const TessRates& rates,
                                       TessellatorOptions options)
    : ctx_(std::move(ctx)),
      surface_(surface),
      kernels_(std::make_unique<KernelSet>(ctx_, surface.precision(), options.workgroupSize, options.packedStores)),
      impl_(std::make_unique<Impl>()) {
  setRates(rates);
}

// Two variants: with list-mode sources (mixed edge rates) or without (no masked list reads).
const vk::ComputePipeline& SurfaceTessellator::packPipeline() {
  const bool list = listSampleCount_ > 0;
  const vk::ComputePipeline*& pipe = impl_->pack[list ? 1 : 0];
  if (pipe) return *pipe;
  const bool d = surface_.precision() == Precision::Double;
  vk::ComputePipelineDesc desc;
  const ShaderVariants code{tessellate_pack_comp, tessellate_pack_comp_f64, tessellate_pack_comp_pk,
                            tessellate_pack_comp_f64_pk};
  const bool packed = kernels_->packedStores();
  desc.spirv = code.pick(d, packed);
  desc.specConstants = {{layout::kSpecWorkgroupSize, kernels_->workgroupSize()}, {tl::kTessSpecListSources, list ? 1u : 0u}};
  desc.pushConstantBytes = sizeof(tl::TessPackPush);
  desc.storageBufferCount = tl::kTessBindingCount;
  desc.label = std::string(d ? "tessellate_pack_f64" : "tessellate_pack_f32") + (packed ? "_pk" : "");
  pipe = &ctx_->pipelines().get(desc);
  return *pipe;
}

SurfaceTessellator::~SurfaceTessellator() = default;

TessRates SurfaceTessellator::uniformRates(const GpuSurface& surface, int rate) {
  return uniformTessRates(surface.surface(), rate);
}

VkDeviceSize SurfaceTessellator::vertexBytes() const { return VkDeviceSize(vertexCount()) * tl::kTessVertexStride; }

void SurfaceTessellator::setRates(const TessRates& rates) {
  const int patchesU = int(surface_.gridItemsU()), patchesV = int(surface_.gridItemsV());
  if (rates.patchesU != patchesU || rates.patchesV != patchesV || rates.closedU != surface_.model().closedU ||
      rates.closedV != surface_.model().closedV)
    throw std::invalid_argument("SurfaceTessellator: the rates describe a " + std::to_string(rates.patchesU) + " x " +
                                std::to_string(rates.patchesV) + " patch grid with other closure flags than the surface's " +
                                std::to_string(patchesU) + " x " + std::to_string(patchesV));
  TessTopology topo = buildTessTopology(rates);
  vk::Context& ctx = *ctx_;
  const VkDeviceSize maxRange = ctx.limits().maxStorageBufferRange;
  if (VkDeviceSize(topo.vertexCount) * tl::kTessVertexStride > maxRange)
    throw std::length_error("SurfaceTessellator: " + std::to_string(topo.vertexCount) + " vertices exceed maxStorageBufferRange " +
                            std::to_string(maxRange) + " bytes; lower the rates");
  const GridPlan plan = planGrid(topo);
  const uint32_t shared = topo.cornerCount + topo.edgeVertexCount;
  for (uint32_t k = shared; k < topo.vertexCount; ++k)
    if (topo.extraCount[k] != 0) throw std::logic_error("SurfaceTessellator: an interior vertex has extra samples");

  const TessPatches patches(surface_.surface());

  // Pack pass inputs: sources (canonical ones first, then the extras), extra ranges, uv.
  SourceMap sourceOf(topo, plan);
  std::vector<uint32_t> sources(shared), extra(2 * size_t(shared));
  std::vector<float> uvs(2 * size_t(shared));
  for (uint32_t k = 0; k < shared; ++k) {
    sources[k] = sourceOf(topo.samples[k]);
    const auto uv = patches.uv(surface_.surface(), topo.samples[k]);
    uvs[2 * k] = uv[0];
    uvs[2 * k + 1] = uv[1];
  }
  for (uint32_t k = 0; k < shared; ++k) {
    extra[2 * k] = uint32_t(sources.size());
    extra[2 * k + 1] = topo.extraCount[k];
    for (uint32_t e = 0; e < topo.extraCount[k]; ++e) sources.push_back(sourceOf(topo.samples[topo.extraFirst[k] + e]));
  }

  // List-mode samples (model patch indices; knot spans and parameters as the CPU picks them).
  const Precision pr = surface_.precision();
  const size_t listCount = sourceOf.list.size();
  std::vector<SurfaceSample> listed(listCount);
  for (size_t k = 0; k < listCount; ++k) {
    const TessSample& s = sourceOf.list[k];
    listed[k] = {patches.u[s.a], patches.v[s.b], s.u, s.v};
  }
  const std::vector<std::byte> listBytes = packListSamples(surfaceListSamples(surface_, listed), pr);
  if (generation_ > 0) ctx.waitIdle();  // the old buffers may still be in use by submitted work

  const size_t rs = realSize(pr);
  patchRecords_ = uploaded(ctx, plan.patches, "tess.patches");
  rowItems_ = uploaded(ctx, plan.rows, "tess.rows");
  boundary_ = storage(ctx, VkDeviceSize(plan.perimeterSlots) * 2 * 4 * rs, "tess.boundary");
  sources_ = uploaded(ctx, sources, "tess.sources");
  extra_ = uploaded(ctx, extra, "tess.extra");
  uvs_ = uploaded(ctx, uvs, "tess.uv");
  listSamples_ = uploaded(ctx, listBytes, "tess.list");
  const VkDeviceSize planeBytes = VkDeviceSize((listCount * 3 + 3) / 4) * 4 * rs;
  points_ = storage(ctx, planeBytes, "tess.points");
  normals_ = storage(ctx, planeBytes, "tess.normals");
  indices_ = uploaded(ctx, topo.indices, "tess.indices", VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
  ownVertices_ = vk::Buffer::create(ctx, std::max<VkDeviceSize>(VkDeviceSize(topo.vertexCount) * tl::kTessVertexStride, 64),
                                    kTessVertexBufferUsage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                    vk::MemoryUse::DeviceLocal, "tess.vertices");
  boundaryVertexCount_ = shared;
  gridUniform_ = plan.uniform;
  gridPush_ = {};
  gridPush_.invocations = uint32_t(plan.rows.size() / 2);
  gridPush_.rowsPerInvocation = rowsPerInvocation(plan.patches[0] - 1, uint32_t(plan.patches.size() / 4));
  gridPush_.patchesV = uint32_t(surface_.gridItemsV());
  setSurfaceNetFields(gridPush_, surface_);
  gridPush_.rateN = plan.patches[0];
  gridPush_.rateM = plan.patches[1];
  gridPush_.interiorFirst = plan.patches[2];
  gridPatchCount_ = uint32_t(plan.patches.size() / 4);
  listSampleCount_ = uint32_t(listCount);
  topo_ = std::move(topo);
  ++generation_;
  impl_->targetSets.clear();
  impl_->indexGeneration.clear();
  impl_->listSet = vk::DescriptorSet();
  impl_->vertexPassSet = vk::DescriptorSet();
}

// The grid and pack passes write the target vertex buffer, so each target gets its own sets.
SurfaceTessellator::TargetSets& SurfaceTessellator::targetSets(VkBuffer vertices, VkDeviceSize offset) {
  const auto key = std::make_pair(vertices, offset);
  auto it = impl_->targetSets.find(key);
  if (it != impl_->targetSets.end()) return it->second;
  KernelSet& k = *kernels_;
  TargetSets sets;
  sets.grid = vk::DescriptorSet::create(*ctx_, gridPipeline());
  for (uint32_t b = 0; b < kBindingCount; ++b) sets.grid.bind(b, k.dummy());
  sets.grid.bind(layout::kBindingNet, surface_.netBuffer())
      .bind(layout::kBindingParams, surface_.paramBuffer())
      .bind(layout::kBindingVerts, surface_.vertexBuffer())
      .bind(tl::kTessGridBindingPatches, patchRecords_)
      .bind(tl::kTessGridBindingRows, rowItems_)
      .bind(tl::kTessGridBindingBoundary, boundary_);
  sets.grid.bindExternal(tl::kTessGridBindingVertices, vertices, offset, vertexBytes());
  sets.pack = vk::DescriptorSet::create(*ctx_, packPipeline());
  sets.pack.bind(0, k.dummy())
      .bind(1, k.dummy())
      .bind(tl::kTessBindingPoints, points_)
      .bind(tl::kTessBindingNormals, normals_)
      .bind(tl::kTessBindingUV, uvs_)
      .bind(tl::kTessBindingExtra, extra_)
      .bind(tl::kTessBindingBoundary, boundary_)
      .bind(tl::kTessBindingSources, sources_);
  sets.pack.bindExternal(tl::kTessBindingVertices, vertices, offset, vertexBytes());
  return impl_->targetSets.emplace(key, std::move(sets)).first->second;
}

const vk::ComputePipeline& SurfaceTessellator::gridPipeline() {
  const SpanBasis& bu = surface_.basisU();
  const SpanBasis& bv = surface_.basisV();
  SpecValues spec = basisSpec(bu, bv);
  spec[layout::kSpecAlphaEB] = surface_.alphaEB() ? 1u : 0u;
  spec[layout::kSpecUniformRates] = gridUniform_ ? 1u : 0u;
  if (surface_.knotVector()) {
    spec[layout::kSpecKnotPatches] = 1u;
    spec[layout::kSpecRational] = surface_.rational() ? 1u : 0u;
  }
  return kernels_->pipeline(Kernel::TessellateGrid, spec);
}

void SurfaceTessellator::record(VkCommandBuffer cmd) {
  record(cmd, {ownVertices_.handle(), 0, VK_NULL_HANDLE, 0});
}

void SurfaceTessellator::record(VkCommandBuffer cmd, const TessTargets& targets) {
  if (targets.vertexBuffer == VK_NULL_HANDLE) throw std::invalid_argument("SurfaceTessellator::record: null vertex buffer");
  if (targets.vertexOffset % ctx_->limits().minStorageBufferOffsetAlignment != 0)
    throw std::invalid_argument("SurfaceTessellator::record: vertexOffset " + std::to_string(targets.vertexOffset) +
                                " is not a multiple of minStorageBufferOffsetAlignment " +
                                std::to_string(ctx_->limits().minStorageBufferOffsetAlignment));
  KernelSet& k = *kernels_;
  const SpanBasis& bu = surface_.basisU();
  const SpanBasis& bv = surface_.basisV();
  const bool aeb = surface_.alphaEB();

  // Earlier draws read the vertex/index buffers, earlier tessellations wrote our planes: WAR/WAW.
  vk::memoryBarrier(cmd,
                VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                    VK_ACCESS_TRANSFER_WRITE_BIT);

  // (1) α-EB nodes and V from the current PARAMS (a few hundred invocations: always run, so that a
  // recorded command buffer never depends on host-side dirty state).
  if (aeb) recordAlphaEBVertices(k, surface_, true, cmd, impl_->vertexPassSet);

  // (2) Edge points that are not on their patch's grid (mixed edge rates): list mode (knot
  // vectors: bspline_surface_eval.comp).
  if (listSampleCount_ > 0) {
    const bool knot = surface_.knotVector();
    const FieldMask mask = fieldBit(Field::Point) | fieldBit(Field::Normal);
    SpecValues spec = basisSpec(bu, bv);
    spec[layout::kSpecOutputMask] = mask;
    spec[layout::kSpecAlphaEB] = aeb ? 1u : 0u;
    if (knot) {
      spec[layout::kSpecRational] = surface_.rational() ? 1u : 0u;
    } else {
      spec[layout::kSpecListMode] = 1u;
    }
    const auto& eval = k.pipeline(knot ? Kernel::BSplineSurfaceEval : Kernel::SurfaceEval, spec);
    if (!impl_->listSet.handle()) {
      impl_->listSet = vk::DescriptorSet::create(*ctx_, eval);
      for (uint32_t b = 0; b < kBindingCount; ++b) impl_->listSet.bind(b, k.dummy());
      impl_->listSet.bind(layout::kBindingNet, surface_.netBuffer())
          .bind(layout::kBindingParams, surface_.paramBuffer())
          .bind(layout::kBindingVerts, surface_.vertexBuffer())
          .bind(layout::kBindingSamples, listSamples_)
          .bind(layout::kBindingOutput + uint32_t(Field::Point), points_)
          .bind(layout::kBindingOutput + uint32_t(Field::Normal), normals_);
    }
    eval.bind(cmd, impl_->listSet.handle());
    if (knot) {
      layout::KnotEvalPush kp = knotPush(surface_, uint32_t(surface_.gridItemsV()), surface_.netCols());
      kp.listMode = 1;
      kp.firstItem = 0;
      kp.itemCount = listSampleCount_;
      eval.push(cmd, kp);
    } else {
      layout::EvalPush ep = surfacePush(surface_);
      ep.firstItem = 0;
      ep.itemCount = listSampleCount_;
      eval.push(cmd, ep);
    }
    k.dispatch(cmd, (uint64_t(listSampleCount_) + layout::kPointsPerInvocation - 1) / layout::kPointsPerInvocation);
  }

  // (3) Every patch's grid: interior vertices into the target, perimeter samples into boundary_.
  TargetSets& sets = targetSets(targets.vertexBuffer, targets.vertexOffset);
  if (gridUniform_) {
    const auto& grid = gridPipeline();
    grid.bind(cmd, sets.grid.handle());  // inner rows, then rows 0 and n (tess_layout.h TessGridPush)
    tl::TessGridPush inner = gridPush_, edges = gridPush_;
    inner.invocations = gridPatchCount_ * ((gridPush_.rateN - 2) / gridPush_.rowsPerInvocation + 1);
    inner.edgeRows = 0;
    edges.invocations = gridPatchCount_;
    edges.edgeRows = 1;
    grid.push(cmd, inner);
    k.dispatch(cmd, inner.invocations);
    grid.push(cmd, edges);
    k.dispatch(cmd, edges.invocations);
  } else {
    const auto& grid = gridPipeline();
    grid.bind(cmd, sets.grid.handle());
    grid.push(cmd, gridPush_);
    k.dispatch(cmd, gridPush_.invocations);
  }
  vk::computeBarrier(cmd);

  // (4) The shared corner and edge vertices.
  const tl::TessPackPush pp{boundaryVertexCount_, 0, 0, 0};
  const vk::ComputePipeline& pack = packPipeline();
  pack.bind(cmd, sets.pack.handle());
  pack.push(cmd, pp);
  k.dispatch(cmd, boundaryVertexCount_);

  // (5) Indices, once per configuration and target.
  VkAccessFlags dstAccess = VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT;
  VkAccessFlags srcAccess = VK_ACCESS_SHADER_WRITE_BIT;
  VkPipelineStageFlags srcStage = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  if (targets.indexBuffer != VK_NULL_HANDLE) {
    uint64_t& gen = impl_->indexGeneration[{targets.indexBuffer, targets.indexOffset}];
    if (gen != generation_) {
      const VkBufferCopy region{0, targets.indexOffset, indexBytes()};
      vkCmdCopyBuffer(cmd, indices_.handle(), targets.indexBuffer, 1, &region);
      gen = generation_;
      srcAccess |= VK_ACCESS_TRANSFER_WRITE_BIT;
      srcStage |= VK_PIPELINE_STAGE_TRANSFER_BIT;
    }
    dstAccess |= VK_ACCESS_INDEX_READ_BIT;
  }
  // (6) Make the results visible to vertex input (and to compute/transfer/host consumers).
  vk::memoryBarrier(cmd, srcStage, srcAccess,
                VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                dstAccess | VK_ACCESS_INDEX_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
}

VkVertexInputBindingDescription SurfaceTessellator::vertexBinding(uint32_t binding) {
  return {binding, tl::kTessVertexStride, VK_VERTEX_INPUT_RATE_VERTEX};
}

std::array<VkVertexInputAttributeDescription, 3> SurfaceTessellator::vertexAttributes(uint32_t binding,
                                                                                     uint32_t firstLocation) {
  return {{{firstLocation, binding, VK_FORMAT_R32G32B32_SFLOAT, tl::kTessOffsetPosition},
           {firstLocation + 1, binding, VK_FORMAT_R32G32B32_SFLOAT, tl::kTessOffsetNormal},
           {firstLocation + 2, binding, VK_FORMAT_R32G32_SFLOAT, tl::kTessOffsetUV}}};
}

}  // namespace shapespline::gpu
