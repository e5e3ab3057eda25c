#include <shapespline/sampling/devices.h>

#include <shapespline/sampling/report.h>
#include <shapespline/vk/context.h>
#include <shapespline/vk/error.h>

#include <cstdarg>
#include <cstdio>

namespace shapespline::sampling {
namespace {

void append(std::string& out, const char* format, ...) {
  char line[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(line, sizeof line, format, args);
  va_end(args);
  out += line;
}

}  // namespace

std::string describeDevices() {
  std::string out;
  try {
    const auto devices = vk::Context::listDevices();
    append(out, "Vulkan devices: %zu\n", devices.size());
    for (const auto& d : devices) {
      append(out, "  [%u] %s (%s, Vulkan %s) fp64 %s, int64 %s, compute queue %s%s\n", d.index, d.name.c_str(),
             vk::deviceTypeName(d.type), vk::apiVersionString(d.apiVersion).c_str(), d.float64 ? "yes" : "no",
             d.int64 ? "yes" : "no", d.computeQueue ? "yes" : "no", d.usable ? "" : " (not usable)");
    }
    std::shared_ptr<vk::Context> ctx;
    try {
      ctx = vk::Context::create();
    } catch (const vk::NoDeviceError& e) {
      append(out, "selected: none (%s); sample/eval run on the CPU fp64 path\n", e.reason().c_str());
      return out;
    }
    const auto& l = ctx->limits();
    append(out, "selected: [%u] %s\n", ctx->deviceInfo().index, ctx->deviceName().c_str());
    append(out, "  shaderFloat64: %s (--precision double on the GPU %s)\n", ctx->supportsFloat64() ? "yes" : "no",
           ctx->supportsFloat64() ? "available" : "falls back to the CPU");
    append(out, "  maxStorageBufferRange: %llu bytes\n", static_cast<unsigned long long>(l.maxStorageBufferRange));
    append(out, "  maxMemoryAllocationSize: %llu bytes\n", static_cast<unsigned long long>(l.maxMemoryAllocationSize));
    append(out, "  maxComputeWorkGroupCount: %u x %u x %u\n", l.maxComputeWorkGroupCount[0],
           l.maxComputeWorkGroupCount[1], l.maxComputeWorkGroupCount[2]);
    append(out, "  maxComputeWorkGroupSize: %u x %u x %u, invocations %u\n", l.maxComputeWorkGroupSize[0],
           l.maxComputeWorkGroupSize[1], l.maxComputeWorkGroupSize[2], l.maxComputeWorkGroupInvocations);
    append(out, "  maxPushConstantsSize: %u bytes\n", l.maxPushConstantsSize);
    append(out, "  unified memory: %s\n", ctx->unifiedMemory() ? "yes" : "no");
  } catch (const vk::NoDeviceError&) {
    throw;
  } catch (const vk::VulkanError& e) {
    throw DeviceError(std::string(e.what()) + "; --device cpu avoids the GPU", false);
  }
  return out;
}

}  // namespace shapespline::sampling
