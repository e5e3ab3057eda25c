#pragma once
// Readback planes kept from one grid job to the next. On lavapipe (and any unified-memory device)
// a new readback buffer is new host memory: the kernel's first write to each page faults and the
// kernel zeroes the page, which cost 14% of a 3.8 M-point fp32 job (perf, S = 32 bicubic). The
// chunk ring therefore takes its planes from here, reallocating only a plane that is too small,
// and trim() drops any plane over the job's plane budget, so what stays held is bounded by
// slots x fields x maxPlaneBytes.
#include <shapespline/core/sample_grid.h>
#include <shapespline/vk/buffer.h>

#include <array>

namespace shapespline::gpu {

class PlanePool {
 public:
  static constexpr int kSlots = 2;

  // A host-visible storage buffer of at least `bytes` for output `field` of ring slot `slot`.
  const vk::Buffer& acquire(vk::Context& ctx, int slot, int field, VkDeviceSize bytes);
  // Drops the planes larger than `maxKeptBytes` (one-off jobs whose items exceed the budget).
  void trim(VkDeviceSize maxKeptBytes);

 private:
  std::array<std::array<vk::Buffer, kFieldCount>, kSlots> planes_;
};

}  // namespace shapespline::gpu
