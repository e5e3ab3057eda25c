#pragma once
// PipelineCache: the one VkPipelineCache of a Context, persisted on disk so that the second run of
// a shader skips the driver's compiler. Reading or writing the file is never fatal: a missing,
// corrupt or foreign file means an empty cache, a failed save is reported by save() and lastError().
#include <shapespline/vk/handle.h>

#include <vulkan/vulkan_core.h>

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

namespace shapespline::vk {

class PipelineCache {
 public:
  // dir empty: memory only. Otherwise loads dir/fileName(properties) if its header matches the device.
  PipelineCache(VkDevice device, const VkPhysicalDeviceProperties& properties, std::filesystem::path dir);
  ~PipelineCache();  // save()s
  PipelineCache(const PipelineCache&) = delete;
  PipelineCache& operator=(const PipelineCache&) = delete;

  VkPipelineCache handle() const { return cache_.get(); }

  // Writes the cache to path() via a temporary file + rename, so a reader never sees half a file.
  // Skipped (returns true) when the data is unchanged since load/last save. Never throws.
  bool save() noexcept;

  bool persistent() const { return !path_.empty(); }
  const std::filesystem::path& path() const { return path_; }  // empty when memory-only
  bool loadedFromDisk() const { return loadedBytes_ > 0; }
  std::size_t loadedBytes() const { return loadedBytes_; }
  // Why the last load or save did not use the file ("" when it did or there was none).
  const std::string& lastError() const { return lastError_; }

  // $SHAPESPLINE_CACHE_DIR, else $XDG_CACHE_HOME/shapespline, else $HOME/.cache/shapespline; empty
  // when none of those variables is set.
  static std::filesystem::path defaultDirectory();
  // "pipeline_cache_<vendorID>_<deviceID>_<pipelineCacheUUID>.bin", all lower-case hex.
  static std::string fileName(const VkPhysicalDeviceProperties& properties);
  // True when `data` starts with a VkPipelineCacheHeaderVersionOne for this exact device/driver.
  static bool headerMatches(std::span<const std::byte> data, const VkPhysicalDeviceProperties& properties);

 private:
  VkDevice device_;
  VkPhysicalDeviceProperties properties_;
  std::filesystem::path path_;
  PipelineCacheHandle cache_;
  std::size_t loadedBytes_ = 0;
  std::size_t savedHash_ = 0;  // hash of the bytes on disk, to skip rewriting an unchanged cache
  std::string lastError_;
};

}  // namespace shapespline::vk
