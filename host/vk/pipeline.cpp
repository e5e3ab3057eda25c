#include <shapespline/vk/pipeline.h>

#include <shapespline/vk/buffer.h>
#include <shapespline/vk/error.h>
#include <shapespline/vk/pipeline_cache.h>

#include <stdexcept>

namespace shapespline::vk {

ComputePipeline ComputePipeline::create(Context& ctx, const ComputePipelineDesc& desc) {
  const Limits& limits = ctx.limits();
  const std::string name = desc.label.empty() ? std::string("compute pipeline") : desc.label;
  if (desc.spirv.empty() || desc.spirv[0] != 0x07230203u) {
    throw std::invalid_argument(name + ": spirv is empty or lacks the SPIR-V magic number");
  }
  if (desc.pushConstantBytes % 4 != 0 || desc.pushConstantBytes > limits.maxPushConstantsSize) {
    throw std::invalid_argument(name + ": pushConstantBytes " + std::to_string(desc.pushConstantBytes) +
                                " must be a multiple of 4 and <= maxPushConstantsSize " +
                                std::to_string(limits.maxPushConstantsSize));
  }
  const VkDevice device = ctx.device();
  ComputePipeline p;
  p.storageBufferCount_ = desc.storageBufferCount;
  p.pushConstantBytes_ = desc.pushConstantBytes;
  p.label_ = desc.label;

  std::vector<VkDescriptorSetLayoutBinding> bindings(desc.storageBufferCount);
  for (uint32_t i = 0; i < desc.storageBufferCount; ++i) {
    bindings[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  }
  VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  setInfo.bindingCount = uint32_t(bindings.size());
  setInfo.pBindings = bindings.data();
  VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
  check(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &setLayout), "vkCreateDescriptorSetLayout");
  p.setLayout_ = DescriptorSetLayoutHandle(device, setLayout);

  VkPushConstantRange pushRange{VK_SHADER_STAGE_COMPUTE_BIT, 0, desc.pushConstantBytes};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = 1;
  layoutInfo.pSetLayouts = &setLayout;
  layoutInfo.pushConstantRangeCount = desc.pushConstantBytes > 0 ? 1 : 0;
  layoutInfo.pPushConstantRanges = &pushRange;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  check(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &layout), "vkCreatePipelineLayout");
  p.layout_ = PipelineLayoutHandle(device, layout);

  VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  moduleInfo.codeSize = desc.spirv.size_bytes();
  moduleInfo.pCode = desc.spirv.data();
  VkShaderModule module = VK_NULL_HANDLE;
  check(vkCreateShaderModule(device, &moduleInfo, nullptr, &module), ("vkCreateShaderModule (" + name + ")").c_str());
  // Only needed until the pipeline exists.
  ShaderModuleHandle moduleOwner(device, module);

  std::vector<VkSpecializationMapEntry> entries;
  std::vector<uint32_t> values;
  for (const SpecConstant& c : desc.specConstants) {
    entries.push_back({c.id, uint32_t(values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
    values.push_back(c.value);
  }
  VkSpecializationInfo spec{};
  spec.mapEntryCount = uint32_t(entries.size());
  spec.pMapEntries = entries.data();
  spec.dataSize = values.size() * sizeof(uint32_t);
  spec.pData = values.data();

  VkComputePipelineCreateInfo pipelineInfo{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  pipelineInfo.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipelineInfo.stage.module = module;
  pipelineInfo.stage.pName = "main";
  pipelineInfo.stage.pSpecializationInfo = entries.empty() ? nullptr : &spec;
  pipelineInfo.layout = layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  check(vkCreateComputePipelines(device, ctx.pipelineCache().handle(), 1, &pipelineInfo, nullptr, &pipeline),
        ("vkCreateComputePipelines (" + name + ")").c_str());
  p.pipeline_ = PipelineHandle(device, pipeline);
  ctx.setDebugName(VK_OBJECT_TYPE_PIPELINE, uint64_t(pipeline), desc.label.c_str());
  return p;
}

void ComputePipeline::bind(VkCommandBuffer cmd, VkDescriptorSet set) const {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
  if (set != VK_NULL_HANDLE) {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set, 0, nullptr);
  }
}

void ComputePipeline::push(VkCommandBuffer cmd, const void* data, uint32_t bytes, uint32_t offset) const {
  if (offset % 4 != 0 || bytes % 4 != 0 || offset + bytes > pushConstantBytes_) {
    throw std::invalid_argument("push constants [" + std::to_string(offset) + ", " + std::to_string(offset + bytes) +
                                ") do not fit the " + std::to_string(pushConstantBytes_) + "-byte block of " +
                                (label_.empty() ? std::string("the pipeline") : label_));
  }
  vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, offset, bytes, data);
}

DescriptorSet DescriptorSet::create(Context& ctx, const ComputePipeline& pipeline) {
  DescriptorSet s;
  s.ctx_ = &ctx;
  s.bindingCount_ = pipeline.storageBufferCount();
  const VkDevice device = ctx.device();

  // A pool for one set: sets are few (one per evaluator job) and this keeps ownership trivial.
  VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, std::max(1u, s.bindingCount_)};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.maxSets = 1;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = &size;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  check(vkCreateDescriptorPool(device, &poolInfo, nullptr, &pool), "vkCreateDescriptorPool");
  s.pool_ = DescriptorPoolHandle(device, pool);

  VkDescriptorSetLayout layout = pipeline.setLayout();
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &layout;
  check(vkAllocateDescriptorSets(device, &alloc, &s.set_), "vkAllocateDescriptorSets");
  return s;
}

DescriptorSet& DescriptorSet::bind(uint32_t binding, const Buffer& buffer, VkDeviceSize offset, VkDeviceSize range) {
  return bind({BufferBinding{binding, &buffer, offset, range}});
}

DescriptorSet& DescriptorSet::bind(std::initializer_list<BufferBinding> list) {
  const Limits& limits = ctx_->limits();
  std::vector<VkDescriptorBufferInfo> infos;
  infos.reserve(list.size());  // pointers into it go into `writes`
  std::vector<VkWriteDescriptorSet> writes;
  for (const BufferBinding& b : list) {
    const std::string where = "binding " + std::to_string(b.binding);
    if (b.binding >= bindingCount_) {
      throw std::invalid_argument(where + " is out of range: the pipeline has " + std::to_string(bindingCount_) +
                                  " storage buffers");
    }
    if (b.buffer == nullptr || b.buffer->handle() == VK_NULL_HANDLE) {
      throw std::invalid_argument(where + ": buffer is empty");
    }
    const VkDeviceSize size = b.buffer->size();
    if (b.offset % limits.minStorageBufferOffsetAlignment != 0 || b.offset >= size) {
      throw std::invalid_argument(where + ": offset " + std::to_string(b.offset) + " must be < buffer size " +
                                  std::to_string(size) + " and a multiple of minStorageBufferOffsetAlignment " +
                                  std::to_string(limits.minStorageBufferOffsetAlignment));
    }
    const VkDeviceSize effective = b.range == VK_WHOLE_SIZE ? size - b.offset : b.range;
    if (effective == 0 || b.offset + effective > size || effective > limits.maxStorageBufferRange) {
      throw std::invalid_argument(where + ": range " + std::to_string(effective) + " at offset " +
                                  std::to_string(b.offset) + " must be non-empty, inside the " +
                                  std::to_string(size) + "-byte buffer and <= maxStorageBufferRange " +
                                  std::to_string(limits.maxStorageBufferRange) + " (bind a sub-range per chunk)");
    }
    infos.push_back({b.buffer->handle(), b.offset, b.range});
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set_;
    write.dstBinding = b.binding;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    write.pBufferInfo = &infos.back();
    writes.push_back(write);
  }
  vkUpdateDescriptorSets(ctx_->device(), uint32_t(writes.size()), writes.data(), 0, nullptr);
  return *this;
}

DescriptorSet& DescriptorSet::bindExternal(uint32_t binding, VkBuffer buffer, VkDeviceSize offset,
                                           VkDeviceSize range) {
  const Limits& limits = ctx_->limits();
  const std::string where = "binding " + std::to_string(binding);
  if (binding >= bindingCount_)
    throw std::invalid_argument(where + " is out of range: the pipeline has " + std::to_string(bindingCount_) +
                                " storage buffers");
  if (buffer == VK_NULL_HANDLE) throw std::invalid_argument(where + ": null buffer");
  if (offset % limits.minStorageBufferOffsetAlignment != 0)
    throw std::invalid_argument(where + ": offset " + std::to_string(offset) +
                                " must be a multiple of minStorageBufferOffsetAlignment " +
                                std::to_string(limits.minStorageBufferOffsetAlignment));
  if (range == 0 || range == VK_WHOLE_SIZE || range > limits.maxStorageBufferRange)
    throw std::invalid_argument(where + ": range " + std::to_string(range) +
                                " must be explicit, non-zero and <= maxStorageBufferRange " +
                                std::to_string(limits.maxStorageBufferRange));
  const VkDescriptorBufferInfo info{buffer, offset, range};
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = set_;
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  write.pBufferInfo = &info;
  vkUpdateDescriptorSets(ctx_->device(), 1, &write, 0, nullptr);
  return *this;
}

}  // namespace shapespline::vk
