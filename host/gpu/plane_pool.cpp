#include <shapespline/gpu/plane_pool.h>

namespace shapespline::gpu {

const vk::Buffer& PlanePool::acquire(vk::Context& ctx, int slot, int field, VkDeviceSize bytes) {
  vk::Buffer& plane = planes_.at(size_t(slot)).at(size_t(field));
  if (plane.handle() == VK_NULL_HANDLE || plane.size() < bytes) {
    plane = vk::Buffer();  // free the old one first: peak memory stays at one plane
    plane = vk::Buffer::create(ctx, bytes, vk::kStorageUsage, vk::MemoryUse::Readback, "gpu.plane");
  }
  return plane;
}

void PlanePool::trim(VkDeviceSize maxKeptBytes) {
  for (auto& slot : planes_)
    for (vk::Buffer& plane : slot)
      if (plane.handle() != VK_NULL_HANDLE && plane.size() > maxKeptBytes) plane = vk::Buffer();
}

}  // namespace shapespline::gpu
