#pragma once
// What a front end asks of the sampling layer (DeviceRequest), what it gets back about the path
// taken (Report), and the one error type of the layer (DeviceError).
#include <shapespline/core/sample_grid.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace shapespline::sampling {

// Auto and Vulkan both use the GPU where it handles the job and fall back to the CPU with a reason
// otherwise; Cpu never touches Vulkan. `require` turns every fallback into a DeviceError.
enum class DeviceKind { Auto, Vulkan, Cpu };

struct DeviceRequest {
  DeviceKind device = DeviceKind::Auto;
  Precision precision = Precision::Double;  // of the results handed to the sink
  bool require = false;
  // A grid job (Session::sampleGrid sets it; so does a front end that plans one): a surface net
  // too large for one device buffer is then sampled on the GPU in bands of patch rows instead of
  // falling back to the CPU. List evaluation needs the whole net on the device.
  bool grid = false;
};

struct Report {
  std::string device = "cpu";                      // "cpu" or the Vulkan device's name
  bool gpu = false;
  Precision computedPrecision = Precision::Double;  // the CPU path computes in fp64 whatever is asked
  Precision outputPrecision = Precision::Double;
  std::vector<std::string> fallbacks;              // why the GPU was not used, in the order found
  int netScaleExponent = 0;                        // the job evaluates 2^k * net (net_scale.h), on either path
  int bandRows = 0;                                // GPU grid in bands of this many patch rows; 0: the whole net
};

// A Vulkan failure (with a hint what to change), or a fallback refused because the request
// required the device (fallbackRefused()).
class DeviceError : public std::runtime_error {
 public:
  DeviceError(const std::string& message, bool fallbackRefused)
      : std::runtime_error(message), fallbackRefused_(fallbackRefused) {}
  bool fallbackRefused() const noexcept { return fallbackRefused_; }

 private:
  bool fallbackRefused_;
};

}  // namespace shapespline::sampling
