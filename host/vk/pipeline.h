#pragma once
// ComputePipeline: a compute shader (SPIR-V, entry "main") with specialization constants, a
// push-constant block and N storage buffers at bindings 0..N-1 of set 0. DescriptorSet: one set of
// that layout, binding whole buffers or sub-ranges (offset + range) so callers can chunk buffers
// larger than maxStorageBufferRange.
#include <shapespline/vk/context.h>
#include <shapespline/vk/handle.h>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace shapespline::vk {

class Buffer;

struct SpecConstant {
  uint32_t id;     // layout(constant_id = id); local_size_x_id = 0 is the usual workgroup size
  uint32_t value;  // 32-bit payload: uint/int as is, bool as 0/1, float via std::bit_cast
  bool operator==(const SpecConstant&) const = default;
};

struct ComputePipelineDesc {
  std::span<const uint32_t> spirv;  // SPIR-V words (gen/shaders/<name>_comp.h)
  std::vector<SpecConstant> specConstants;
  uint32_t pushConstantBytes = 0;   // multiple of 4, <= limits().maxPushConstantsSize
  uint32_t storageBufferCount = 0;  // bindings 0..N-1 in set 0
  std::string label;                // debug name for validation messages
};

class ComputePipeline {
 public:
  ComputePipeline() = default;
  // Throws std::invalid_argument for a desc that breaks a device limit, VulkanError otherwise.
  static ComputePipeline create(Context& ctx, const ComputePipelineDesc& desc);

  VkPipeline handle() const { return pipeline_.get(); }
  VkPipelineLayout layout() const { return layout_.get(); }
  VkDescriptorSetLayout setLayout() const { return setLayout_.get(); }
  uint32_t storageBufferCount() const { return storageBufferCount_; }
  uint32_t pushConstantBytes() const { return pushConstantBytes_; }
  const std::string& label() const { return label_; }

  // Binds the pipeline and `set` for compute.
  void bind(VkCommandBuffer cmd, VkDescriptorSet set) const;
  // Pushes `bytes` at `offset` of the push-constant block.
  void push(VkCommandBuffer cmd, const void* data, uint32_t bytes, uint32_t offset = 0) const;
  template <typename T>
  void push(VkCommandBuffer cmd, const T& block) const {
    push(cmd, &block, uint32_t(sizeof(T)));
  }

 private:
  DescriptorSetLayoutHandle setLayout_;
  PipelineLayoutHandle layout_;
  PipelineHandle pipeline_;
  uint32_t storageBufferCount_ = 0;
  uint32_t pushConstantBytes_ = 0;
  std::string label_;
};

// A (sub-)range of a buffer for one binding; range VK_WHOLE_SIZE: from offset to the end.
struct BufferBinding {
  uint32_t binding;
  const Buffer* buffer;
  VkDeviceSize offset = 0;
  VkDeviceSize range = VK_WHOLE_SIZE;
};

// One descriptor set for a ComputePipeline's layout, from its own small pool. Rebinding is allowed
// only while no submitted command buffer uses the set (OneShot waits, so between OneShots is fine).
class DescriptorSet {
 public:
  DescriptorSet() = default;
  static DescriptorSet create(Context& ctx, const ComputePipeline& pipeline);
  DescriptorSet(DescriptorSet&& other) noexcept
      : ctx_(other.ctx_),
        pool_(std::move(other.pool_)),
        set_(std::exchange(other.set_, VK_NULL_HANDLE)),
        bindingCount_(std::exchange(other.bindingCount_, 0)) {}
  DescriptorSet& operator=(DescriptorSet&& other) noexcept {
    if (this != &other) {
      ctx_ = other.ctx_;
      pool_ = std::move(other.pool_);  // frees our old set with our old pool
      set_ = std::exchange(other.set_, VK_NULL_HANDLE);
      bindingCount_ = std::exchange(other.bindingCount_, 0);
    }
    return *this;
  }

  VkDescriptorSet handle() const { return set_; }

  // Throws std::invalid_argument when the binding is out of range, the offset is not a multiple of
  // minStorageBufferOffsetAlignment, or the range exceeds the buffer or maxStorageBufferRange.
  DescriptorSet& bind(uint32_t binding, const Buffer& buffer, VkDeviceSize offset = 0,
                      VkDeviceSize range = VK_WHOLE_SIZE);
  DescriptorSet& bind(std::initializer_list<BufferBinding> bindings);
  // A buffer the caller owns (its size unknown here): the range must be explicit and non-zero.
  DescriptorSet& bindExternal(uint32_t binding, VkBuffer buffer, VkDeviceSize offset, VkDeviceSize range);

 private:
  const Context* ctx_ = nullptr;
  DescriptorPoolHandle pool_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;  // freed with pool_
  uint32_t bindingCount_ = 0;
};

}  // namespace shapespline::vk
