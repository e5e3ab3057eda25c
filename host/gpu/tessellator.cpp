#include "gpu/tessellator.h"

#include "gpu/kernels.h"
#include "layout.h"
#include "shaders/tessellate_pack_comp.h"
#include "shaders/tessellate_pack_comp_f64.h"
#include "tess_layout.h"
#include "vk/error.h"
#include "vk/pipeline.h"
#include "vk/submit.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace shapespline::gpu {
namespace tl = tess_layout;

struct SurfaceTessellator::PackSet {
  vk::DescriptorPoolHandle pool;
  VkDescriptorSet set = VK_NULL_HANDLE;
};

struct SurfaceTessellator::Impl {
  vk::ComputePipeline pack;
  vk::DescriptorSet vertexPassSet, evalSet;
  std::map<std::pair<VkBuffer, VkDeviceSize>, PackSet> packSets;
  std::map<std::pair<VkBuffer, VkDeviceSize>, uint64_t> indexGeneration;
};

namespace {

vk::Buffer storage(vk::Context& ctx, VkDeviceSize bytes, const char* label,
                   VkBufferUsageFlags extra = 0) {
  return vk::Buffer::create(ctx, std::max<VkDeviceSize>(bytes, 64), vk::kStorageUsage | extra,
                            vk::MemoryUse::DeviceLocal, label);
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags srcAccess, VkPipelineStageFlags dst,
                   VkAccessFlags dstAccess) {
  VkMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  b.srcAccessMask = srcAccess;
  b.dstAccessMask = dstAccess;
  vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &b, 0, nullptr, 0, nullptr);
}

}  // namespace

SurfaceTessellator::SurfaceTessellator(std::shared_ptr<vk::Context> ctx, GpuSurface& surface, const TessRates& rates,
                                       TessellatorOptions options)
    : ctx_(std::move(ctx)),
      surface_(surface),
      kernels_(std::make_unique<KernelSet>(ctx_, surface.precision(), options.workgroupSize)),
      impl_(std::make_unique<Impl>()) {
  const bool d = surface.precision() == Precision::Double;
  vk::ComputePipelineDesc desc;
  desc.spirv = d ? std::span<const uint32_t>(tessellate_pack_comp_f64) : std::span<const uint32_t>(tessellate_pack_comp);
  desc.specConstants = {{layout::kSpecWorkgroupSize, options.workgroupSize}};
  desc.pushConstantBytes = sizeof(tl::TessPackPush);
  desc.storageBufferCount = tl::kTessBindingCount;
  desc.label = d ? "tessellate_pack_f64" : "tessellate_pack_f32";
  impl_->pack = vk::ComputePipeline::create(*ctx_, desc);
  packLayoutHandle_ = impl_->pack.setLayout();
  setRates(rates);
}

SurfaceTessellator::~SurfaceTessellator() = default;

TessRates SurfaceTessellator::uniformRates(const GpuSurface& surface, int rate) {
  return TessRates::uniform(int(surface.patchesU()), int(surface.patchesV()), surface.model().closedU,
                            surface.model().closedV, rate);
}

VkDeviceSize SurfaceTessellator::vertexBytes() const { return VkDeviceSize(vertexCount()) * tl::kTessVertexStride; }

void SurfaceTessellator::setRates(const TessRates& rates) {
  if (rates.patchesU != int(surface_.patchesU()) || rates.patchesV != int(surface_.patchesV()) ||
      rates.closedU != surface_.model().closedU || rates.closedV != surface_.model().closedV)
    throw std::invalid_argument("SurfaceTessellator: the rates describe a " + std::to_string(rates.patchesU) + " x " +
                                std::to_string(rates.patchesV) + " patch grid with other closure flags than the surface's " +
                                std::to_string(surface_.patchesU()) + " x " + std::to_string(surface_.patchesV()));
  TessTopology topo = buildTessTopology(rates);
  vk::Context& ctx = *ctx_;
  const Precision pr = surface_.precision();
  const size_t rs = realSize(pr);
  const size_t total = topo.samples.size();
  const VkDeviceSize maxRange = ctx.limits().maxStorageBufferRange;
  const size_t sampleBytes = total * (pr == Precision::Double ? sizeof(layout::ListSampleD) : sizeof(layout::ListSampleF));
  if (sampleBytes > maxRange || VkDeviceSize(topo.vertexCount) * tl::kTessVertexStride > maxRange)
    throw std::length_error("SurfaceTessellator: " + std::to_string(topo.vertexCount) + " vertices (" +
                            std::to_string(total) + " samples) exceed maxStorageBufferRange " + std::to_string(maxRange) +
                            " bytes; lower the rates");
  if (generation_ > 0) ctx.waitIdle();  // the old buffers may still be in use by submitted work

  // Sample list in REAL precision, model patch indices.
  const uint32_t fu = uint32_t(surface_.patches().u.first), fv = uint32_t(surface_.patches().v.first);
  std::vector<std::byte> bytes(sampleBytes);
  for (size_t k = 0; k < total; ++k) {
    const TessSample& s = topo.samples[k];
    if (pr == Precision::Double) {
      const layout::ListSampleD x{uint32_t(s.a) + fu, uint32_t(s.b) + fv, 0, 0, s.u, s.v, 0.0, 0.0};
      std::memcpy(bytes.data() + k * sizeof(x), &x, sizeof(x));
    } else {
      const layout::ListSampleF x{uint32_t(s.a) + fu, uint32_t(s.b) + fv, 0, 0, float(s.u), float(s.v), 0.f, 0.f};
      std::memcpy(bytes.data() + k * sizeof(x), &x, sizeof(x));
    }
  }
  samples_ = storage(ctx, sampleBytes, "tess.samples");
  samples_.upload(bytes);
  std::vector<uint32_t> extra(size_t(topo.vertexCount) * 2);
  for (uint32_t k = 0; k < topo.vertexCount; ++k) {
    extra[2 * k] = topo.extraFirst[k];
    extra[2 * k + 1] = topo.extraCount[k];
  }
  extra_ = storage(ctx, extra.size() * 4, "tess.extra");
  extra_.uploadSpan(std::span<const uint32_t>(extra));
  const VkDeviceSize planeBytes = VkDeviceSize((total * 3 + 3) / 4) * 4 * rs;
  points_ = storage(ctx, planeBytes, "tess.points");
  normals_ = storage(ctx, planeBytes, "tess.normals");
  indices_ = storage(ctx, topo.indices.size() * 4, "tess.indices", VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
  indices_.uploadSpan(std::span<const uint32_t>(topo.indices));
  ownVertices_ = vk::Buffer::create(ctx, std::max<VkDeviceSize>(VkDeviceSize(topo.vertexCount) * tl::kTessVertexStride, 64),
                                    kTessVertexBufferUsage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                    vk::MemoryUse::DeviceLocal, "tess.vertices");
  topo_ = std::move(topo);
  ++generation_;
  impl_->packSets.clear();
  impl_->indexGeneration.clear();
  impl_->evalSet = vk::DescriptorSet();
  impl_->vertexPassSet = vk::DescriptorSet();
}

SurfaceTessellator::PackSet& SurfaceTessellator::packSet(VkBuffer vertices, VkDeviceSize offset) {
  auto key = std::make_pair(vertices, offset);
  auto it = impl_->packSets.find(key);
  if (it != impl_->packSets.end()) return it->second;
  VkDevice dev = ctx_->device();
  PackSet ps;
  VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, tl::kTessBindingCount};
  VkDescriptorPoolCreateInfo pi{};
  pi.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  pi.maxSets = 1;
  pi.poolSizeCount = 1;
  pi.pPoolSizes = &size;
  VkDescriptorPool pool;
  vk::check(vkCreateDescriptorPool(dev, &pi, nullptr, &pool), "vkCreateDescriptorPool (tessellate_pack)");
  ps.pool = vk::DescriptorPoolHandle(dev, pool);
  VkDescriptorSetAllocateInfo ai{};
  ai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  ai.descriptorPool = pool;
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &packLayoutHandle_;
  vk::check(vkAllocateDescriptorSets(dev, &ai, &ps.set), "vkAllocateDescriptorSets (tessellate_pack)");
  const VkBuffer bufs[tl::kTessBindingCount] = {kernels_->dummy().handle(), kernels_->dummy().handle(), points_.handle(),
                                                normals_.handle(), samples_.handle(), extra_.handle(), vertices};
  VkDescriptorBufferInfo infos[tl::kTessBindingCount];
  VkWriteDescriptorSet writes[tl::kTessBindingCount];
  for (uint32_t b = 0; b < tl::kTessBindingCount; ++b) {
    infos[b] = {bufs[b], b == tl::kTessBindingVertices ? offset : 0,
                b == tl::kTessBindingVertices ? vertexBytes() : VK_WHOLE_SIZE};
    writes[b] = {};
    writes[b].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[b].dstSet = ps.set;
    writes[b].dstBinding = b;
    writes[b].descriptorCount = 1;
    writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[b].pBufferInfo = &infos[b];
  }
  vkUpdateDescriptorSets(dev, tl::kTessBindingCount, writes, 0, nullptr);
  return impl_->packSets.emplace(key, std::move(ps)).first->second;
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
  const uint32_t total = uint32_t(topo_.samples.size());

  // Earlier draws read the vertex/index buffers, earlier tessellations wrote our planes: WAR/WAW.
  memoryBarrier(cmd,
                VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                    VK_ACCESS_TRANSFER_WRITE_BIT);

  // (1) α-EB nodes and V from the current PARAMS (a few hundred invocations: always run, so that a
  // recorded command buffer never depends on host-side dirty state).
  if (aeb) {
    const auto& pipe = k.pipeline(Kernel::AlphaEBVertices, {uint32_t(bu.count), uint32_t(bu.degree), uint32_t(bv.count),
                                                            uint32_t(bv.degree), 0u, 1u, 0u, 1u});
    if (!impl_->vertexPassSet.handle()) {
      impl_->vertexPassSet = vk::DescriptorSet::create(*ctx_, pipe);
      for (uint32_t b = 0; b < kBindingCount; ++b) impl_->vertexPassSet.bind(b, k.dummy());
      impl_->vertexPassSet.bind(layout::kBindingNet, surface_.netBuffer())
          .bind(layout::kBindingParams, surface_.paramBuffer())
          .bind(layout::kBindingVerts, surface_.vertexBuffer());
    }
    const layout::VertexPush pc{surface_.vertexRows(), surface_.vertexCols(), surface_.netCols(), surface_.alphaOffset()};
    pipe.bind(cmd, impl_->vertexPassSet.handle());
    pipe.push(cmd, pc);
    k.dispatch(cmd, uint64_t(pc.rows) * pc.cols);
    vk::computeBarrier(cmd);
  }

  // (2) Points and normals of every sample.
  const FieldMask mask = fieldBit(Field::Point) | fieldBit(Field::Normal);
  const auto& eval = k.pipeline(Kernel::SurfaceEval, {uint32_t(bu.count), uint32_t(bu.degree), uint32_t(bv.count),
                                                      uint32_t(bv.degree), mask, aeb ? 1u : 0u, 1u, 1u});
  if (!impl_->evalSet.handle()) {
    impl_->evalSet = vk::DescriptorSet::create(*ctx_, eval);
    for (uint32_t b = 0; b < kBindingCount; ++b) impl_->evalSet.bind(b, k.dummy());
    impl_->evalSet.bind(layout::kBindingNet, surface_.netBuffer())
        .bind(layout::kBindingParams, surface_.paramBuffer())
        .bind(layout::kBindingVerts, surface_.vertexBuffer())
        .bind(layout::kBindingSamples, samples_)
        .bind(layout::kBindingOutput + uint32_t(Field::Point), points_)
        .bind(layout::kBindingOutput + uint32_t(Field::Normal), normals_);
  }
  layout::EvalPush ep{};
  ep.firstItem = 0;
  ep.itemCount = total;
  ep.itemsV = uint32_t(surface_.patchesV());
  ep.samplesU = 1;
  ep.samplesV = 1;
  ep.firstSpanU = uint32_t(surface_.patches().u.first);
  ep.firstSpanV = uint32_t(surface_.patches().v.first);
  ep.netCols = surface_.netCols();
  ep.netOffsetU = surface_.netOffsetU();
  ep.netOffsetV = surface_.netOffsetV();
  ep.rows = surface_.vertexRows();
  ep.cols = surface_.vertexCols();
  ep.alphaOffset = surface_.alphaOffset();
  ep.invHOffset = layout::kNoOffset;
  eval.bind(cmd, impl_->evalSet.handle());
  eval.push(cmd, ep);
  k.dispatch(cmd, (uint64_t(total) + layout::kPointsPerInvocation - 1) / layout::kPointsPerInvocation);
  vk::computeBarrier(cmd);

  // (3) Interleave into the target vertex buffer.
  PackSet& ps = packSet(targets.vertexBuffer, targets.vertexOffset);
  const tl::TessPackPush pp{topo_.vertexCount, 0, 0, 0};
  impl_->pack.bind(cmd, ps.set);
  impl_->pack.push(cmd, pp);
  k.dispatch(cmd, topo_.vertexCount);

  // (4) Indices, once per configuration and target.
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
  // (5) Make the results visible to vertex input (and to compute/transfer/host consumers).
  memoryBarrier(cmd, srcStage, srcAccess,
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
