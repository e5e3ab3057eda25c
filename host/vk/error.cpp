#include <shapespline/vk/error.h>

namespace shapespline::vk {

const char* resultName(VkResult result) {
  switch (result) {
#define SHAPESPLINE_RESULT(name) \
  case name:                     \
    return #name;
    SHAPESPLINE_RESULT(VK_SUCCESS)
    SHAPESPLINE_RESULT(VK_NOT_READY)
    SHAPESPLINE_RESULT(VK_TIMEOUT)
    SHAPESPLINE_RESULT(VK_EVENT_SET)
    SHAPESPLINE_RESULT(VK_EVENT_RESET)
    SHAPESPLINE_RESULT(VK_INCOMPLETE)
    SHAPESPLINE_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
    SHAPESPLINE_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    SHAPESPLINE_RESULT(VK_ERROR_INITIALIZATION_FAILED)
    SHAPESPLINE_RESULT(VK_ERROR_DEVICE_LOST)
    SHAPESPLINE_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
    SHAPESPLINE_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
    SHAPESPLINE_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
    SHAPESPLINE_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
    SHAPESPLINE_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
    SHAPESPLINE_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
    SHAPESPLINE_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
    SHAPESPLINE_RESULT(VK_ERROR_FRAGMENTED_POOL)
    SHAPESPLINE_RESULT(VK_ERROR_UNKNOWN)
    SHAPESPLINE_RESULT(VK_ERROR_OUT_OF_POOL_MEMORY)
    SHAPESPLINE_RESULT(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    SHAPESPLINE_RESULT(VK_ERROR_FRAGMENTATION)
    SHAPESPLINE_RESULT(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
    SHAPESPLINE_RESULT(VK_PIPELINE_COMPILE_REQUIRED)
    SHAPESPLINE_RESULT(VK_ERROR_VALIDATION_FAILED_EXT)
    SHAPESPLINE_RESULT(VK_ERROR_INVALID_SHADER_NV)
#undef SHAPESPLINE_RESULT
    default:
      return nullptr;
  }
}

namespace {

std::string describe(VkResult result, const std::string& attempted) {
  const char* name = resultName(result);
  std::string text = attempted + " failed: " +
                     (name ? std::string(name) : "VkResult(" + std::to_string(int(result)) + ")");
  // Device loss is the one error people misread as a bug in the call that reported it: say what
  // it means and that the context is finished.
  if (result == VK_ERROR_DEVICE_LOST) {
    text += " (the GPU was lost: driver reset, hang/timeout detection or a crash; this Vulkan "
            "context cannot be used any more)";
  }
  return text;
}

}  // namespace

VulkanError::VulkanError(VkResult result, std::string attempted)
    : std::runtime_error(describe(result, attempted)), result_(result), attempted_(std::move(attempted)) {}

VulkanError::VulkanError(VkResult result, std::string attempted, const std::string& message)
    : std::runtime_error(message), result_(result), attempted_(std::move(attempted)) {}

NoDeviceError::NoDeviceError(VkResult result, const std::string& reason)
    : VulkanError(result, reason, "no suitable Vulkan device: " + reason) {}

}  // namespace shapespline::vk
