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

void OneShot::submitAndWait(std::chrono::nanoseconds timeout) {
  if (submitted_) throw std::logic_error("OneShot::submitAndWait called twice");
  if (deviceLostFaultDue()) {
    ctx_.markDeviceLost();
    throw VulkanError(VK_ERROR_DEVICE_LOST, std::string("vkQueueSubmit") + kInjectedNote);
  }
  VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  toHost.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  // The fence wait alone makes writes available but not visible to the host (Vulkan spec 7.9,
  // "Host Write Ordering Guarantees" covers only the other direction).
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost, 0, nullptr, 0, nullptr);
  check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");

  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd_;
  VkResult result = vkQueueSubmit(ctx_.queue(), 1, &submit, fence_.get());
  if (result == VK_ERROR_DEVICE_LOST) ctx_.markDeviceLost();
  check(result, "vkQueueSubmit");
  submitted_ = true;

  VkFence fence = fence_.get();
  const uint64_t ns = uint64_t(std::max<std::chrono::nanoseconds::rep>(0, timeout.count()));
  result = vkWaitForFences(ctx_.device(), 1, &fence, VK_TRUE, ns);
  if (result == VK_TIMEOUT) {
    throw VulkanError(VK_TIMEOUT, "vkWaitForFences",
                      "GPU work did not finish within " +
                          std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(timeout).count()) +
                          " ms (vkWaitForFences returned VK_TIMEOUT)");
  }
  if (result == VK_ERROR_DEVICE_LOST) ctx_.markDeviceLost();
  check(result, "vkWaitForFences (waiting for a compute submission)");
  submitted_ = false;  // finished: nothing left to wait for in the destructor
}

void runOneShot(Context& ctx, const std::function<void(VkCommandBuffer)>& record, std::chrono::nanoseconds timeout) {
  OneShot shot(ctx);
  record(shot.cmd());
  shot.submitAndWait(timeout);
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
