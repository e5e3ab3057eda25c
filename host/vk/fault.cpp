#include <shapespline/vk/fault.h>

#include <atomic>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>

namespace shapespline::vk {

namespace {

struct State {
  std::mutex mutex;
  bool loaded = false;
  FaultPlan plan;
  std::atomic<uint64_t> allocations{0};
};

State& state() {
  static State s;
  return s;
}

FaultPlan loadedPlan() {
  State& s = state();
  std::lock_guard lock(s.mutex);
  if (!s.loaded) {
    s.loaded = true;
    const char* env = std::getenv("SHAPESPLINE_FAULT");
    if (env && !parseFault(env, s.plan)) {
      std::fprintf(stderr,
                   "warning: SHAPESPLINE_FAULT=%s is not one of alloc, alloc:N, device_lost, no_device; ignored\n", env);
      s.plan = {};
    }
  }
  return s.plan;
}

}  // namespace

bool parseFault(std::string_view text, FaultPlan& plan) {
  plan = {};
  if (text.empty()) return true;
  if (text == "device_lost") return plan.fault = Fault::DeviceLost, true;
  if (text == "no_device") return plan.fault = Fault::NoDevice, true;
  if (text == "alloc") return plan.fault = Fault::Alloc, true;
  if (text.starts_with("alloc:")) {
    const std::string_view n = text.substr(6);
    uint64_t value = 0;
    const auto [end, ec] = std::from_chars(n.data(), n.data() + n.size(), value);
    if (ec != std::errc() || end != n.data() + n.size() || value == 0) return false;
    plan.fault = Fault::Alloc;
    plan.firstFailingAllocation = value;
    return true;
  }
  return false;
}

FaultPlan activeFault() { return loadedPlan(); }

void setFaultForTesting(const FaultPlan& plan) {
  State& s = state();
  std::lock_guard lock(s.mutex);
  s.loaded = true;
  s.plan = plan;
  s.allocations = 0;
}

bool allocationFaultDue() {
  const FaultPlan plan = loadedPlan();
  if (plan.fault != Fault::Alloc) return false;
  return ++state().allocations >= plan.firstFailingAllocation;
}

bool deviceLostFaultDue() { return loadedPlan().fault == Fault::DeviceLost; }
bool noDeviceFaultDue() { return loadedPlan().fault == Fault::NoDevice; }

}  // namespace shapespline::vk
