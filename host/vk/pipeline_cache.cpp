#include <shapespline/vk/pipeline_cache.h>

#include <shapespline/vk/error.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string_view>
#include <vector>

#include <unistd.h>

namespace shapespline::vk {

namespace {

// A cache file larger than this is not something we wrote; refuse to read it into memory.
constexpr std::uintmax_t kMaxCacheFileBytes = std::uintmax_t(512) << 20;
// sizeof(VkPipelineCacheHeaderVersionOne): 4 x uint32 + 16-byte UUID.
constexpr std::size_t kHeaderBytes = 32;

std::string hex(const uint8_t* bytes, std::size_t n) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (std::size_t i = 0; i < n; ++i) {
    s += kDigits[bytes[i] >> 4];
    s += kDigits[bytes[i] & 15];
  }
  return s;
}

std::string hex32(uint32_t v) {
  char buf[9];
  std::snprintf(buf, sizeof buf, "%08x", v);
  return buf;
}

uint32_t readU32(const std::byte* p) {
  uint32_t v;  // the header is in host byte order (Vulkan spec, "Pipeline Cache Header")
  std::memcpy(&v, p, 4);
  return v;
}

std::size_t hashBytes(std::span<const std::byte> data) {
  return std::hash<std::string_view>{}(std::string_view(reinterpret_cast<const char*>(data.data()), data.size()));
}

std::vector<std::byte> readFile(const std::filesystem::path& path, std::string& error) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return {};  // no file yet: not an error
  if (size > kMaxCacheFileBytes) {
    error = "ignoring " + path.string() + ": " + std::to_string(size) + " bytes is too large for a pipeline cache";
    return {};
  }
  std::vector<std::byte> data(size);
  std::ifstream in(path, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(data.data()), std::streamsize(size))) {
    error = "could not read " + path.string();
    return {};
  }
  return data;
}

}  // namespace

std::filesystem::path PipelineCache::defaultDirectory() {
  auto get = [](const char* name) -> const char* {
    const char* v = std::getenv(name);
    return (v && *v) ? v : nullptr;
  };
  if (const char* dir = get("SHAPESPLINE_CACHE_DIR")) return dir;
  if (const char* xdg = get("XDG_CACHE_HOME")) return std::filesystem::path(xdg) / "shapespline";
  if (const char* home = get("HOME")) return std::filesystem::path(home) / ".cache" / "shapespline";
  return {};
}

std::string PipelineCache::fileName(const VkPhysicalDeviceProperties& p) {
  return "pipeline_cache_" + hex32(p.vendorID) + "_" + hex32(p.deviceID) + "_" +
         hex(p.pipelineCacheUUID, VK_UUID_SIZE) + ".bin";
}

bool PipelineCache::headerMatches(std::span<const std::byte> data, const VkPhysicalDeviceProperties& p) {
  if (data.size() < kHeaderBytes) return false;
  const uint32_t headerSize = readU32(&data[0]);
  const uint32_t version = readU32(&data[4]);
  return headerSize >= kHeaderBytes && headerSize <= data.size() &&
         version == uint32_t(VK_PIPELINE_CACHE_HEADER_VERSION_ONE) && readU32(&data[8]) == p.vendorID &&
         readU32(&data[12]) == p.deviceID && std::memcmp(&data[16], p.pipelineCacheUUID, VK_UUID_SIZE) == 0;
}

PipelineCache::PipelineCache(VkDevice device, const VkPhysicalDeviceProperties& properties,
                             std::filesystem::path dir)
    : device_(device), properties_(properties) {
  std::vector<std::byte> data;
  if (!dir.empty()) {
    path_ = dir / fileName(properties);
    data = readFile(path_, lastError_);
    if (!data.empty() && !headerMatches(data, properties)) {
      lastError_ = "ignoring " + path_.string() + ": header does not match this device/driver";
      data.clear();
    }
  }
  VkPipelineCacheCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
  info.initialDataSize = data.size();
  info.pInitialData = data.empty() ? nullptr : data.data();
  VkPipelineCache cache = VK_NULL_HANDLE;
  VkResult result = vkCreatePipelineCache(device, &info, nullptr, &cache);
  if (result != VK_SUCCESS && !data.empty()) {
    // The header matched but the driver still refused the body (truncated or corrupt): start empty.
    lastError_ = "driver rejected " + path_.string() + " (" + (resultName(result) ? resultName(result) : "?") + ")";
    data.clear();
    info.initialDataSize = 0;
    info.pInitialData = nullptr;
    result = vkCreatePipelineCache(device, &info, nullptr, &cache);
  }
  check(result, "vkCreatePipelineCache");
  cache_ = PipelineCacheHandle(device, cache);
  loadedBytes_ = data.size();
  if (!data.empty()) savedHash_ = hashBytes(data);
}

PipelineCache::~PipelineCache() { save(); }

bool PipelineCache::save() noexcept {
  if (path_.empty() || !cache_) return true;
  try {
    std::size_t size = 0;
    VkResult result = vkGetPipelineCacheData(device_, cache_.get(), &size, nullptr);
    if (result != VK_SUCCESS) {
      lastError_ = std::string("vkGetPipelineCacheData: ") + (resultName(result) ? resultName(result) : "?");
      return false;
    }
    std::vector<std::byte> data(size);
    result = vkGetPipelineCacheData(device_, cache_.get(), &size, data.data());
    if (result != VK_SUCCESS && result != VK_INCOMPLETE) {
      lastError_ = std::string("vkGetPipelineCacheData: ") + (resultName(result) ? resultName(result) : "?");
      return false;
    }
    data.resize(size);
    // A header-only cache (lavapipe keeps no pipeline binaries) is still written: it is tiny, and
    // it proves the save/load path on every driver.
    if (data.size() < kHeaderBytes) return true;
    const std::size_t hash = hashBytes(data);
    if (hash == savedHash_) return true;

    std::error_code ec;
    std::filesystem::create_directories(path_.parent_path(), ec);
    if (ec) {
      lastError_ = "cannot create " + path_.parent_path().string() + ": " + ec.message();
      return false;
    }
    // Unique temporary name in the same folder: concurrent processes never share a temp file and
    // rename() within one file system replaces the target atomically.
    std::filesystem::path tmp = path_;
    tmp += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(std::random_device{}());
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      out.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size()));
      out.close();
      if (!out) {
        lastError_ = "cannot write " + tmp.string();
        std::filesystem::remove(tmp, ec);
        return false;
      }
    }
    std::filesystem::rename(tmp, path_, ec);
    if (ec) {
      lastError_ = "cannot rename " + tmp.string() + " to " + path_.string() + ": " + ec.message();
      std::filesystem::remove(tmp, ec);
      return false;
    }
    savedHash_ = hash;
    lastError_.clear();
    return true;
  } catch (const std::exception& e) {
    lastError_ = e.what();
    return false;
  }
}

}  // namespace shapespline::vk
