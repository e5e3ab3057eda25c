#include <shapespline/vk/timestamps.h>

#include <shapespline/vk/error.h>

#include <stdexcept>

namespace shapespline::vk {

namespace {

// Every earlier command completes before any later one starts (and lavapipe flushes its context).
void fullBarrier(VkCommandBuffer cmd) {
  VkMemoryBarrier all{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  all.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  all.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &all, 0,
                       nullptr, 0, nullptr);
}

}  // namespace

PassTimer::PassTimer(Context& ctx, uint32_t maxMarks) : ctx_(ctx), capacity_(maxMarks + 1) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(ctx.physicalDevice(), &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(ctx.physicalDevice(), &count, families.data());
  const uint32_t bits = ctx.queueFamily() < count ? families[ctx.queueFamily()].timestampValidBits : 0;
  if (bits == 0) return;
  validMask_ = bits >= 64 ? ~0ull : (1ull << bits) - 1;
  periodNs_ = double(ctx.properties().limits.timestampPeriod);
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = capacity_;
  VkQueryPool pool = VK_NULL_HANDLE;
  check(vkCreateQueryPool(ctx.device(), &info, nullptr, &pool), "vkCreateQueryPool");
  pool_ = QueryPoolHandle(ctx.device(), pool);
}

void PassTimer::reset(VkCommandBuffer cmd) {
  names_.clear();
  if (!available()) return;
  vkCmdResetQueryPool(cmd, pool_.get(), 0, capacity_);
  fullBarrier(cmd);
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_.get(), 0);
  fullBarrier(cmd);
}

void PassTimer::mark(VkCommandBuffer cmd, std::string name) {
  if (!available()) return;
  if (names_.size() + 1 >= capacity_) throw std::length_error("PassTimer: more marks than its capacity");
  names_.push_back(std::move(name));
  // Everything recorded so far completes first: a bare timestamp needs only earlier commands to
  // have reached the stage, and lavapipe writes it before the compute work it follows has run,
  // charging that work to a later pass.
  fullBarrier(cmd);
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_.get(), uint32_t(names_.size()));
  // And the timestamp is taken now: llvmpipe can defer a timestamp to its next flush (it bins the
  // query into its render scene), and in the real-time bench, after frames had been drawn, each
  // mark then read the clock after the *next* pass: every interval was charged to the pass before
  // it (removing a pass emptied the interval before its own).
  fullBarrier(cmd);
}

std::vector<std::pair<std::string, double>> PassTimer::passes() const {
  std::vector<std::pair<std::string, double>> out;
  if (!available() || names_.empty()) return out;
  std::vector<uint64_t> ticks(names_.size() + 1);
  check(vkGetQueryPoolResults(ctx_.device(), pool_.get(), 0, uint32_t(ticks.size()), ticks.size() * sizeof(uint64_t),
                              ticks.data(), sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  for (size_t k = 0; k < names_.size(); ++k) {
    const uint64_t dt = (ticks[k + 1] - ticks[k]) & validMask_;
    out.emplace_back(names_[k], double(dt) * periodNs_ * 1e-6);
  }
  return out;
}

}  // namespace shapespline::vk
