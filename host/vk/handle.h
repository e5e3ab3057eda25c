#pragma once
// Move-only owner of one Vulkan object created from a VkDevice (or VkInstance): the destructor
// releases it, a move leaves the source empty. One template instead of one class per object type,
// because every vkDestroy*/vkFree* of a child object has the same shape
// (parent, handle, allocator).
#include <vulkan/vulkan_core.h>

#include <utility>

namespace shapespline::vk {

template <typename T, typename Parent, void (*Destroy)(Parent, T, const VkAllocationCallbacks*)>
class Handle {
 public:
  Handle() = default;
  Handle(Parent parent, T handle) noexcept : parent_(parent), handle_(handle) {}
  ~Handle() { reset(); }

  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept
      : parent_(other.parent_), handle_(std::exchange(other.handle_, T(VK_NULL_HANDLE))) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      parent_ = other.parent_;
      handle_ = std::exchange(other.handle_, T(VK_NULL_HANDLE));
    }
    return *this;
  }

  T get() const noexcept { return handle_; }
  Parent parent() const noexcept { return parent_; }
  explicit operator bool() const noexcept { return handle_ != T(VK_NULL_HANDLE); }

  // Gives up ownership without destroying.
  T release() noexcept { return std::exchange(handle_, T(VK_NULL_HANDLE)); }
  void reset() noexcept {
    if (handle_ != T(VK_NULL_HANDLE)) {
      Destroy(parent_, handle_, nullptr);
      handle_ = T(VK_NULL_HANDLE);
    }
  }

 private:
  Parent parent_ = Parent(VK_NULL_HANDLE);
  T handle_ = T(VK_NULL_HANDLE);
};

using BufferHandle = Handle<VkBuffer, VkDevice, vkDestroyBuffer>;
using MemoryHandle = Handle<VkDeviceMemory, VkDevice, vkFreeMemory>;
using ShaderModuleHandle = Handle<VkShaderModule, VkDevice, vkDestroyShaderModule>;
using PipelineHandle = Handle<VkPipeline, VkDevice, vkDestroyPipeline>;
using PipelineLayoutHandle = Handle<VkPipelineLayout, VkDevice, vkDestroyPipelineLayout>;
using PipelineCacheHandle = Handle<VkPipelineCache, VkDevice, vkDestroyPipelineCache>;
using DescriptorSetLayoutHandle = Handle<VkDescriptorSetLayout, VkDevice, vkDestroyDescriptorSetLayout>;
using DescriptorPoolHandle = Handle<VkDescriptorPool, VkDevice, vkDestroyDescriptorPool>;
using CommandPoolHandle = Handle<VkCommandPool, VkDevice, vkDestroyCommandPool>;
using FenceHandle = Handle<VkFence, VkDevice, vkDestroyFence>;
using QueryPoolHandle = Handle<VkQueryPool, VkDevice, vkDestroyQueryPool>;

}  // namespace shapespline::vk
