#pragma once
// What `shapespline info` shows about the machine's Vulkan devices: each device, the one a
// Session would select, its fp64 support and the limits that bound a job.
#include <string>

namespace shapespline::sampling {

// Lines of text ending in '\n'. "selected: none (REASON); ..." when no device can be used; any
// Vulkan failure other than that throws DeviceError.
std::string describeDevices();

}  // namespace shapespline::sampling
