#pragma once
// Recording and submitting work: OneShot (one primary command buffer, submit, wait on a fence),
// SubmitRing (a few reusable command buffers in flight at once, for streaming chunked jobs), the
// barriers used between dependent dispatches, and chunked 1-D dispatch that respects
// maxComputeWorkGroupCount. Both submitters go through the same submit and fence-wait steps.
#include <shapespline/vk/context.h>
#include <shapespline/vk/handle.h>

#include <vulkan/vulkan_core.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

namespace shapespline::vk {

class ComputePipeline;

// Long enough for the biggest lavapipe jobs of the test suite; a real hang is reported, not waited on forever.
inline constexpr std::chrono::milliseconds kDefaultFenceTimeout{std::chrono::minutes(5)};

// One primary command buffer from the context's pool, begun in the constructor. Record into cmd(),
// then submitAndWait(). Holds the context's submit mutex for its whole life (the command pool and
// queue are externally synchronized), so GPU work through one Context is serialized across threads.
class OneShot {
 public:
  explicit OneShot(Context& ctx);
  ~OneShot();  // frees the command buffer (leaks it to the Context if a timed-out submission is pending)
  OneShot(const OneShot&) = delete;
  OneShot& operator=(const OneShot&) = delete;

  VkCommandBuffer cmd() const { return cmd_; }

  // Ends the command buffer, submits it and waits for its fence. Appends a barrier that makes every
  // shader/transfer write visible to the host, so mapped buffers can be read right after.
  // Throws VulkanError: VK_TIMEOUT after `timeout`, VK_ERROR_DEVICE_LOST (the context is marked lost).
  void submitAndWait(std::chrono::nanoseconds timeout = kDefaultFenceTimeout);

 private:
  Context& ctx_;
  std::unique_lock<std::recursive_mutex> lock_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  FenceHandle fence_;
  bool submitted_ = false;
};

// `slots` primary command buffers with a fence each, from the ring's own command pool, reused for
// a stream of submissions: while the GPU runs slot k+1 the caller reads slot k's results. begin()
// re-records a slot (its previous submission must have been waited for); submit() appends the same
// host-read barrier as OneShot. The submit mutex is held only inside submit(). The destructor waits
// for pending slots (a caller that throws mid-stream leaves one in flight).
class SubmitRing {
 public:
  SubmitRing(Context& ctx, uint32_t slots);
  ~SubmitRing();
  SubmitRing(const SubmitRing&) = delete;
  SubmitRing& operator=(const SubmitRing&) = delete;

  uint32_t slots() const { return uint32_t(cmd_.size()); }
  VkCommandBuffer begin(uint32_t slot);
  void submit(uint32_t slot);
  // Throws VulkanError like OneShot::submitAndWait.
  void wait(uint32_t slot, std::chrono::nanoseconds timeout = kDefaultFenceTimeout);

 private:
  Context& ctx_;
  CommandPoolHandle pool_;
  std::vector<VkCommandBuffer> cmd_;
  std::vector<FenceHandle> fence_;
  std::vector<bool> pending_;
};

// Records into a OneShot and submits it: runOneShot(ctx, [&](VkCommandBuffer cmd) { ... }).
void runOneShot(Context& ctx, const std::function<void(VkCommandBuffer)>& record,
                std::chrono::nanoseconds timeout = kDefaultFenceTimeout);

// Global memory barrier between a dispatch and whatever consumes its results: compute-shader and
// transfer writes -> shader read/write, transfer read/write, host read.
void computeBarrier(VkCommandBuffer cmd);
// One global memory barrier: writes `srcAccess` of stages `src` before accesses `dstAccess` of `dst`.
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags srcAccess, VkPipelineStageFlags dst,
                   VkAccessFlags dstAccess);
// Transfer writes (copy/fill) -> compute shader reads, transfer reads, host reads.
void transferBarrier(VkCommandBuffer cmd);

struct ChunkedDispatch {
  uint64_t groupCount = 0;  // workgroups along x; at most UINT32_MAX so that the base fits a uint
  // Byte offset in the pipeline's push-constant block of the uint32 field that receives the index of
  // the first workgroup of each dispatch; the shader adds it to gl_WorkGroupID.x.
  uint32_t baseGroupOffset = 0;
  // Groups per dispatch; 0: the device's maxComputeWorkGroupCount[0].
  uint32_t maxGroupsPerDispatch = 0;
};

// Records ceil(groupCount / limit) vkCmdDispatch(n, 1, 1), pushing the base group before each.
// The pipeline and descriptor set must be bound and the rest of the push constants pushed already.
// The chunks are independent: no barrier between them. Returns the number of dispatches recorded.
uint32_t dispatchChunked(VkCommandBuffer cmd, const Context& ctx, const ComputePipeline& pipeline,
                         const ChunkedDispatch& dispatch);

}  // namespace shapespline::vk
