#pragma once
// Test-only fault injection (issue 7): makes the Vulkan layer fail the way real drivers and devices
// do but lavapipe never does, so the error paths above it (clear message, exit code 3, no partial
// output, no leak) can be tested. Chosen by the environment variable SHAPESPLINE_FAULT, read once
// per process on first use:
//   alloc         every Buffer::create throws VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY), before
//                 any Vulkan object is created
//   alloc:N       the first N-1 Buffer::create calls succeed, every later one throws as above
//   device_lost   OneShot::submitAndWait marks the Context lost and throws
//                 VulkanError(VK_ERROR_DEVICE_LOST) instead of submitting
//   no_device     Context::create throws NoDeviceError and Context::listDevices() returns nothing
// Unset or empty: no fault. Any other value is ignored with a message on stderr. Every injected
// error says "(injected by SHAPESPLINE_FAULT)" so it is never mistaken for a real one.
#include <cstdint>
#include <string_view>

namespace shapespline::vk {

enum class Fault { None, Alloc, DeviceLost, NoDevice };

struct FaultPlan {
  Fault fault = Fault::None;
  uint64_t firstFailingAllocation = 1;  // Alloc only: 1-based index of the first Buffer::create that fails
};

// Parses a SHAPESPLINE_FAULT value ("" -> none). Returns false for an unknown value.
bool parseFault(std::string_view text, FaultPlan& plan);

// The active plan: $SHAPESPLINE_FAULT, unless overridden by setFaultForTesting.
FaultPlan activeFault();
// Replaces the plan for this process and restarts the allocation count (unit tests).
void setFaultForTesting(const FaultPlan& plan);

// Hooks used by vk/ itself. `allocationFaultDue` counts Buffer::create calls.
bool allocationFaultDue();
bool deviceLostFaultDue();
bool noDeviceFaultDue();

// Appended to the message of every injected error.
inline constexpr const char* kInjectedNote = " (injected by SHAPESPLINE_FAULT)";

}  // namespace shapespline::vk
