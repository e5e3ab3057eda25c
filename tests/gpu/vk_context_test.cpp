// Tests of the thin Vulkan layer (host/vk): context, buffers, pipelines + descriptor sets, one-shot
// submission, chunked dispatch, the on-disk pipeline cache, adopt(), and that validation is live.
#include "support/vk_fixture.h"
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/context.h>
#include <shapespline/vk/error.h>
#include <shapespline/vk/pipeline.h>
#include <shapespline/vk/pipeline_cache.h>
#include <shapespline/vk/pipeline_table.h>
#include <shapespline/vk/submit.h>
#include <shapespline/vk/timestamps.h>

#include <cstdint>
// Generated at build time from shaders/*.comp (cmake/EmbedShaders.cmake).
#include "shaders/vk_selftest_comp.h"
#include "shaders/vk_selftest_fp64_comp.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

// Host mirrors of the push-constant blocks of shaders/vk_selftest*.comp.
struct SelftestPush {
  uint32_t count;
  uint32_t baseGroup;
  float addend;
  uint32_t pad;
};
static_assert(sizeof(SelftestPush) == 16 && offsetof(SelftestPush, baseGroup) == 4 &&
              offsetof(SelftestPush, addend) == 8);
struct SelftestPush64 {
  uint32_t count;
  uint32_t baseGroup;
  double addend;
};
static_assert(sizeof(SelftestPush64) == 16 && offsetof(SelftestPush64, baseGroup) == 4 &&
              offsetof(SelftestPush64, addend) == 8);

constexpr uint32_t kSpecLocalSize = 0;  // local_size_x_id in vk_selftest*.comp

// Sets an environment variable for one scope and restores the previous value.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) {
      ::setenv(name_, old_->c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// A fresh, empty folder under the system temp dir, removed at the end of the scope.
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    path_ = fs::temp_directory_path() /
            ("shapespline-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(std::random_device{}()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

vk::ComputePipeline selftestPipeline(vk::Context& ctx, uint32_t localSize) {
  vk::ComputePipelineDesc desc;
  desc.spirv = vk_selftest_comp;
  desc.specConstants = {{kSpecLocalSize, localSize}};
  desc.pushConstantBytes = sizeof(SelftestPush);
  desc.storageBufferCount = 2;
  desc.label = "vk_selftest";
  return vk::ComputePipeline::create(ctx, desc);
}

std::vector<float> ramp(size_t n) {
  std::vector<float> x(n);
  for (size_t i = 0; i < n; ++i) x[i] = float(i % 9973) * 0.25f - 100.0f;
  return x;
}

// y = x * 2 + addend over `count` floats, with `localSize` invocations per group, chunked at
// `maxGroups` per dispatch (0: device limit). Returns the number of dispatches recorded.
uint32_t runSelftest(vk::Context& ctx, const vk::ComputePipeline& pipeline, const vk::DescriptorSet& set,
                     uint32_t count, uint32_t localSize, float addend, uint32_t maxGroups = 0) {
  uint32_t dispatches = 0;
  vk::runOneShot(ctx, [&](VkCommandBuffer cmd) {
    pipeline.bind(cmd, set.handle());
    pipeline.push(cmd, SelftestPush{count, 0, addend, 0});
    const uint64_t groups = (uint64_t(count) + localSize - 1) / localSize;
    dispatches = vk::dispatchChunked(cmd, ctx, pipeline, {groups, offsetof(SelftestPush, baseGroup), maxGroups});
    vk::computeBarrier(cmd);
  });
  return dispatches;
}

void expectSelftestOutput(const std::vector<float>& x, const std::vector<float>& y, float addend) {
  ASSERT_EQ(x.size(), y.size());
  size_t bad = 0;
  for (size_t i = 0; i < x.size() && bad < 10; ++i) {
    // x*2 is exact, so GPU (fused or not) and CPU round the same single addition.
    const float expected = x[i] * 2.0f + addend;
    if (y[i] != expected) {
      ADD_FAILURE() << "element " << i << ": x=" << x[i] << " expected " << expected << " got " << y[i];
      ++bad;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Errors (no device needed)

TEST(VulkanErrorTest, CarriesResultAndWhat) {
  try {
    vk::check(VK_ERROR_OUT_OF_DEVICE_MEMORY, "vkAllocateMemory (test)");
    FAIL() << "check did not throw";
  } catch (const vk::VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY);
    EXPECT_EQ(e.attempted(), "vkAllocateMemory (test)");
    EXPECT_NE(std::string(e.what()).find("VK_ERROR_OUT_OF_DEVICE_MEMORY"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(vk::check(VK_SUCCESS, "nothing"));
}

TEST(VulkanErrorTest, DeviceLostIsExplained) {
  vk::VulkanError e(VK_ERROR_DEVICE_LOST, "vkWaitForFences");
  EXPECT_NE(std::string(e.what()).find("VK_ERROR_DEVICE_LOST"), std::string::npos);
  EXPECT_NE(std::string(e.what()).find("GPU was lost"), std::string::npos) << e.what();
}

TEST(VulkanErrorTest, NoDeviceErrorIsAVulkanError) {
  vk::NoDeviceError e(VK_ERROR_INITIALIZATION_FAILED, "no device name contains \"x\"");
  const vk::VulkanError& base = e;
  EXPECT_EQ(base.result(), VK_ERROR_INITIALIZATION_FAILED);
  EXPECT_EQ(e.reason(), "no device name contains \"x\"");
}

TEST(PipelineCacheFileTest, DirectoryFollowsEnvironment) {
  {
    ScopedEnv dir("SHAPESPLINE_CACHE_DIR", "/tmp/explicit");
    EXPECT_EQ(vk::PipelineCache::defaultDirectory(), fs::path("/tmp/explicit"));
  }
  ScopedEnv noDir("SHAPESPLINE_CACHE_DIR", "");
  {
    ScopedEnv xdg("XDG_CACHE_HOME", "/tmp/xdg");
    EXPECT_EQ(vk::PipelineCache::defaultDirectory(), fs::path("/tmp/xdg/shapespline"));
  }
  ScopedEnv noXdg("XDG_CACHE_HOME", "");
  ScopedEnv home("HOME", "/tmp/home");
  EXPECT_EQ(vk::PipelineCache::defaultDirectory(), fs::path("/tmp/home/.cache/shapespline"));
}

TEST(PipelineCacheFileTest, NameAndHeaderCheck) {
  VkPhysicalDeviceProperties props{};
  props.vendorID = 0x10005;
  props.deviceID = 0xabc;
  for (uint8_t i = 0; i < VK_UUID_SIZE; ++i) props.pipelineCacheUUID[i] = uint8_t(0xf0 + i % 16);
  EXPECT_EQ(vk::PipelineCache::fileName(props),
            "pipeline_cache_00010005_00000abc_f0f1f2f3f4f5f6f7f8f9fafbfcfdfeff.bin");

  std::vector<std::byte> header(48);
  auto put = [&](size_t at, uint32_t v) { std::memcpy(&header[at], &v, 4); };
  put(0, 32);
  put(4, VK_PIPELINE_CACHE_HEADER_VERSION_ONE);
  put(8, props.vendorID);
  put(12, props.deviceID);
  std::memcpy(&header[16], props.pipelineCacheUUID, VK_UUID_SIZE);
  EXPECT_TRUE(vk::PipelineCache::headerMatches(header, props));

  auto mismatched = header;
  mismatched[20] ^= std::byte{1};  // another driver build
  EXPECT_FALSE(vk::PipelineCache::headerMatches(mismatched, props));
  auto otherDevice = header;
  otherDevice[12] ^= std::byte{1};
  EXPECT_FALSE(vk::PipelineCache::headerMatches(otherDevice, props));
  EXPECT_FALSE(vk::PipelineCache::headerMatches(std::span(header).first(31), props));
  auto badSize = header;
  std::memset(&badSize[0], 0xff, 4);  // headerSize beyond the data
  EXPECT_FALSE(vk::PipelineCache::headerMatches(badSize, props));
}

// ---------------------------------------------------------------------------------------------
// Context

using VkContextTest = VulkanTest;

TEST_F(VkContextTest, DeviceInfoAndLimits) {
  EXPECT_TRUE(ctx().validationEnabled());
  EXPECT_TRUE(ctx().ownsHandles());
  EXPECT_FALSE(ctx().deviceName().empty());
  EXPECT_NE(ctx().device(), VK_NULL_HANDLE);
  EXPECT_NE(ctx().queue(), VK_NULL_HANDLE);
  EXPECT_GE(ctx().deviceInfo().apiVersion, uint32_t(VK_API_VERSION_1_1));
  const vk::Limits& l = ctx().limits();
  EXPECT_GT(l.maxStorageBufferRange, 0u);
  EXPECT_GE(l.maxComputeWorkGroupCount[0], 65535u);  // the Vulkan minimum
  EXPECT_GE(l.maxComputeWorkGroupInvocations, 128u);
  EXPECT_GE(l.maxPushConstantsSize, 128u);
  EXPECT_GT(l.maxMemoryAllocationSize, 0u);
  EXPECT_GT(ctx().memoryProperties().memoryTypeCount, 0u);
  EXPECT_EQ(ctx().supportsFloat64(), ctx().deviceInfo().float64);

  const std::vector<vk::DeviceInfo> devices = vk::Context::listDevices();
  ASSERT_FALSE(devices.empty());
  bool listed = false;
  for (const vk::DeviceInfo& d : devices) listed = listed || d.name == ctx().deviceName();
  EXPECT_TRUE(listed) << ctx().deviceName() << " missing from listDevices()";
  std::printf("device: %s (%s, Vulkan %s, fp64 %s, unified memory %s)\n", ctx().deviceName().c_str(),
              vk::deviceTypeName(ctx().deviceInfo().type), vk::apiVersionString(ctx().deviceInfo().apiVersion).c_str(),
              ctx().supportsFloat64() ? "yes" : "no", ctx().unifiedMemory() ? "yes" : "no");
}

TEST_F(VkContextTest, UnknownDeviceIsNoDeviceError) {
  vk::ContextOptions byName;
  byName.deviceName = "no-such-device-0123456789";
  byName.persistentPipelineCache = false;
  EXPECT_THROW(vk::Context::create(byName), vk::NoDeviceError);
  vk::ContextOptions byIndex;
  byIndex.deviceIndex = 4096;
  byIndex.persistentPipelineCache = false;
  EXPECT_THROW(vk::Context::create(byIndex), vk::NoDeviceError);
}

TEST_F(VkContextTest, DeviceChosenByEnvironment) {
  ScopedEnv device("SHAPESPLINE_DEVICE", ctx().deviceName().substr(0, 4));
  vk::ContextOptions options;
  options.validation = true;
  options.persistentPipelineCache = false;
  auto other = vk::Context::create(options);
  EXPECT_EQ(other->deviceName().substr(0, 4), ctx().deviceName().substr(0, 4));
  EXPECT_TRUE(other->validationMessages().empty()) << formatValidationMessages(other->validationMessages());
}

// The messenger must really be connected: provoke one invalid call and expect it to be reported.
TEST_F(VkContextTest, ValidationCatchesInvalidUsage) {
  ASSERT_TRUE(ctx().validationEnabled());
  VkFenceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  // 0x2 is no VkFenceCreateFlagBits value (VUID-VkFenceCreateInfo-flags-parameter); drivers ignore
  // unknown flag bits, so the call is harmless.
  info.flags = 0x2;
  VkFence fence = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateFence(ctx().device(), &info, nullptr, &fence), VK_SUCCESS);
  vkDestroyFence(ctx().device(), fence, nullptr);
  const auto messages = ctx().validationMessages();
  ASSERT_GE(messages.size(), 1u) << "the validation layer reported nothing: checking is off";
  EXPECT_NE(formatValidationMessages(messages).find("VUID-VkFenceCreateInfo-flags"), std::string::npos)
      << formatValidationMessages(messages);
  ctx().clearValidationMessages();  // expected: keep TearDown from failing the test
}

// ---------------------------------------------------------------------------------------------
// Buffers

class VkBufferTest : public VulkanTest, public ::testing::WithParamInterface<vk::MemoryUse> {};

TEST_P(VkBufferTest, UploadDownloadRoundTrip) {
  constexpr size_t kCount = 10007;
  std::vector<uint32_t> data(kCount);
  std::iota(data.begin(), data.end(), 0x1000u);
  vk::Buffer buffer = vk::Buffer::create(ctx(), kCount * 4, vk::kStorageUsage, GetParam(), "round trip");
  EXPECT_EQ(buffer.size(), kCount * 4);
  if (ctx().unifiedMemory()) {
    EXPECT_NE(buffer.mapped(), nullptr) << "unified memory buffers are mapped";
  }
  buffer.uploadSpan(std::span<const uint32_t>(data));

  std::vector<uint32_t> back(kCount, 0);
  buffer.downloadSpan(std::span(back));
  EXPECT_EQ(back, data);

  // Partial ranges at an odd offset.
  const std::vector<uint32_t> patch = {7, 8, 9};
  buffer.uploadSpan(std::span<const uint32_t>(patch), 4 * 101);
  std::vector<uint32_t> window(5);
  buffer.downloadSpan(std::span(window), 4 * 100);
  EXPECT_EQ(window, (std::vector<uint32_t>{data[100], 7, 8, 9, data[104]}));

  EXPECT_THROW(buffer.uploadSpan(std::span<const uint32_t>(patch), kCount * 4 - 8), std::out_of_range);
}

INSTANTIATE_TEST_SUITE_P(AllUses, VkBufferTest,
                         ::testing::Values(vk::MemoryUse::Upload, vk::MemoryUse::Readback, vk::MemoryUse::DeviceLocal),
                         [](const auto& info) {
                           switch (info.param) {
                             case vk::MemoryUse::Upload: return std::string("Upload");
                             case vk::MemoryUse::Readback: return std::string("Readback");
                             default: return std::string("DeviceLocal");
                           }
                         });

TEST_F(VkContextTest, BufferMoveNullsSource) {
  vk::Buffer a = vk::Buffer::create(ctx(), 256);
  const VkBuffer handle = a.handle();
  vk::Buffer b = std::move(a);
  EXPECT_EQ(b.handle(), handle);
  EXPECT_EQ(a.handle(), VK_NULL_HANDLE);  // NOLINT(bugprone-use-after-move): the point of the test
  EXPECT_EQ(a.mapped(), nullptr);
  EXPECT_EQ(a.size(), 0u);
  b = vk::Buffer::create(ctx(), 128);  // releases the first buffer
  EXPECT_EQ(b.size(), 128u);
}

TEST_F(VkContextTest, AllocationFailureIsOutOfDeviceMemory) {
  const VkDeviceSize huge = VkDeviceSize(1) << 52;  // 4 PiB
  try {
    vk::Buffer::create(ctx(), huge, vk::kStorageUsage, vk::MemoryUse::DeviceLocal, "huge");
    FAIL() << "a 4 PiB buffer was allocated";
  } catch (const vk::VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY) << e.what();
    EXPECT_NE(std::string(e.what()).find(std::to_string(huge)), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// Pipelines, submission, chunking

TEST_F(VkContextTest, SelftestShaderFloat32) {
  for (uint32_t localSize : {1u, 64u, 256u}) {
    SCOPED_TRACE("local size " + std::to_string(localSize));
    const uint32_t count = 1000 + localSize / 2;  // never a multiple: the tail is bounds-checked
    const std::vector<float> x = ramp(count);
    vk::Buffer in = vk::Buffer::create(ctx(), count * 4, vk::kStorageUsage, vk::MemoryUse::Upload, "x");
    vk::Buffer out = vk::Buffer::create(ctx(), count * 4, vk::kStorageUsage, vk::MemoryUse::Readback, "y");
    in.uploadSpan(std::span<const float>(x));
    vk::ComputePipeline pipeline = selftestPipeline(ctx(), localSize);
    vk::DescriptorSet set = vk::DescriptorSet::create(ctx(), pipeline);
    set.bind({{0, &in}, {1, &out}});
    EXPECT_EQ(runSelftest(ctx(), pipeline, set, count, localSize, 0.5f), 1u);
    std::vector<float> y(count);
    out.downloadSpan(std::span(y));
    expectSelftestOutput(x, y, 0.5f);
  }
}

// PassTimer: one interval per mark, in order, in milliseconds of the device clock: each finite and
// non-negative, a pass of 16 dispatches over 4 M floats longer than zero, and the sum no longer
// than the host's wall time around the whole submission (a wrong timestampPeriod scale fails).
TEST_F(VkContextTest, PassTimerTimesEachPass) {
  vk::PassTimer timer(ctx(), 3);
  ASSERT_TRUE(timer.available()) << "lavapipe has timestamps on its queue";
  const uint32_t count = 1u << 22, localSize = 64;
  const std::vector<float> x = ramp(count);
  vk::Buffer in = vk::Buffer::create(ctx(), count * 4, vk::kStorageUsage, vk::MemoryUse::Upload, "x");
  vk::Buffer out = vk::Buffer::create(ctx(), count * 4, vk::kStorageUsage, vk::MemoryUse::Readback, "y");
  in.uploadSpan(std::span<const float>(x));
  vk::ComputePipeline pipeline = selftestPipeline(ctx(), localSize);
  vk::DescriptorSet set = vk::DescriptorSet::create(ctx(), pipeline);
  set.bind({{0, &in}, {1, &out}});
  const auto t0 = std::chrono::steady_clock::now();
  vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) {
    timer.reset(cmd);
    timer.mark(cmd, "nothing");
    pipeline.bind(cmd, set.handle());
    for (int rep = 0; rep < 16; ++rep) {
      pipeline.push(cmd, SelftestPush{count, 0, 0.5f, 0});
      vk::dispatchChunked(cmd, ctx(), pipeline, {count / localSize, offsetof(SelftestPush, baseGroup), 0});
      vk::computeBarrier(cmd);
    }
    timer.mark(cmd, "selftest x16");
    timer.mark(cmd, "after");
    EXPECT_THROW(timer.mark(cmd, "one too many"), std::length_error);
  });
  const double wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const auto passes = timer.passes();
  ASSERT_EQ(passes.size(), 3u);
  EXPECT_EQ(passes[0].first, "nothing");
  EXPECT_EQ(passes[1].first, "selftest x16");
  EXPECT_EQ(passes[2].first, "after");
  double sum = 0;
  for (const auto& [name, ms] : passes) {
    EXPECT_TRUE(std::isfinite(ms) && ms >= 0.0) << name << ": " << ms;
    sum += ms;
  }
  EXPECT_GT(passes[1].second, 0.0);
  // The 16 dispatches are charged to their own mark: far more than the empty intervals around them.
  EXPECT_GT(passes[1].second, 4.0 * passes[0].second) << "the pass was charged to the mark before it";
  EXPECT_GT(passes[1].second, 4.0 * passes[2].second);
  EXPECT_LE(sum, wallMs) << "GPU intervals longer than the submission itself";
  std::vector<float> y(count);
  out.downloadSpan(std::span(y));
  expectSelftestOutput(x, y, 0.5f);
}

TEST_F(VkContextTest, SelftestShaderFloat64) {
  if (!ctx().supportsFloat64()) GTEST_SKIP() << ctx().deviceName() << " has no shaderFloat64";
  constexpr uint32_t kCount = 4099;
  constexpr uint32_t kLocal = 64;
  std::vector<double> x(kCount);
  for (uint32_t i = 0; i < kCount; ++i) x[i] = 1.0 / 3.0 + i * 1e-9;  // needs more than float precision
  vk::Buffer in = vk::Buffer::create(ctx(), kCount * 8, vk::kStorageUsage, vk::MemoryUse::Upload, "x64");
  vk::Buffer out = vk::Buffer::create(ctx(), kCount * 8, vk::kStorageUsage, vk::MemoryUse::Readback, "y64");
  in.uploadSpan(std::span<const double>(x));

  vk::ComputePipelineDesc desc;
  desc.spirv = vk_selftest_fp64_comp;
  desc.specConstants = {{kSpecLocalSize, kLocal}};
  desc.pushConstantBytes = sizeof(SelftestPush64);
  desc.storageBufferCount = 2;
  desc.label = "vk_selftest_fp64";
  vk::ComputePipeline pipeline = vk::ComputePipeline::create(ctx(), desc);
  vk::DescriptorSet set = vk::DescriptorSet::create(ctx(), pipeline);
  set.bind({{0, &in}, {1, &out}});
  const double addend = 1e-12;
  vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) {
    pipeline.bind(cmd, set.handle());
    pipeline.push(cmd, SelftestPush64{kCount, 0, addend});
    vk::dispatchChunked(cmd, ctx(), pipeline, {(kCount + kLocal - 1) / kLocal, offsetof(SelftestPush64, baseGroup)});
  });
  std::vector<double> y(kCount);
  out.downloadSpan(std::span(y));
  for (uint32_t i = 0; i < kCount; ++i) {
    ASSERT_EQ(y[i], x[i] * 2.0 + addend) << "element " << i << " x=" << x[i];
  }
}

TEST_F(VkContextTest, ChunkedDispatchBeyondGroupLimit) {
  constexpr uint32_t kLocal = 4;
  const uint32_t maxGroups = ctx().limits().maxComputeWorkGroupCount[0];
  // More groups than one dispatch may have, and a partial last group.
  const uint64_t groups = uint64_t(maxGroups) + 9466;
  const uint64_t count64 = groups * kLocal - 3;
  ASSERT_LT(count64 * 4, ctx().limits().maxStorageBufferRange) << "test sized for a smaller limit";
  const uint32_t count = uint32_t(count64);
  const std::vector<float> x = ramp(count);
  vk::Buffer in = vk::Buffer::create(ctx(), count * 4ull, vk::kStorageUsage, vk::MemoryUse::Upload, "x");
  vk::Buffer out = vk::Buffer::create(ctx(), count * 4ull, vk::kStorageUsage, vk::MemoryUse::Readback, "y");
  in.uploadSpan(std::span<const float>(x));
  vk::ComputePipeline pipeline = selftestPipeline(ctx(), kLocal);
  vk::DescriptorSet set = vk::DescriptorSet::create(ctx(), pipeline);
  set.bind({{0, &in}, {1, &out}});

  EXPECT_EQ(runSelftest(ctx(), pipeline, set, count, kLocal, -1.0f), 2u);
  std::vector<float> y(count);
  out.downloadSpan(std::span(y));
  expectSelftestOutput(x, y, -1.0f);

  // Many small chunks through the same push-constant field.
  EXPECT_EQ(runSelftest(ctx(), pipeline, set, count, kLocal, 3.0f, 7000), uint32_t((groups + 6999) / 7000));
  out.downloadSpan(std::span(y));
  expectSelftestOutput(x, y, 3.0f);
}

TEST_F(VkContextTest, SubRangeBinding) {
  const VkDeviceSize align = ctx().limits().minStorageBufferOffsetAlignment;
  constexpr uint32_t kCount = 300;
  const VkDeviceSize offset = ((4 * 1000 + align - 1) / align) * align;  // past the first 1000 floats
  const size_t total = size_t(offset / 4) + kCount + 50;
  std::vector<float> x = ramp(total);
  vk::Buffer in = vk::Buffer::create(ctx(), total * 4, vk::kStorageUsage, vk::MemoryUse::Upload, "x");
  vk::Buffer out = vk::Buffer::create(ctx(), total * 4, vk::kStorageUsage, vk::MemoryUse::Readback, "y");
  in.uploadSpan(std::span<const float>(x));
  const std::vector<float> sentinel(total, -7.0f);
  out.uploadSpan(std::span<const float>(sentinel));

  vk::ComputePipeline pipeline = selftestPipeline(ctx(), 32);
  vk::DescriptorSet set = vk::DescriptorSet::create(ctx(), pipeline);
  set.bind({{0, &in, offset, kCount * 4}, {1, &out, offset, kCount * 4}});
  runSelftest(ctx(), pipeline, set, kCount, 32, 1.0f);

  std::vector<float> y(total);
  out.downloadSpan(std::span(y));
  const size_t first = size_t(offset / 4);
  for (size_t i = 0; i < total; ++i) {
    const bool inside = i >= first && i < first + kCount;
    const float expected = inside ? x[i] * 2.0f + 1.0f : -7.0f;
    ASSERT_EQ(y[i], expected) << "element " << i << (inside ? " (bound range)" : " (outside the bound range)");
  }

  if (align > 1) {
    EXPECT_THROW(set.bind(0, in, 1), std::invalid_argument);
  }
  EXPECT_THROW(set.bind(2, in), std::invalid_argument);
  EXPECT_THROW(set.bind(0, in, 0, total * 4 + 4), std::invalid_argument);
}

TEST_F(VkContextTest, PushConstantBoundsChecked) {
  vk::ComputePipeline pipeline = selftestPipeline(ctx(), 8);
  vk::OneShot shot(ctx());
  const uint32_t words[5] = {};
  EXPECT_THROW(pipeline.push(shot.cmd(), words, sizeof words), std::invalid_argument);
  vk::ChunkedDispatch bad{1, 14, 0};  // not a 4-aligned field inside the block
  EXPECT_THROW(vk::dispatchChunked(shot.cmd(), ctx(), pipeline, bad), std::invalid_argument);
  shot.submitAndWait();
}

// The context's pipeline table: one pipeline per distinct desc, whoever asks and from whatever
// buffer the SPIR-V comes; any field that differs (a specialization constant, the label) is another
// pipeline; a bad desc throws and stores nothing; what it returns runs.
TEST_F(VkContextTest, PipelineTableCompilesEachDescOnce) {
  vk::PipelineTable& table = ctx().pipelines();
  vk::ComputePipelineDesc desc;
  desc.spirv = vk_selftest_comp;
  desc.specConstants = {{kSpecLocalSize, 32}};
  desc.pushConstantBytes = sizeof(SelftestPush);
  desc.storageBufferCount = 2;
  desc.label = "vk_selftest_table";
  const size_t before = table.size();
  const vk::ComputePipeline& first = table.get(desc);
  EXPECT_EQ(table.size(), before + 1);
  {
    // The same words from another buffer, freed afterwards: the same pipeline.
    const std::vector<uint32_t> copy(std::begin(vk_selftest_comp), std::end(vk_selftest_comp));
    vk::ComputePipelineDesc same = desc;
    same.spirv = copy;
    EXPECT_EQ(&table.get(same), &first);
  }
  EXPECT_EQ(&table.get(desc), &first);
  EXPECT_EQ(table.size(), before + 1);
  vk::ComputePipelineDesc otherSpec = desc;
  otherSpec.specConstants = {{kSpecLocalSize, 16}};
  EXPECT_NE(&table.get(otherSpec), &first);
  vk::ComputePipelineDesc otherLabel = desc;
  otherLabel.label = "vk_selftest_table_2";
  EXPECT_NE(&table.get(otherLabel), &first);
  EXPECT_EQ(table.size(), before + 3);
  vk::ComputePipelineDesc bad = desc;
  bad.pushConstantBytes = 3;
  EXPECT_THROW(table.get(bad), std::invalid_argument);
  EXPECT_EQ(table.size(), before + 3);

  const uint32_t count = 1000;
  const std::vector<float> x = ramp(count);
  vk::Buffer in = vk::Buffer::create(ctx(), count * 4, vk::kStorageUsage, vk::MemoryUse::Upload, "x");
  vk::Buffer out = vk::Buffer::create(ctx(), count * 4, vk::kStorageUsage, vk::MemoryUse::Readback, "y");
  in.uploadSpan(std::span<const float>(x));
  vk::DescriptorSet set = vk::DescriptorSet::create(ctx(), first);
  set.bind({{0, &in}, {1, &out}});
  runSelftest(ctx(), first, set, count, 32, 0.5f);
  std::vector<float> y(count);
  out.downloadSpan(std::span(y));
  expectSelftestOutput(x, y, 0.5f);
}

// Threads that ask at once for the same new descs get one pipeline per desc, compiled once; a bad
// desc asked for by several threads throws in each and stores nothing.
TEST_F(VkContextTest, PipelineTableGivesConcurrentAskersOnePipelinePerDesc) {
  vk::PipelineTable& table = ctx().pipelines();
  constexpr int kDescs = 3, kThreads = 6;
  std::vector<vk::ComputePipelineDesc> descs(kDescs);
  for (int k = 0; k < kDescs; ++k) {
    descs[k].spirv = vk_selftest_comp;
    descs[k].specConstants = {{kSpecLocalSize, 32}};
    descs[k].pushConstantBytes = sizeof(SelftestPush);
    descs[k].storageBufferCount = 2;
    descs[k].label = "vk_selftest_concurrent_" + std::to_string(k);
  }
  vk::ComputePipelineDesc bad = descs[0];
  bad.label = "vk_selftest_concurrent_bad";
  bad.pushConstantBytes = 3;
  const size_t before = table.size();
  std::vector<std::vector<const vk::ComputePipeline*>> got(kThreads, std::vector<const vk::ComputePipeline*>(kDescs));
  std::atomic<int> refused{0}, waiting{kThreads};
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (--waiting; waiting > 0;) std::this_thread::yield();  // all ask at once
      for (int i = 0; i < kDescs; ++i) {
        const int k = (t + i) % kDescs;  // each thread in its own order
        got[t][k] = &table.get(descs[k]);
      }
      try {
        table.get(bad);
      } catch (const std::invalid_argument&) {
        ++refused;
      }
    });
  for (auto& t : threads) t.join();
  for (int k = 0; k < kDescs; ++k)
    for (int t = 1; t < kThreads; ++t) EXPECT_EQ(got[t][k], got[0][k]) << "desc " << k << ", thread " << t;
  EXPECT_NE(got[0][0], got[0][1]);
  EXPECT_NE(got[0][1], got[0][2]);
  EXPECT_EQ(refused.load(), kThreads);
  EXPECT_EQ(table.size(), before + kDescs);
}

// ---------------------------------------------------------------------------------------------
// Pipeline cache on disk

TEST_F(VkContextTest, PipelineCachePersistsAcrossContexts) {
  TempDir dir("pipeline-cache");
  ScopedEnv cacheDir("SHAPESPLINE_CACHE_DIR", dir.path().string());
  vk::ContextOptions options;
  options.validation = true;
  fs::path file;
  {
    auto first = vk::Context::create(options);
    file = first->pipelineCache().path();
    EXPECT_EQ(file, dir.path() / vk::PipelineCache::fileName(first->properties()));
    EXPECT_FALSE(first->pipelineCache().loadedFromDisk());
    vk::ComputePipeline pipeline = selftestPipeline(*first, 16);
    EXPECT_TRUE(first->validationMessages().empty()) << formatValidationMessages(first->validationMessages());
  }  // saved on destruction
  ASSERT_TRUE(fs::exists(file)) << file << " not written";
  EXPECT_GE(fs::file_size(file), 32u);  // at least the VkPipelineCacheHeaderVersionOne
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path(), file) << "stray file (temporary not renamed?)";
  }

  {
    auto second = vk::Context::create(options);
    EXPECT_TRUE(second->pipelineCache().loadedFromDisk()) << second->pipelineCache().lastError();
    EXPECT_EQ(second->pipelineCache().loadedBytes(), fs::file_size(file));
    vk::ComputePipeline pipeline = selftestPipeline(*second, 16);
    EXPECT_TRUE(second->pipelineCache().save()) << second->pipelineCache().lastError();
    EXPECT_TRUE(second->validationMessages().empty()) << formatValidationMessages(second->validationMessages());
  }

  // A corrupt file is ignored, never fatal, and replaced by a good one.
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << "definitely not a pipeline cache, but longer than thirty-two bytes";
  }
  {
    auto third = vk::Context::create(options);
    EXPECT_FALSE(third->pipelineCache().loadedFromDisk());
    EXPECT_FALSE(third->pipelineCache().lastError().empty());
    vk::ComputePipeline pipeline = selftestPipeline(*third, 16);
    EXPECT_TRUE(third->validationMessages().empty()) << formatValidationMessages(third->validationMessages());
  }
  std::vector<std::byte> bytes(fs::file_size(file));
  std::ifstream(file, std::ios::binary).read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  EXPECT_TRUE(vk::PipelineCache::headerMatches(bytes, ctx().properties()));
}

TEST_F(VkContextTest, UnwritableCacheDirIsNotFatal) {
  TempDir dir("pipeline-cache-ro");
  const fs::path blocker = dir.path() / "file";
  std::ofstream(blocker) << "x";  // a file where the cache folder should be
  vk::ContextOptions options;
  options.validation = true;
  options.cacheDir = (blocker / "sub").string();
  auto context = vk::Context::create(options);
  vk::ComputePipeline pipeline = selftestPipeline(*context, 16);
  EXPECT_FALSE(context->pipelineCache().save());
  EXPECT_FALSE(context->pipelineCache().lastError().empty());
  EXPECT_TRUE(context->validationMessages().empty()) << formatValidationMessages(context->validationMessages());
}

// ---------------------------------------------------------------------------------------------
// adopt(): caller-owned handles survive the Context

std::atomic<int> gExternalMessages{0};

VKAPI_ATTR VkBool32 VKAPI_CALL countMessage(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                            const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  std::fprintf(stderr, "external instance: %s\n", data->pMessage);
  ++gExternalMessages;
  return VK_FALSE;
}

TEST_F(VkContextTest, AdoptDoesNotDestroyCallerHandles) {
  gExternalMessages = 0;
  // Caller-side instance with validation, so that a use of a destroyed handle would be reported.
  VkDebugUtilsMessengerCreateInfoEXT messenger{};
  messenger.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
  messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
  messenger.pfnUserCallback = countMessage;
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.apiVersion = VK_API_VERSION_1_1;
  const char* layer = "VK_LAYER_KHRONOS_validation";
  const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
  VkInstanceCreateInfo instanceInfo{};
  instanceInfo.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  instanceInfo.pNext = &messenger;  // covers every call on this instance and its devices
  instanceInfo.pApplicationInfo = &app;
  instanceInfo.enabledLayerCount = 1;
  instanceInfo.ppEnabledLayerNames = &layer;
  instanceInfo.enabledExtensionCount = 1;
  instanceInfo.ppEnabledExtensionNames = &extension;
  VkInstance instance = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateInstance(&instanceInfo, nullptr, &instance), VK_SUCCESS);

  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> physicals(count);
  vkEnumeratePhysicalDevices(instance, &count, physicals.data());
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  uint32_t family = 0;
  for (VkPhysicalDevice p : physicals) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(p, &props);
    if (ctx().deviceName() != props.deviceName) continue;
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(p, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vkGetPhysicalDeviceQueueFamilyProperties(p, &n, families.data());
    for (uint32_t i = 0; i < n && physical == VK_NULL_HANDLE; ++i) {
      if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
        physical = p;
        family = i;
      }
    }
  }
  ASSERT_NE(physical, VK_NULL_HANDLE);
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{};
  queueInfo.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queueInfo.queueFamilyIndex = family;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;
  VkDeviceCreateInfo deviceInfo{};
  deviceInfo.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  deviceInfo.queueCreateInfoCount = 1;
  deviceInfo.pQueueCreateInfos = &queueInfo;
  VkDevice device = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateDevice(physical, &deviceInfo, nullptr, &device), VK_SUCCESS);
  VkQueue queue = VK_NULL_HANDLE;
  vkGetDeviceQueue(device, family, 0, &queue);

  {
    vk::ContextOptions options;
    options.persistentPipelineCache = false;
    auto adopted = vk::Context::adopt(instance, physical, device, family, queue, nullptr, options);
    EXPECT_FALSE(adopted->ownsHandles());
    EXPECT_FALSE(adopted->supportsFloat64()) << "fp64 was not enabled on the caller's device";
    // Real work through the adopted device.
    const uint32_t n = 500;
    const std::vector<float> x = ramp(n);
    vk::Buffer in = vk::Buffer::create(*adopted, n * 4, vk::kStorageUsage, vk::MemoryUse::Upload);
    vk::Buffer out = vk::Buffer::create(*adopted, n * 4, vk::kStorageUsage, vk::MemoryUse::Readback);
    in.uploadSpan(std::span<const float>(x));
    vk::ComputePipeline pipeline = selftestPipeline(*adopted, 32);
    vk::DescriptorSet set = vk::DescriptorSet::create(*adopted, pipeline);
    set.bind({{0, &in}, {1, &out}});
    runSelftest(*adopted, pipeline, set, n, 32, 2.0f);
    std::vector<float> y(n);
    out.downloadSpan(std::span(y));
    expectSelftestOutput(x, y, 2.0f);
  }  // objects and the adopted context are gone; the caller's handles must not be

  EXPECT_EQ(vkDeviceWaitIdle(device), VK_SUCCESS);
  VkFenceCreateInfo fenceInfo{};
  fenceInfo.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  VkFence fence = VK_NULL_HANDLE;
  EXPECT_EQ(vkCreateFence(device, &fenceInfo, nullptr, &fence), VK_SUCCESS);
  VkSubmitInfo submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  EXPECT_EQ(vkQueueSubmit(queue, 1, &submit, fence), VK_SUCCESS);
  EXPECT_EQ(vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX), VK_SUCCESS);
  vkDestroyFence(device, fence, nullptr);
  uint32_t again = 0;
  EXPECT_EQ(vkEnumeratePhysicalDevices(instance, &again, nullptr), VK_SUCCESS);
  vkDestroyDevice(device, nullptr);
  vkDestroyInstance(instance, nullptr);
  EXPECT_EQ(gExternalMessages.load(), 0) << "validation messages on the caller's instance (see stderr)";
}

}  // namespace
}  // namespace shapespline::test
