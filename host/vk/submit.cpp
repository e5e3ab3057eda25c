#include <shapespline/vk/submit.h>

#include <shapespline/vk/error.h>
#include <shapespline/vk/fault.h>
#include <shapespline/vk/pipeline.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace shapespline::vk {

OneShot::OneShot(Context& ctx) : ctx_(ctx), lock_(ctx.submitMutex()) {
  if (ctx.deviceLost()) throw VulkanError(VK_ERROR_DEVICE_LOST, "starting a command buffer");
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = ctx.commandPool();
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(ctx.device(), &alloc, &cmd_), "vkAllocateCommandBuffers");

  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  VkResult result = vkCreateFence(ctx.device(), &fenceInfo, nullptr, &fence);
  if (result != VK_SUCCESS) {
    vkFreeCommandBuffers(ctx.device(), ctx.commandPool(), 1, &cmd_);
    check(result, "vkCreateFence");
  }
  fence_ = FenceHandle(ctx.device(), fence);

  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  result = vkBeginCommandBuffer(cmd_, &begin);
  if (result != VK_SUCCESS) {
    vkFreeCommandBuffers(ctx.device(), ctx.commandPool(), 1, &cmd_);
    check(result, "vkBeginCommandBuffer");
  }
}

OneShot::~OneShot() {
  // A submission still pending (submitAndWait timed out) must not have its command buffer or fence
  // destroyed while the GPU may use them: leave both to the Context, which waits for the device
  // before destroying the pool. Blocking here could hang forever on a hung GPU.
  if (submitted_ && !ctx_.deviceLost() && vkGetFenceStatus(ctx_.device(), fence_.get()) != VK_SUCCESS) {
    fence_.release();
    return;
  }
  vkFreeCommandBuffers(ctx_.device(), ctx_.commandPool(), 1, &cmd_);
}

namespace {

// The fence wait alone makes writes available but not visible to the host (Vulkan spec 7.9,
// "Host Write Ordering Guarantees" covers only the other direction).
void hostReadBarrier(VkCommandBuffer cmd) {
  VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  toHost.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost, 0, nullptr, 0, nullptr);
}

// Ends `cmd` (after the host-read barrier) and submits it with `fence`; the caller holds the
// context's submit mutex (the queue is externally synchronized).
void endAndSubmit(Context& ctx, VkCommandBuffer cmd, VkFence fence) {
  if (ctx.deviceLost()) throw VulkanError(VK_ERROR_DEVICE_LOST, "submitting a command buffer");
  if (deviceLostFaultDue()) {  // test-only fault injection (vk/fault.h)
    ctx.markDeviceLost();
    throw VulkanError(VK_ERROR_DEVICE_LOST, std::string("vkQueueSubmit") + kInjectedNote);
  }
  hostReadBarrier(cmd);
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  const VkResult result = vkQueueSubmit(ctx.queue(), 1, &submit, fence);
  if (result == VK_ERROR_DEVICE_LOST) ctx.markDeviceLost();
  check(result, "vkQueueSubmit");
}

void waitForFence(Context& ctx, VkFence fence, std::chrono::nanoseconds timeout) {
  const uint64_t ns = uint64_t(std::max<std::chrono::nanoseconds::rep>(0, timeout.count()));
  const VkResult result = vkWaitForFences(ctx.device(), 1, &fence, VK_TRUE, ns);
  if (result == VK_TIMEOUT) {
    throw VulkanError(VK_TIMEOUT, "vkWaitForFences",
                      "GPU work did not finish within " +
                          std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(timeout).count()) +
                          " ms (vkWaitForFences returned VK_TIMEOUT)");
  }
  if (result == VK_ERROR_DEVICE_LOST) ctx.markDeviceLost();
  check(result, "vkWaitForFences (waiting for a compute submission)");
}

FenceHandle createFence(Context& ctx) {
  VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  check(vkCreateFence(ctx.device(), &info, nullptr, &fence), "vkCreateFence");
  return FenceHandle(ctx.device(), fence);
}

void beginOneTime(VkCommandBuffer cmd) {
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
}

}  // namespace

void OneShot::submitAndWait(std::chrono::nanoseconds timeout) {
  if (submitted_) throw std::logic_error("OneShot::submitAndWait called twice");
  endAndSubmit(ctx_, cmd_, fence_.get());
  submitted_ = true;
  waitForFence(ctx_, fence_.get(), timeout);
  submitted_ = false;  // finished: nothing left to wait for in the destructor
}

SubmitRing::SubmitRing(Context& ctx, uint32_t slots) : ctx_(ctx), pending_(slots, false) {
  VkCommandPoolCreateInfo info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  info.queueFamilyIndex = ctx.queueFamily();
  VkCommandPool pool = VK_NULL_HANDLE;
  check(vkCreateCommandPool(ctx.device(), &info, nullptr, &pool), "vkCreateCommandPool (submit ring)");
  pool_ = CommandPoolHandle(ctx.device(), pool);
  cmd_.resize(slots);
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = pool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = slots;
  check(vkAllocateCommandBuffers(ctx.device(), &alloc, cmd_.data()), "vkAllocateCommandBuffers (submit ring)");
  for (uint32_t i = 0; i < slots; ++i) fence_.push_back(createFence(ctx));
}

SubmitRing::~SubmitRing() {
  for (size_t i = 0; i < cmd_.size(); ++i) {
    if (!pending_[i] || ctx_.deviceLost()) continue;
    VkFence f = fence_[i].get();
    if (vkWaitForFences(ctx_.device(), 1, &f, VK_TRUE, uint64_t(kDefaultFenceTimeout.count()) * 1000000ull) !=
        VK_SUCCESS) {
      fence_[i].release();  // still in use by a hung device: leak rather than destroy
      pool_.release();
    }
  }
}

VkCommandBuffer SubmitRing::begin(uint32_t slot) {
  check(vkResetCommandBuffer(cmd_[slot], 0), "vkResetCommandBuffer (submit ring)");
  beginOneTime(cmd_[slot]);
  return cmd_[slot];
}

void SubmitRing::submit(uint32_t slot) {
  VkFence f = fence_[slot].get();
  check(vkResetFences(ctx_.device(), 1, &f), "vkResetFences (submit ring)");
  std::lock_guard<std::recursive_mutex> lock(ctx_.submitMutex());
  endAndSubmit(ctx_, cmd_[slot], f);
  pending_[slot] = true;
}

void SubmitRing::wait(uint32_t slot, std::chrono::nanoseconds timeout) {
  waitForFence(ctx_, fence_[slot].get(), timeout);
  pending_[slot] = false;
}

void runOneShot(Context& ctx, const std::function<void(VkCommandBuffer)>& record, std::chrono::nanoseconds timeout) {
  OneShot shot(ctx);
  record(shot.cmd());
  shot.submitAndWait(timeout);
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags srcAccess, VkPipelineStageFlags dst,
                   VkAccessFlags dstAccess) {
  VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  b.srcAccessMask = srcAccess;
  b.dstAccessMask = dstAccess;
  vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &b, 0, nullptr, 0, nullptr);
}

void computeBarrier(VkCommandBuffer cmd) {
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                          VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                           VK_PIPELINE_STAGE_HOST_BIT,
                       0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void transferBarrier(VkCommandBuffer cmd) {
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                           VK_PIPELINE_STAGE_HOST_BIT,
                       0, 1, &barrier, 0, nullptr, 0, nullptr);
}

uint32_t dispatchChunked(VkCommandBuffer cmd, const Context& ctx, const ComputePipeline& pipeline,
                         const ChunkedDispatch& dispatch) {
  if (dispatch.groupCount > UINT32_MAX) {
    throw std::invalid_argument("dispatchChunked: groupCount " + std::to_string(dispatch.groupCount) +
                                " exceeds 2^32-1 (the base group is a uint32 push constant)");
  }
  if (dispatch.baseGroupOffset % 4 != 0 || dispatch.baseGroupOffset + 4 > pipeline.pushConstantBytes()) {
    throw std::invalid_argument("dispatchChunked: baseGroupOffset " + std::to_string(dispatch.baseGroupOffset) +
                                " is not a 4-aligned uint32 inside the " +
                                std::to_string(pipeline.pushConstantBytes()) + "-byte push-constant block");
  }
  uint32_t limit = ctx.limits().maxComputeWorkGroupCount[0];
  if (dispatch.maxGroupsPerDispatch != 0) limit = std::min(limit, dispatch.maxGroupsPerDispatch);
  uint32_t dispatches = 0;
  for (uint64_t base = 0; base < dispatch.groupCount; base += limit) {
    const uint32_t base32 = uint32_t(base);
    const uint32_t groups = uint32_t(std::min<uint64_t>(limit, dispatch.groupCount - base));
    vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, dispatch.baseGroupOffset, 4, &base32);
    vkCmdDispatch(cmd, groups, 1, 1);
    ++dispatches;
  }
  return dispatches;
}

}  // namespace shapespline::vk
