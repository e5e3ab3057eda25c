#pragma once
// Context: one Vulkan instance + physical device + logical device with one compute queue, the
// pipeline cache and the command pool every other object in vk/ is created from. Knows nothing of
// splines. Objects created from a Context (Buffer, ComputePipeline, DescriptorSet, OneShot) keep a
// reference to it: the Context must outlive them.
#include <shapespline/vk/handle.h>

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace shapespline::vk {

class PipelineCache;
class PipelineTable;

struct ContextOptions {
  // Enable VK_LAYER_KHRONOS_validation + a VK_EXT_debug_utils messenger that records messages.
  // Also turned on by the environment variable SHAPESPLINE_VALIDATION=1. Throws VulkanError
  // (VK_ERROR_LAYER_NOT_PRESENT) when requested but the layer is not installed.
  bool validation = false;
  // Device choice: a case-insensitive name substring, or an index into listDevices(). When both are
  // empty/-1, $SHAPESPLINE_DEVICE (digits: index, otherwise a name substring) is used; when that is
  // unset, the best device by type (discrete > integrated > virtual > CPU).
  std::string deviceName;
  int deviceIndex = -1;
  // Rank devices with shaderFloat64 above those without, before the device type.
  bool preferFp64 = false;
  std::string appName = "shapespline";
  // Pipeline cache folder; empty: $SHAPESPLINE_CACHE_DIR, $XDG_CACHE_HOME/shapespline,
  // ~/.cache/shapespline. persistentPipelineCache=false keeps the cache in memory only.
  std::string cacheDir;
  bool persistentPipelineCache = true;
  // Presentation (the viewer, host/viewer): extra instance extensions (glfwGetRequiredInstanceExtensions),
  // extra device extensions (VK_KHR_swapchain), and a test the queue family must also pass
  // (graphics + present support). A device without such a family counts as unusable. Empty: the
  // headless context of every other caller.
  std::vector<std::string> instanceExtensions;
  std::vector<std::string> deviceExtensions;
  std::function<bool(VkInstance, VkPhysicalDevice, uint32_t queueFamily)> queueFamilyFilter;
};

struct DeviceInfo {
  uint32_t index = 0;  // position in vkEnumeratePhysicalDevices
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t apiVersion = 0;
  uint32_t vendorId = 0;
  uint32_t deviceId = 0;
  bool float64 = false;  // shaderFloat64
  bool int64 = false;    // shaderInt64
  bool computeQueue = false;
  bool usable = false;   // Vulkan >= 1.1 and a compute queue family
};

// "discrete", "integrated", "virtual", "cpu", "other".
const char* deviceTypeName(VkPhysicalDeviceType type);
// "1.3.230"
std::string apiVersionString(uint32_t version);

struct Limits {
  VkDeviceSize maxStorageBufferRange = 0;
  VkDeviceSize minStorageBufferOffsetAlignment = 1;
  VkDeviceSize nonCoherentAtomSize = 1;
  VkDeviceSize maxMemoryAllocationSize = 0;
  std::array<uint32_t, 3> maxComputeWorkGroupCount{};
  std::array<uint32_t, 3> maxComputeWorkGroupSize{};
  uint32_t maxComputeWorkGroupInvocations = 0;
  uint32_t maxPushConstantsSize = 0;
  uint32_t maxBoundDescriptorSets = 0;
};

struct ValidationMessage {
  VkDebugUtilsMessageSeverityFlagBitsEXT severity{};
  VkDebugUtilsMessageTypeFlagsEXT type = 0;
  std::string id;    // pMessageIdName, e.g. "VUID-vkCmdDispatch-None-02697"
  std::string text;  // pMessage
};

class Context {
 public:
  // Creates instance (Vulkan 1.1+), picks a device, creates the device with one compute queue,
  // shaderFloat64/shaderInt64/fillModeNonSolid when supported, loads the pipeline cache. Throws NoDeviceError when
  // there is no Vulkan driver or no device fits, VulkanError for any other failure.
  static std::shared_ptr<Context> create(const ContextOptions& options = {});

  // Wraps caller-owned handles; the Context never destroys them (it still creates and destroys its
  // own pipeline cache and command pool on that device). enabledFeatures: the features the caller
  // enabled on `device` (null: none, so supportsFloat64() is false). No validation messenger is
  // installed; validationMessages() stays empty.
  static std::shared_ptr<Context> adopt(VkInstance instance, VkPhysicalDevice physicalDevice,
                                        VkDevice device, uint32_t queueFamily, VkQueue queue,
                                        const VkPhysicalDeviceFeatures* enabledFeatures = nullptr,
                                        const ContextOptions& options = {});

  // Every physical device of a temporary instance (for the `info` command). Empty when there is no
  // Vulkan driver at all.
  static std::vector<DeviceInfo> listDevices();

  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physicalDevice_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  bool ownsHandles() const { return owns_; }

  const DeviceInfo& deviceInfo() const { return info_; }
  const std::string& deviceName() const { return info_.name; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  const VkPhysicalDeviceMemoryProperties& memoryProperties() const { return memory_; }
  const Limits& limits() const { return limits_; }
  bool supportsFloat64() const { return float64_; }
  bool supportsInt64() const { return int64_; }
  // fillModeNonSolid (polygonMode LINE; the renderer's wireframe of an indirect mesh), enabled by
  // create() where the device has it.
  bool supportsFillModeNonSolid() const { return fillModeNonSolid_; }
  // CPU or integrated device whose memory is device-local and host-visible+coherent: buffers are
  // mapped directly and never staged.
  bool unifiedMemory() const { return unifiedMemory_; }

  // Memory type index with all `required` flags, preferring one that also has `preferred`.
  // Returns UINT32_MAX when none of typeBits has the required flags.
  uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                          VkMemoryPropertyFlags preferred = 0) const;

  bool validationEnabled() const { return messenger_ != VK_NULL_HANDLE; }
  // Warnings and errors seen by the debug messenger since creation / the last clear. Thread-safe.
  std::vector<ValidationMessage> validationMessages() const;
  void clearValidationMessages();

  // Names an object for validation messages and debuggers; no-op without VK_EXT_debug_utils.
  void setDebugName(VkObjectType type, uint64_t handle, const char* name) const;

  PipelineCache& pipelineCache() { return *pipelineCache_; }
  // The compute pipelines compiled on this context, each distinct one once (vk/pipeline_table.h).
  PipelineTable& pipelines() { return *pipelines_; }
  VkCommandPool commandPool() const { return commandPool_.get(); }
  // Held while recording into a command buffer of commandPool() and while submitting to queue():
  // both are externally synchronized objects. Recursive so that a Buffer::upload() may stage
  // through its own OneShot while the caller is recording another.
  std::recursive_mutex& submitMutex() const { return submitMutex_; }

  void waitIdle() const;
  // Set by OneShot after VK_ERROR_DEVICE_LOST; every later submission fails fast.
  bool deviceLost() const { return deviceLost_; }
  void markDeviceLost() { deviceLost_ = true; }

  struct MessageLog;  // the messenger's user data; defined in context.cpp

 private:
  Context();
  void initDeviceData(VkPhysicalDevice physicalDevice, const VkPhysicalDeviceFeatures* enabled);
  void initOwnedObjects(const ContextOptions& options);

  bool owns_ = true;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queueFamily_ = 0;

  DeviceInfo info_;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  Limits limits_;
  bool float64_ = false;
  bool int64_ = false;
  bool fillModeNonSolid_ = false;
  bool unifiedMemory_ = false;
  bool deviceLost_ = false;

  std::unique_ptr<MessageLog> log_;
  PFN_vkSetDebugUtilsObjectNameEXT setObjectName_ = nullptr;
  std::unique_ptr<PipelineCache> pipelineCache_;
  std::unique_ptr<PipelineTable> pipelines_;
  CommandPoolHandle commandPool_;
  mutable std::recursive_mutex submitMutex_;
};

}  // namespace shapespline::vk
