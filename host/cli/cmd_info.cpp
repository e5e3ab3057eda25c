// `shapespline info`: Vulkan devices, the one selected, fp64 support and the limits that matter.
#include <shapespline/cli/common.h>
#include <shapespline/vk/context.h>
#include <shapespline/vk/error.h>

#include <cstdio>

namespace shapespline::cli {
namespace {

void runInfo() {
  const auto devices = vk::Context::listDevices();
  std::printf("Vulkan devices: %zu\n", devices.size());
  for (const auto& d : devices) {
    std::printf("  [%u] %s (%s, Vulkan %s) fp64 %s, int64 %s, compute queue %s%s\n", d.index, d.name.c_str(),
                vk::deviceTypeName(d.type), vk::apiVersionString(d.apiVersion).c_str(), d.float64 ? "yes" : "no",
                d.int64 ? "yes" : "no", d.computeQueue ? "yes" : "no", d.usable ? "" : " (not usable)");
  }
  std::shared_ptr<vk::Context> ctx;
  try {
    ctx = vk::Context::create();
  } catch (const vk::NoDeviceError& e) {
    std::printf("selected: none (%s); sample/eval run on the CPU fp64 path\n", e.reason().c_str());
    return;
  }
  const auto& l = ctx->limits();
  std::printf("selected: [%u] %s\n", ctx->deviceInfo().index, ctx->deviceName().c_str());
  std::printf("  shaderFloat64: %s (--precision double on the GPU %s)\n", ctx->supportsFloat64() ? "yes" : "no",
              ctx->supportsFloat64() ? "available" : "falls back to the CPU");
  std::printf("  maxStorageBufferRange: %llu bytes\n", static_cast<unsigned long long>(l.maxStorageBufferRange));
  std::printf("  maxMemoryAllocationSize: %llu bytes\n", static_cast<unsigned long long>(l.maxMemoryAllocationSize));
  std::printf("  maxComputeWorkGroupCount: %u x %u x %u\n", l.maxComputeWorkGroupCount[0], l.maxComputeWorkGroupCount[1],
              l.maxComputeWorkGroupCount[2]);
  std::printf("  maxComputeWorkGroupSize: %u x %u x %u, invocations %u\n", l.maxComputeWorkGroupSize[0],
              l.maxComputeWorkGroupSize[1], l.maxComputeWorkGroupSize[2], l.maxComputeWorkGroupInvocations);
  std::printf("  maxPushConstantsSize: %u bytes\n", l.maxPushConstantsSize);
  std::printf("  unified memory: %s\n", ctx->unifiedMemory() ? "yes" : "no");
}

}  // namespace

void registerInfo(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("info", "Vulkan devices, the selected one, fp64 support and limits.");
  sub->footer(kExitCodeHelp);
  sub->callback([] { runInfo(); });
}

}  // namespace shapespline::cli
