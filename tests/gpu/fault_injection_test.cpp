// Failure injection at the Vulkan layer (issue 7, vk/fault.h): out-of-device-memory, device loss
// and "no device" must surface as typed errors with a clear message, leave the process able to go
// on (or to shut down cleanly) and leak nothing (the sanitizer build of scripts/test.sh runs this
// with LeakSanitizer on).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <shapespline/core/curve.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/gpu/evaluator.h>
#include "support/vk_fixture.h"
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/error.h>
#include <shapespline/vk/fault.h>
#include <shapespline/vk/submit.h>

namespace shapespline::test {
namespace {

using vk::Fault;
using vk::FaultPlan;

// Restores "no fault" whatever the test did.
struct FaultScope {
  explicit FaultScope(FaultPlan plan) { vk::setFaultForTesting(plan); }
  ~FaultScope() { vk::setFaultForTesting({}); }
};

vk::ContextOptions memoryOnlyCache() {
  vk::ContextOptions options;
  options.persistentPipelineCache = false;
  return options;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

CurveModel smallCurve() {
  CurveModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.family.lambda = -2.0;
  m.dimension = 3;
  for (int i = 0; i < 9; ++i) m.points.push_back({i * 1.0, std::sin(i * 0.7), std::cos(i * 0.4)});
  m.alpha.assign(m.points.size(), 0.6);
  return m;
}

TEST(FaultPlanParsing, AcceptsTheDocumentedValuesOnly) {
  FaultPlan p;
  EXPECT_TRUE(vk::parseFault("", p));
  EXPECT_EQ(p.fault, Fault::None);
  EXPECT_TRUE(vk::parseFault("alloc", p));
  EXPECT_EQ(p.fault, Fault::Alloc);
  EXPECT_EQ(p.firstFailingAllocation, 1u);
  EXPECT_TRUE(vk::parseFault("alloc:7", p));
  EXPECT_EQ(p.firstFailingAllocation, 7u);
  EXPECT_TRUE(vk::parseFault("device_lost", p));
  EXPECT_EQ(p.fault, Fault::DeviceLost);
  EXPECT_TRUE(vk::parseFault("no_device", p));
  EXPECT_EQ(p.fault, Fault::NoDevice);
  for (const char* bad : {"alloc:", "alloc:0", "alloc:x", "alloc:3x", "oom", "ALLOC", "device-lost"})
    EXPECT_FALSE(vk::parseFault(bad, p)) << bad;
}

TEST(FaultInjection, NoDeviceIsATypedErrorAndAnEmptyDeviceList) {
  const FaultScope fault({Fault::NoDevice});
  try {
    vk::Context::create(memoryOnlyCache());
    FAIL() << "Context::create succeeded under SHAPESPLINE_FAULT=no_device";
  } catch (const vk::NoDeviceError& e) {
    EXPECT_TRUE(contains(e.what(), "no suitable Vulkan device")) << e.what();
    EXPECT_TRUE(contains(e.what(), vk::kInjectedNote)) << e.what();
  }
  EXPECT_TRUE(vk::Context::listDevices().empty());
}

class FaultInjectionGpu : public VulkanTest {};

TEST_F(FaultInjectionGpu, AllocationFailureNamesTheSizeAndLeavesTheContextUsable) {
  {
    const FaultScope fault({Fault::Alloc, 3});
    vk::Buffer a = vk::Buffer::create(ctx(), 256, vk::kStorageUsage, vk::MemoryUse::DeviceLocal, "first");
    vk::Buffer b = vk::Buffer::create(ctx(), 512, vk::kStorageUsage, vk::MemoryUse::Readback, "second");
    for (int attempt = 0; attempt < 2; ++attempt) {
      try {
        vk::Buffer::create(ctx(), 4096, vk::kStorageUsage, vk::MemoryUse::Upload, "third");
        FAIL() << "allocation " << attempt + 3 << " succeeded under alloc:3";
      } catch (const vk::VulkanError& e) {
        EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY);
        EXPECT_TRUE(contains(e.what(), "VK_ERROR_OUT_OF_DEVICE_MEMORY")) << e.what();
        EXPECT_TRUE(contains(e.what(), "4096")) << e.what();
        EXPECT_TRUE(contains(e.what(), vk::kInjectedNote)) << e.what();
      }
    }
    EXPECT_NE(a.handle(), VK_NULL_HANDLE);
    EXPECT_NE(b.handle(), VK_NULL_HANDLE);
  }
  // The fault is gone: the same context allocates and submits again.
  vk::Buffer c = vk::Buffer::create(ctx(), 4096, vk::kStorageUsage, vk::MemoryUse::Readback, "after");
  vk::runOneShot(ctx(), [&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, c.handle(), 0, VK_WHOLE_SIZE, 7u); });
  EXPECT_FALSE(ctx().deviceLost());
}

TEST_F(FaultInjectionGpu, AllocationFailureInsideAnEvaluatorJobThrowsCleanly) {
  const Curve curve = Curve::create(smallCurve());
  gpu::CurveEvaluator evaluator(ctx_, Precision::Float);
  GridSpec grid;
  grid.samplesU = 16;
  const FieldMask fields = fieldBit(Field::Point) | fieldBit(Field::D1);
  // Fail the 1st, 2nd, ... allocation of model upload + job in turn: every one must throw a
  // VulkanError before any chunk reaches the consumer, and the evaluator must work afterwards.
  for (uint64_t n = 1; n <= 6; ++n) {
    size_t chunks = 0;
    bool threw = false;
    {
      const FaultScope fault({Fault::Alloc, n});
      try {
        gpu::GpuCurve state(ctx_, curve, Precision::Float);
        evaluator.evaluateGrid(state, grid, fields, [&](const GridChunk&) { ++chunks; });
      } catch (const vk::VulkanError& e) {
        threw = true;
        EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY) << e.what();
        EXPECT_EQ(chunks, 0u) << "a chunk was delivered before the allocation failure at allocation " << n;
      }
    }
    if (!threw) break;  // the job needs fewer than n allocations
  }
  gpu::GpuCurve state(ctx_, curve, Precision::Float);
  size_t points = 0;
  evaluator.evaluateGrid(state, grid, fields, [&](const GridChunk& c) { points += c.pointCount(); });
  EXPECT_EQ(points, curveGridItems(curve).size() * 16);
}

TEST(FaultInjection, DeviceLostIsReportedAndEveryLaterSubmissionFailsFast) {
  // A Context of its own: a lost context cannot be used again, and the shared test context must
  // stay healthy for the other tests of this process.
  std::shared_ptr<vk::Context> ctx;
  try {
    ctx = vk::Context::create(memoryOnlyCache());
  } catch (const vk::NoDeviceError& e) {
    GTEST_SKIP() << e.what();
  }
  vk::Buffer buffer = vk::Buffer::create(*ctx, 1024, vk::kStorageUsage, vk::MemoryUse::Readback, "lost");
  {
    const FaultScope fault({Fault::DeviceLost});
    try {
      vk::runOneShot(*ctx, [&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, buffer.handle(), 0, VK_WHOLE_SIZE, 1u); });
      FAIL() << "submission succeeded under device_lost";
    } catch (const vk::VulkanError& e) {
      EXPECT_EQ(e.result(), VK_ERROR_DEVICE_LOST);
      EXPECT_TRUE(contains(e.what(), "GPU was lost")) << e.what();
      EXPECT_TRUE(contains(e.what(), vk::kInjectedNote)) << e.what();
    }
  }
  EXPECT_TRUE(ctx->deviceLost());
  // Fault cleared, but the context stays lost: the next command buffer is refused up front.
  try {
    vk::OneShot shot(*ctx);
    FAIL() << "OneShot started on a lost context";
  } catch (const vk::VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_DEVICE_LOST);
  }
  // The evaluator path reports the same error type.
  EXPECT_THROW(
      {
        gpu::CurveEvaluator evaluator(ctx, Precision::Float);
        const Curve curve = Curve::create(smallCurve());
        gpu::GpuCurve state(ctx, curve, Precision::Float);
        GridSpec grid;
        grid.samplesU = 4;
        evaluator.evaluateGrid(state, grid, fieldBit(Field::Point), [](const GridChunk&) {});
      },
      vk::VulkanError);
  buffer = vk::Buffer();
  ctx.reset();  // destroying a lost context must neither hang nor crash
}

}  // namespace
}  // namespace shapespline::test
