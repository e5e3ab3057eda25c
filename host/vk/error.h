#pragma once
// Typed errors of the Vulkan layer: every failed VkResult becomes a VulkanError that carries the
// result and what was being attempted; "no suitable device" is a NoDeviceError callers can catch
// and treat as an ordinary outcome (skip GPU work, fall back to the CPU path).
#include <vulkan/vulkan_core.h>

#include <stdexcept>
#include <string>

namespace shapespline::vk {

// "VK_ERROR_DEVICE_LOST" etc.; "VkResult(<n>)" for values this header does not know.
const char* resultName(VkResult result);

class VulkanError : public std::runtime_error {
 public:
  // attempted: what was being done, e.g. "vkAllocateMemory (4096 bytes for a storage buffer)".
  VulkanError(VkResult result, std::string attempted);
  VulkanError(VkResult result, std::string attempted, const std::string& message);

  VkResult result() const noexcept { return result_; }
  const std::string& attempted() const noexcept { return attempted_; }

 private:
  VkResult result_;
  std::string attempted_;
};

// No Vulkan loader/driver, no device with Vulkan 1.1 and a compute queue, or none that matches the
// requested name/index. reason() says which.
class NoDeviceError : public VulkanError {
 public:
  NoDeviceError(VkResult result, const std::string& reason);
  const std::string& reason() const noexcept { return attempted(); }
};

// Throws VulkanError(result, what) unless result is VK_SUCCESS. Positive non-success codes
// (VK_TIMEOUT, VK_INCOMPLETE, VK_NOT_READY) throw too: call sites that expect them test first.
inline void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS) [[unlikely]] {
    throw VulkanError(result, what);
  }
}

}  // namespace shapespline::vk
