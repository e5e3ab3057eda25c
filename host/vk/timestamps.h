#pragma once
// PassTimer: GPU timestamps between the passes of one command buffer, for benchmarks and profiling.
// reset(cmd) at the start, mark(cmd, "name") after each pass, and once the submission has completed
// passes() gives each named interval in milliseconds (device clock, timestampPeriod). Each mark
// records a full pipeline barrier before its timestamp and one after it (llvmpipe may otherwise
// read the clock at its next flush), so passes that would overlap are serialised: the sum is an
// upper bound of the unprofiled frame, each interval its pass's. A queue
// family without timestamps (timestampValidBits == 0) makes it inert: passes() is then empty.
#include <shapespline/vk/context.h>
#include <shapespline/vk/handle.h>

#include <vulkan/vulkan_core.h>

#include <string>
#include <utility>
#include <vector>

namespace shapespline::vk {

class PassTimer {
 public:
  // Room for `maxMarks` marks per command buffer (plus the reset's own).
  PassTimer(Context& ctx, uint32_t maxMarks);

  bool available() const { return bool(pool_); }
  void reset(VkCommandBuffer cmd);                        // resets the pool and writes the start time
  void mark(VkCommandBuffer cmd, std::string name);       // the time once every earlier command is done
  // (name, ms since the previous mark) for every mark of the last recording; waits for the results.
  std::vector<std::pair<std::string, double>> passes() const;

 private:
  Context& ctx_;
  QueryPoolHandle pool_;
  uint32_t capacity_ = 0;
  double periodNs_ = 1.0;
  uint64_t validMask_ = ~0ull;
  std::vector<std::string> names_;
};

}  // namespace shapespline::vk
