#include <shapespline/vk/buffer.h>

#include <shapespline/vk/error.h>
#include <shapespline/vk/fault.h>
#include <shapespline/vk/submit.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

namespace shapespline::vk {

namespace {

constexpr VkMemoryPropertyFlags kHostVisible = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
constexpr VkMemoryPropertyFlags kHostCoherent = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
constexpr VkMemoryPropertyFlags kHostCached = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
constexpr VkMemoryPropertyFlags kDeviceLocal = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;

const char* useName(MemoryUse use) {
  switch (use) {
    case MemoryUse::Upload: return "upload";
    case MemoryUse::Readback: return "readback";
    case MemoryUse::DeviceLocal: return "device-local";
  }
  return "?";
}

std::string describeAllocation(VkDeviceSize bytes, MemoryUse use, const char* label) {
  std::string s = std::to_string(bytes) + " bytes of " + useName(use) + " memory";
  if (label && *label) s += std::string(" for ") + label;
  return s;
}

struct MemoryChoice {
  VkMemoryPropertyFlags required;
  VkMemoryPropertyFlags preferred;
};

MemoryChoice chooseMemory(const Context& ctx, MemoryUse use) {
  // Unified memory: the same RAM either way, so map everything and never stage.
  if (ctx.unifiedMemory()) return {kHostVisible | kHostCoherent, kDeviceLocal};
  switch (use) {
    case MemoryUse::Upload: return {kHostVisible | kHostCoherent, kDeviceLocal};
    // Cached: the host reads it back, and uncached reads over PCIe are very slow.
    case MemoryUse::Readback: return {kHostVisible, kHostCached | kHostCoherent};
    case MemoryUse::DeviceLocal: return {kDeviceLocal, 0};
  }
  return {0, 0};
}

// The non-coherent flush/invalidate range covering [offset, offset + bytes), aligned to
// nonCoherentAtomSize as VUID-VkMappedMemoryRange-offset-00687/-size-01390 require.
VkMappedMemoryRange atomRange(const Context& ctx, VkDeviceMemory memory, VkDeviceSize allocationSize,
                              VkDeviceSize offset, VkDeviceSize bytes) {
  const VkDeviceSize atom = ctx.limits().nonCoherentAtomSize;
  VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
  range.memory = memory;
  range.offset = offset / atom * atom;
  const VkDeviceSize end = (offset + bytes + atom - 1) / atom * atom;
  range.size = end >= allocationSize ? VK_WHOLE_SIZE : end - range.offset;
  return range;
}

}  // namespace

Buffer Buffer::create(Context& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage, MemoryUse use, const char* label) {
  if (bytes == 0) throw std::invalid_argument("Buffer::create: size must be > 0");
  const VkDevice device = ctx.device();
  const std::string what = describeAllocation(bytes, use, label);
  if (allocationFaultDue())
    throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, "vkAllocateMemory (" + what + ")" + kInjectedNote);
  const VkDeviceSize maxAllocation = ctx.limits().maxMemoryAllocationSize;
  // Checked up front: the driver's behaviour for oversized requests ranges from an error to a
  // validation message to a crash, and the caller needs a clear VK_ERROR_OUT_OF_DEVICE_MEMORY.
  if (maxAllocation != 0 && bytes > maxAllocation) {
    throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, "allocating " + what,
                      "cannot allocate " + what + ": exceeds maxMemoryAllocationSize " +
                          std::to_string(maxAllocation) + " (VK_ERROR_OUT_OF_DEVICE_MEMORY)");
  }

  Buffer b;
  b.ctx_ = &ctx;
  b.size_ = bytes;
  b.usage_ = usage;
  b.use_ = use;

  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = bytes;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer buffer = VK_NULL_HANDLE;
  check(vkCreateBuffer(device, &info, nullptr, &buffer), ("vkCreateBuffer (" + what + ")").c_str());
  b.buffer_ = BufferHandle(device, buffer);
  ctx.setDebugName(VK_OBJECT_TYPE_BUFFER, uint64_t(buffer), label);

  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device, buffer, &req);
  const MemoryChoice choice = chooseMemory(ctx, use);
  const uint32_t type = ctx.findMemoryType(req.memoryTypeBits, choice.required, choice.preferred);
  if (type == UINT32_MAX) {
    throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, "allocating " + what,
                      "cannot allocate " + what + ": no memory type has the required properties "
                      "(VK_ERROR_OUT_OF_DEVICE_MEMORY)");
  }
  const VkMemoryType& memoryType = ctx.memoryProperties().memoryTypes[type];
  const VkDeviceSize heapSize = ctx.memoryProperties().memoryHeaps[memoryType.heapIndex].size;
  if (req.size > heapSize || (maxAllocation != 0 && req.size > maxAllocation)) {
    throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, "allocating " + what,
                      "cannot allocate " + what + ": needs " + std::to_string(req.size) + " bytes, heap " +
                          std::to_string(memoryType.heapIndex) + " has " + std::to_string(heapSize) +
                          " (VK_ERROR_OUT_OF_DEVICE_MEMORY)");
  }

  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = type;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkResult result = vkAllocateMemory(device, &alloc, nullptr, &memory);
  if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY) {
    // Reported as out of device memory whichever pool ran dry: the caller's remedy (smaller
    // chunks) is the same; the original code stays in the message.
    throw VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY, "allocating " + what,
                      "cannot allocate " + what + ": vkAllocateMemory returned " + resultName(result));
  }
  check(result, ("vkAllocateMemory (" + what + ")").c_str());
  b.memory_ = MemoryHandle(device, memory);
  b.allocationSize_ = req.size;
  b.flags_ = memoryType.propertyFlags;
  check(vkBindBufferMemory(device, buffer, memory, 0), "vkBindBufferMemory");

  if (b.flags_ & kHostVisible) {
    void* ptr = nullptr;
    check(vkMapMemory(device, memory, 0, VK_WHOLE_SIZE, 0, &ptr), ("vkMapMemory (" + what + ")").c_str());
    b.mapped_ = static_cast<std::byte*>(ptr);
  }
  return b;
}

Buffer::Buffer(Buffer&& other) noexcept
    : ctx_(other.ctx_),
      memory_(std::move(other.memory_)),
      buffer_(std::move(other.buffer_)),
      size_(std::exchange(other.size_, 0)),
      allocationSize_(std::exchange(other.allocationSize_, 0)),
      usage_(other.usage_),
      use_(other.use_),
      flags_(other.flags_),
      mapped_(std::exchange(other.mapped_, nullptr)) {}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    buffer_ = std::move(other.buffer_);  // destroys our buffer before our memory
    memory_ = std::move(other.memory_);  // vkFreeMemory unmaps implicitly
    ctx_ = other.ctx_;
    size_ = std::exchange(other.size_, 0);
    allocationSize_ = std::exchange(other.allocationSize_, 0);
    usage_ = other.usage_;
    use_ = other.use_;
    flags_ = other.flags_;
    mapped_ = std::exchange(other.mapped_, nullptr);
  }
  return *this;
}

Buffer::~Buffer() = default;  // members: buffer destroyed, then memory freed (which unmaps)

void Buffer::checkRange(VkDeviceSize offset, VkDeviceSize bytes, const char* what) const {
  if (!buffer_) throw std::logic_error(std::string(what) + " on an empty Buffer");
  if (offset > size_ || bytes > size_ - offset) {
    throw std::out_of_range(std::string(what) + ": [" + std::to_string(offset) + ", " +
                            std::to_string(offset + bytes) + ") is outside the " + std::to_string(size_) +
                            "-byte buffer");
  }
}

void Buffer::upload(std::span<const std::byte> data, VkDeviceSize offset) {
  uploadWith(data.size(), [&](std::byte* to) { std::memcpy(to, data.data(), data.size()); }, offset);
}

void Buffer::uploadWith(VkDeviceSize size, const std::function<void(std::byte*)>& fill, VkDeviceSize offset) {
  checkRange(offset, size, "Buffer::upload");
  if (size == 0) return;
  if (mapped_) {
    fill(mapped_ + offset);
    if (!(flags_ & kHostCoherent)) {
      VkMappedMemoryRange range = atomRange(*ctx_, memory_.get(), allocationSize_, offset, size);
      check(vkFlushMappedMemoryRanges(ctx_->device(), 1, &range), "vkFlushMappedMemoryRanges");
    }
    return;
  }
  Buffer staging = create(*ctx_, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload, "staging upload");
  staging.uploadWith(size, fill, 0);
  runOneShot(*ctx_, [&](VkCommandBuffer cmd) {
    recordCopy(cmd, staging, *this, size, 0, offset);
    transferBarrier(cmd);
  });
}

void Buffer::download(std::span<std::byte> out, VkDeviceSize offset) const {
  checkRange(offset, out.size(), "Buffer::download");
  if (out.empty()) return;
  if (mapped_) {
    if (!(flags_ & kHostCoherent)) {
      VkMappedMemoryRange range = atomRange(*ctx_, memory_.get(), allocationSize_, offset, out.size());
      check(vkInvalidateMappedMemoryRanges(ctx_->device(), 1, &range), "vkInvalidateMappedMemoryRanges");
    }
    std::memcpy(out.data(), mapped_ + offset, out.size());
    return;
  }
  Buffer staging = create(*ctx_, out.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback, "staging download");
  runOneShot(*ctx_, [&](VkCommandBuffer cmd) {
    // Earlier submissions may have written this buffer without a barrier towards transfer reads.
    computeBarrier(cmd);
    recordCopy(cmd, *this, staging, out.size(), offset, 0);
  });
  staging.download(out, 0);
}

void Buffer::recordCopy(VkCommandBuffer cmd, const Buffer& src, const Buffer& dst, VkDeviceSize bytes,
                        VkDeviceSize srcOffset, VkDeviceSize dstOffset) {
  src.checkRange(srcOffset, bytes, "Buffer::recordCopy (source)");
  dst.checkRange(dstOffset, bytes, "Buffer::recordCopy (destination)");
  VkBufferCopy region{srcOffset, dstOffset, bytes};
  vkCmdCopyBuffer(cmd, src.handle(), dst.handle(), 1, &region);
}

}  // namespace shapespline::vk
