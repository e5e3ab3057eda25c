#include <shapespline/vk/context.h>

#include <shapespline/vk/error.h>
#include <shapespline/vk/fault.h>
#include <shapespline/vk/pipeline_cache.h>
#include <shapespline/vk/pipeline_table.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>

namespace shapespline::vk {

struct Context::MessageLog {
  mutable std::mutex mutex;
  std::vector<ValidationMessage> messages;
  bool echo = false;  // also print to stderr (validation turned on from the environment)
};

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr uint32_t kMinApiVersion = VK_API_VERSION_1_1;

std::optional<std::string> env(const char* name) {
  const char* value = std::getenv(name);
  if (value == nullptr || *value == '\0') return std::nullopt;
  return std::string(value);
}

bool envFlag(const char* name) {
  auto value = env(name);
  return value && *value != "0" && *value != "false" && *value != "off";
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

bool allDigits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

VKAPI_ATTR VkBool32 VKAPI_CALL onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT type,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data,
                                              void* user) {
  auto* log = static_cast<Context::MessageLog*>(user);
  ValidationMessage message;
  message.severity = severity;
  message.type = type;
  if (data->pMessageIdName) message.id = data->pMessageIdName;
  if (data->pMessage) message.text = data->pMessage;
  if (log->echo) {
    std::fprintf(stderr, "[vulkan %s] %s\n",
                 severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning",
                 message.text.c_str());
  }
  std::lock_guard lock(log->mutex);
  log->messages.push_back(std::move(message));
  // VK_FALSE: the spec reserves VK_TRUE (skip the call) for layer development.
  return VK_FALSE;
}

VkDebugUtilsMessengerCreateInfoEXT messengerInfo(Context::MessageLog* log) {
  VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  info.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  info.pfnUserCallback = onDebugMessage;
  info.pUserData = log;
  return info;
}

bool hasLayer(const char* name) {
  uint32_t count = 0;
  if (vkEnumerateInstanceLayerProperties(&count, nullptr) != VK_SUCCESS) return false;
  std::vector<VkLayerProperties> layers(count);
  if (vkEnumerateInstanceLayerProperties(&count, layers.data()) != VK_SUCCESS) return false;
  return std::any_of(layers.begin(), layers.begin() + count,
                     [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool hasInstanceExtension(const char* layer, const char* name) {
  uint32_t count = 0;
  if (vkEnumerateInstanceExtensionProperties(layer, &count, nullptr) != VK_SUCCESS) return false;
  std::vector<VkExtensionProperties> exts(count);
  if (vkEnumerateInstanceExtensionProperties(layer, &count, exts.data()) != VK_SUCCESS) return false;
  return std::any_of(exts.begin(), exts.begin() + count,
                     [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

// Creates the instance; `log` non-null turns on validation with a messenger chained into instance
// creation so that messages from vkCreateInstance/vkDestroyInstance are caught too.
VkInstance createInstance(const std::string& appName, Context::MessageLog* log,
                          const std::vector<std::string>& extraExtensions = {}) {
  uint32_t loaderVersion = VK_API_VERSION_1_0;
  if (vkEnumerateInstanceVersion(&loaderVersion) != VK_SUCCESS || loaderVersion < kMinApiVersion) {
    throw NoDeviceError(VK_ERROR_INCOMPATIBLE_DRIVER,
                        "the Vulkan loader supports only " + apiVersionString(loaderVersion) +
                            "; shapespline needs Vulkan 1.1");
  }
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = appName.c_str();
  app.pEngineName = "shapespline";
  app.apiVersion = kMinApiVersion;

  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  // MoltenVK and other non-conformant drivers are only listed with portability enumeration.
  if (hasInstanceExtension(nullptr, VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME)) {
    extensions.push_back(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME);
    info.flags |= VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
  }
  for (const std::string& e : extraExtensions) extensions.push_back(e.c_str());
  VkDebugUtilsMessengerCreateInfoEXT debugInfo{};
  if (log) {
    if (!hasLayer(kValidationLayer)) {
      throw VulkanError(VK_ERROR_LAYER_NOT_PRESENT,
                        "enabling validation (VK_LAYER_KHRONOS_validation is not installed; "
                        "Debian: vulkan-validationlayers)");
    }
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    debugInfo = messengerInfo(log);
    info.pNext = &debugInfo;
  }
  info.pApplicationInfo = &app;
  info.enabledLayerCount = uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();

  VkInstance instance = VK_NULL_HANDLE;
  VkResult result = vkCreateInstance(&info, nullptr, &instance);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER) {
    throw NoDeviceError(result, "no Vulkan driver (ICD) is installed");
  }
  check(result, "vkCreateInstance");
  return instance;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
  uint32_t count = 0;
  check(vkEnumeratePhysicalDevices(instance, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  VkResult result = vkEnumeratePhysicalDevices(instance, &count, devices.data());
  if (result != VK_INCOMPLETE) check(result, "vkEnumeratePhysicalDevices");
  devices.resize(count);
  return devices;
}

// The first compute family that also passes `filter` (ContextOptions::queueFamilyFilter) when set.
using QueueFamilyFilter = std::function<bool(VkPhysicalDevice, uint32_t)>;
std::optional<uint32_t> computeQueueFamily(VkPhysicalDevice device, const QueueFamilyFilter& filter = {}) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  for (uint32_t i = 0; i < count; ++i) {
    if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) && families[i].queueCount > 0 && (!filter || filter(device, i)))
      return i;
  }
  return std::nullopt;
}

DeviceInfo queryDevice(VkPhysicalDevice device, uint32_t index, const QueueFamilyFilter& filter = {}) {
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(device, &props);
  VkPhysicalDeviceFeatures features;
  vkGetPhysicalDeviceFeatures(device, &features);
  DeviceInfo info;
  info.index = index;
  info.name = props.deviceName;
  info.type = props.deviceType;
  info.apiVersion = props.apiVersion;
  info.vendorId = props.vendorID;
  info.deviceId = props.deviceID;
  info.float64 = features.shaderFloat64 == VK_TRUE;
  info.int64 = features.shaderInt64 == VK_TRUE;
  info.computeQueue = computeQueueFamily(device, filter).has_value();
  info.usable = info.computeQueue && props.apiVersion >= kMinApiVersion;
  return info;
}

int typeRank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
  }
}

std::string deviceList(const std::vector<DeviceInfo>& infos) {
  std::string text;
  for (const DeviceInfo& d : infos) {
    text += "\n  [" + std::to_string(d.index) + "] " + d.name + " (" + deviceTypeName(d.type) +
            ", Vulkan " + apiVersionString(d.apiVersion) + (d.usable ? "" : ", unusable") + ")";
  }
  return text;
}

// Returns the index into `infos` of the device to use, or throws NoDeviceError.
uint32_t selectDevice(const std::vector<DeviceInfo>& infos, const ContextOptions& options) {
  if (infos.empty()) throw NoDeviceError(VK_ERROR_INITIALIZATION_FAILED, "the Vulkan driver lists no devices");

  int wantIndex = options.deviceIndex;
  std::string wantName = options.deviceName;
  std::string source = "options";
  if (wantIndex < 0 && wantName.empty()) {
    if (auto fromEnv = env("SHAPESPLINE_DEVICE")) {
      source = "SHAPESPLINE_DEVICE";
      if (allDigits(*fromEnv)) {
        wantIndex = std::atoi(fromEnv->c_str());
      } else {
        wantName = *fromEnv;
      }
    }
  }
  if (wantIndex >= 0) {
    if (size_t(wantIndex) >= infos.size() || !infos[size_t(wantIndex)].usable) {
      throw NoDeviceError(VK_ERROR_INITIALIZATION_FAILED,
                          "device index " + std::to_string(wantIndex) + " (from " + source +
                              ") is not a usable device; devices:" + deviceList(infos));
    }
    return uint32_t(wantIndex);
  }

  const std::string needle = lower(wantName);
  std::optional<uint32_t> best;
  auto better = [&](const DeviceInfo& a, const DeviceInfo& b) {
    if (options.preferFp64 && a.float64 != b.float64) return a.float64;
    return typeRank(a.type) > typeRank(b.type);
  };
  for (uint32_t i = 0; i < infos.size(); ++i) {
    const DeviceInfo& d = infos[i];
    if (!d.usable) continue;
    if (!needle.empty() && lower(d.name).find(needle) == std::string::npos) continue;
    if (!best || better(d, infos[*best])) best = i;
  }
  if (!best) {
    const char* queue = options.queueFamilyFilter
                            ? "a compute queue family that also passes the caller's queue test (e.g. graphics + present)"
                            : "a compute queue";
    std::string why = needle.empty() ? std::string("no device supports Vulkan 1.1 with ") + queue
                                     : "no usable device name contains \"" + wantName + "\" (from " + source + ")";
    throw NoDeviceError(VK_ERROR_INITIALIZATION_FAILED, why + "; devices:" + deviceList(infos));
  }
  return *best;
}

}  // namespace

const char* deviceTypeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

std::string apiVersionString(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

Context::Context() : log_(std::make_unique<MessageLog>()) {}

Context::~Context() {
  if (device_ != VK_NULL_HANDLE) vkDeviceWaitIdle(device_);  // result ignored: nothing to do about it here
  pipelines_.reset();      // pipelines before their device
  pipelineCache_.reset();  // saves to disk while the device is alive
  commandPool_.reset();
  if (!owns_) return;
  if (device_ != VK_NULL_HANDLE) vkDestroyDevice(device_, nullptr);
  if (messenger_ != VK_NULL_HANDLE) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

std::shared_ptr<Context> Context::create(const ContextOptions& options) {
  if (noDeviceFaultDue())
    throw NoDeviceError(VK_ERROR_INITIALIZATION_FAILED, std::string("no Vulkan device") + kInjectedNote);
  std::shared_ptr<Context> ctx(new Context());
  const bool fromEnv = envFlag("SHAPESPLINE_VALIDATION");
  const bool validation = options.validation || fromEnv;
  ctx->log_->echo = fromEnv && !options.validation;
  ctx->instance_ = createInstance(options.appName, validation ? ctx->log_.get() : nullptr, options.instanceExtensions);

  if (validation) {
    auto createMessenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(ctx->instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (!createMessenger) {
      throw VulkanError(VK_ERROR_EXTENSION_NOT_PRESENT, "vkGetInstanceProcAddr(vkCreateDebugUtilsMessengerEXT)");
    }
    VkDebugUtilsMessengerCreateInfoEXT info = messengerInfo(ctx->log_.get());
    check(createMessenger(ctx->instance_, &info, nullptr, &ctx->messenger_), "vkCreateDebugUtilsMessengerEXT");
    ctx->setObjectName_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(ctx->instance_, "vkSetDebugUtilsObjectNameEXT"));
  }

  std::vector<VkPhysicalDevice> devices = physicalDevices(ctx->instance_);
  QueueFamilyFilter filter;
  if (options.queueFamilyFilter) {
    filter = [&options, instance = ctx->instance_](VkPhysicalDevice d, uint32_t family) {
      return options.queueFamilyFilter(instance, d, family);
    };
  }
  std::vector<DeviceInfo> infos;
  for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(queryDevice(devices[i], i, filter));
  const uint32_t chosen = selectDevice(infos, options);
  VkPhysicalDevice physical = devices[chosen];

  VkPhysicalDeviceFeatures supported;
  vkGetPhysicalDeviceFeatures(physical, &supported);
  VkPhysicalDeviceFeatures enabled{};
  enabled.shaderFloat64 = supported.shaderFloat64;
  enabled.shaderInt64 = supported.shaderInt64;
  enabled.fillModeNonSolid = supported.fillModeNonSolid;

  ctx->queueFamily_ = *computeQueueFamily(physical, filter);
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = ctx->queueFamily_;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;

  std::vector<const char*> extensions;
  {
    // A portability-subset device must have that extension enabled (VUID-VkDeviceCreateInfo-pProperties-04451).
    uint32_t count = 0;
    check(vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, nullptr), "vkEnumerateDeviceExtensionProperties");
    std::vector<VkExtensionProperties> exts(count);
    check(vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, exts.data()), "vkEnumerateDeviceExtensionProperties");
    for (const auto& e : exts) {
      if (std::strcmp(e.extensionName, "VK_KHR_portability_subset") == 0) extensions.push_back("VK_KHR_portability_subset");
    }
    for (const std::string& want : options.deviceExtensions) {
      if (std::none_of(exts.begin(), exts.end(), [&](const VkExtensionProperties& e) { return want == e.extensionName; }))
        throw NoDeviceError(VK_ERROR_EXTENSION_NOT_PRESENT,
                            "device '" + infos[chosen].name + "' lacks the extension " + want);
      extensions.push_back(want.c_str());
    }
  }
  VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  deviceInfo.queueCreateInfoCount = 1;
  deviceInfo.pQueueCreateInfos = &queueInfo;
  deviceInfo.enabledExtensionCount = uint32_t(extensions.size());
  deviceInfo.ppEnabledExtensionNames = extensions.data();
  deviceInfo.pEnabledFeatures = &enabled;
  check(vkCreateDevice(physical, &deviceInfo, nullptr, &ctx->device_),
        ("vkCreateDevice (" + infos[chosen].name + ")").c_str());
  vkGetDeviceQueue(ctx->device_, ctx->queueFamily_, 0, &ctx->queue_);

  ctx->initDeviceData(physical, &enabled);
  ctx->info_.index = chosen;
  ctx->initOwnedObjects(options);
  return ctx;
}

std::shared_ptr<Context> Context::adopt(VkInstance instance, VkPhysicalDevice physicalDevice, VkDevice device,
                                        uint32_t queueFamily, VkQueue queue,
                                        const VkPhysicalDeviceFeatures* enabledFeatures,
                                        const ContextOptions& options) {
  if (!instance || !physicalDevice || !device || !queue) {
    throw std::invalid_argument("Context::adopt: instance, physicalDevice, device and queue must be non-null");
  }
  std::shared_ptr<Context> ctx(new Context());
  ctx->owns_ = false;
  ctx->instance_ = instance;
  ctx->device_ = device;
  ctx->queue_ = queue;
  ctx->queueFamily_ = queueFamily;
  VkPhysicalDeviceFeatures none{};
  ctx->initDeviceData(physicalDevice, enabledFeatures ? enabledFeatures : &none);
  ctx->initOwnedObjects(options);
  return ctx;
}

void Context::initDeviceData(VkPhysicalDevice physical, const VkPhysicalDeviceFeatures* enabled) {
  physicalDevice_ = physical;
  info_ = queryDevice(physical, 0);
  float64_ = enabled->shaderFloat64 == VK_TRUE;
  int64_ = enabled->shaderInt64 == VK_TRUE;
  fillModeNonSolid_ = enabled->fillModeNonSolid == VK_TRUE;

  VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props2.pNext = &maintenance3;
  vkGetPhysicalDeviceProperties2(physical, &props2);
  properties_ = props2.properties;
  vkGetPhysicalDeviceMemoryProperties(physical, &memory_);

  const VkPhysicalDeviceLimits& l = properties_.limits;
  limits_.maxStorageBufferRange = l.maxStorageBufferRange;
  limits_.minStorageBufferOffsetAlignment = std::max<VkDeviceSize>(1, l.minStorageBufferOffsetAlignment);
  limits_.nonCoherentAtomSize = std::max<VkDeviceSize>(1, l.nonCoherentAtomSize);
  limits_.maxMemoryAllocationSize = maintenance3.maxMemoryAllocationSize;
  for (int i = 0; i < 3; ++i) {
    limits_.maxComputeWorkGroupCount[i] = l.maxComputeWorkGroupCount[i];
    limits_.maxComputeWorkGroupSize[i] = l.maxComputeWorkGroupSize[i];
  }
  limits_.maxComputeWorkGroupInvocations = l.maxComputeWorkGroupInvocations;
  limits_.maxPushConstantsSize = l.maxPushConstantsSize;
  limits_.maxBoundDescriptorSets = l.maxBoundDescriptorSets;

  const bool sharedType = findMemoryType(~0u,
                                         VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                             VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != UINT32_MAX;
  unifiedMemory_ = sharedType && (info_.type == VK_PHYSICAL_DEVICE_TYPE_CPU ||
                                  info_.type == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU);
}

void Context::initOwnedObjects(const ContextOptions& options) {
  std::filesystem::path dir;
  if (options.persistentPipelineCache) {
    dir = options.cacheDir.empty() ? PipelineCache::defaultDirectory() : std::filesystem::path(options.cacheDir);
  }
  pipelineCache_ = std::make_unique<PipelineCache>(device_, properties_, dir);
  pipelines_ = std::make_unique<PipelineTable>(*this);

  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  // TRANSIENT: one-shot command buffers are recorded once and freed after the fence.
  poolInfo.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  poolInfo.queueFamilyIndex = queueFamily_;
  VkCommandPool pool = VK_NULL_HANDLE;
  check(vkCreateCommandPool(device_, &poolInfo, nullptr, &pool), "vkCreateCommandPool");
  commandPool_ = CommandPoolHandle(device_, pool);
}

std::vector<DeviceInfo> Context::listDevices() {
  if (noDeviceFaultDue()) return {};
  VkInstance instance = VK_NULL_HANDLE;
  try {
    instance = createInstance("shapespline", nullptr);
  } catch (const NoDeviceError&) {
    return {};
  }
  std::vector<DeviceInfo> infos;
  try {
    std::vector<VkPhysicalDevice> devices = physicalDevices(instance);
    for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(queryDevice(devices[i], i));
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
  vkDestroyInstance(instance, nullptr);
  return infos;
}

uint32_t Context::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                                 VkMemoryPropertyFlags preferred) const {
  uint32_t fallback = UINT32_MAX;
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    if (!(typeBits & (1u << i))) continue;
    const VkMemoryPropertyFlags flags = memory_.memoryTypes[i].propertyFlags;
    if ((flags & required) != required) continue;
    if ((flags & preferred) == preferred) return i;
    if (fallback == UINT32_MAX) fallback = i;
  }
  return fallback;
}

std::vector<ValidationMessage> Context::validationMessages() const {
  std::lock_guard lock(log_->mutex);
  return log_->messages;
}

void Context::clearValidationMessages() {
  std::lock_guard lock(log_->mutex);
  log_->messages.clear();
}

void Context::setDebugName(VkObjectType type, uint64_t handle, const char* name) const {
  if (!setObjectName_ || !name || !*name) return;
  VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name;
  setObjectName_(device_, &info);  // a failed name is not worth an exception
}

void Context::waitIdle() const {
  std::lock_guard lock(submitMutex_);
  check(vkDeviceWaitIdle(device_), "vkDeviceWaitIdle");
}

}  // namespace shapespline::vk
