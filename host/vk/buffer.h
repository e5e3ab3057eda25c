#pragma once
// Buffer: a VkBuffer with its own VkDeviceMemory. Where the memory lives follows MemoryUse and the
// device: on unified-memory devices (integrated GPUs, lavapipe) every buffer is host-visible and
// coherent and is mapped for its whole life; on discrete GPUs DeviceLocal buffers live in VRAM and
// upload()/download() go through a temporary staging buffer and a OneShot.
#include <shapespline/vk/context.h>
#include <shapespline/vk/handle.h>

#include <vulkan/vulkan_core.h>

#include <cstddef>
#include <functional>
#include <span>
#include <type_traits>

namespace shapespline::vk {

enum class MemoryUse {
  Upload,       // host writes, GPU reads: host-visible (device-local too where possible)
  Readback,     // GPU writes, host reads: host-visible, preferably host-cached
  DeviceLocal,  // GPU working memory: device-local (host-visible as well on unified memory)
};

// Storage buffer + transfer source/destination: what every evaluator buffer needs.
inline constexpr VkBufferUsageFlags kStorageUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

class Buffer {
 public:
  Buffer() = default;
  // bytes > 0. Throws VulkanError(VK_ERROR_OUT_OF_DEVICE_MEMORY) naming the size when the memory
  // cannot be allocated (including sizes over maxMemoryAllocationSize or the heap size).
  static Buffer create(Context& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage = kStorageUsage,
                       MemoryUse use = MemoryUse::DeviceLocal, const char* label = nullptr);

  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_.get(); }
  VkDeviceMemory memory() const { return memory_.get(); }
  VkDeviceSize size() const { return size_; }
  VkBufferUsageFlags usage() const { return usage_; }
  MemoryUse use() const { return use_; }
  VkMemoryPropertyFlags memoryFlags() const { return flags_; }
  bool hostVisible() const { return mapped_ != nullptr; }

  // Persistent mapping of the whole buffer; nullptr when the memory is not host-visible.
  std::byte* mapped() const { return mapped_; }
  template <typename T>
  std::span<T> mappedAs() const {
    static_assert(std::is_trivially_copyable_v<T>);
    return {reinterpret_cast<T*>(mapped_), mapped_ ? size_t(size_ / sizeof(T)) : 0};
  }

  // Copies into/out of the buffer at `offset`: memcpy (+ flush/invalidate for non-coherent memory)
  // when mapped, otherwise through a staging buffer (needs TRANSFER_DST / TRANSFER_SRC usage).
  // Throws std::out_of_range when [offset, offset + size) is outside the buffer.
  void upload(std::span<const std::byte> data, VkDeviceSize offset = 0);
  // The same for `size` bytes that fill(destination) writes: straight into the mapped memory, or
  // into the staging buffer. A big net converted on the way needs no array of its bytes.
  void uploadWith(VkDeviceSize size, const std::function<void(std::byte*)>& fill, VkDeviceSize offset = 0);
  void download(std::span<std::byte> out, VkDeviceSize offset = 0) const;
  template <typename T>
  void uploadSpan(std::span<const T> data, VkDeviceSize offset = 0) {
    static_assert(std::is_trivially_copyable_v<T>);
    upload(std::as_bytes(data), offset);
  }
  template <typename T>
  void downloadSpan(std::span<T> out, VkDeviceSize offset = 0) const {
    static_assert(std::is_trivially_copyable_v<T>);
    download(std::as_writable_bytes(out), offset);
  }

  // Records a copy of `bytes` from src to dst (both need the transfer usage bits).
  static void recordCopy(VkCommandBuffer cmd, const Buffer& src, const Buffer& dst, VkDeviceSize bytes,
                         VkDeviceSize srcOffset = 0, VkDeviceSize dstOffset = 0);

 private:
  void checkRange(VkDeviceSize offset, VkDeviceSize bytes, const char* what) const;

  Context* ctx_ = nullptr;
  MemoryHandle memory_;  // declared first so that the buffer is destroyed before its memory is freed
  BufferHandle buffer_;
  VkDeviceSize size_ = 0;
  VkDeviceSize allocationSize_ = 0;
  VkBufferUsageFlags usage_ = 0;
  MemoryUse use_ = MemoryUse::DeviceLocal;
  VkMemoryPropertyFlags flags_ = 0;
  std::byte* mapped_ = nullptr;
};

}  // namespace shapespline::vk
