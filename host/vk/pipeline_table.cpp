#include <shapespline/vk/pipeline_table.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace shapespline::vk {

// A desc by value: the SPIR-V is copied, so a caller's buffer may go away after get().
struct PipelineTable::Entry {
  explicit Entry(const ComputePipelineDesc& d)
      : spirv(d.spirv.begin(), d.spirv.end()), spec(d.specConstants), pushConstantBytes(d.pushConstantBytes),
        storageBufferCount(d.storageBufferCount), label(d.label) {}

  std::vector<uint32_t> spirv;
  std::vector<SpecConstant> spec;
  uint32_t pushConstantBytes;
  uint32_t storageBufferCount;
  std::string label;
  std::mutex compiling;                     // held while `pipeline` compiles
  std::optional<ComputePipeline> pipeline;  // set once, under `compiling`
  std::atomic<bool> ready{false};           // `pipeline` is set (size() reads it without `compiling`)

  bool matches(const ComputePipelineDesc& d) const {
    return pushConstantBytes == d.pushConstantBytes && storageBufferCount == d.storageBufferCount &&
           label == d.label && std::ranges::equal(spirv, d.spirv) && spec == d.specConstants;
  }
};

namespace {

// FNV-1a over every field of the desc.
std::size_t hashOf(const ComputePipelineDesc& d) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](uint64_t v) {
    h ^= v;
    h *= 1099511628211ull;
  };
  for (uint32_t w : d.spirv) mix(w);
  for (const SpecConstant& c : d.specConstants) mix((uint64_t(c.id) << 32) | c.value);
  mix(d.pushConstantBytes);
  mix(d.storageBufferCount);
  mix(std::hash<std::string>{}(d.label));
  return std::size_t(h);
}

}  // namespace

PipelineTable::PipelineTable(Context& ctx) : ctx_(ctx) {}
PipelineTable::~PipelineTable() = default;

const ComputePipeline& PipelineTable::get(const ComputePipelineDesc& desc) {
  const std::size_t key = hashOf(desc);
  std::shared_ptr<Entry> entry;
  {
    std::lock_guard lock(mutex_);
    auto [first, last] = entries_.equal_range(key);
    for (auto it = first; it != last && !entry; ++it)
      if (it->second->matches(desc)) entry = it->second;
    if (!entry) entry = entries_.emplace(key, std::make_shared<Entry>(desc))->second;
  }
  std::lock_guard compiling(entry->compiling);
  if (!entry->pipeline) {
    try {
      entry->pipeline.emplace(ComputePipeline::create(ctx_, desc));
    } catch (...) {
      forget(key, entry);  // a bad desc stores nothing
      throw;
    }
    entry->ready.store(true, std::memory_order_release);
  }
  return *entry->pipeline;
}

void PipelineTable::forget(std::size_t key, const std::shared_ptr<Entry>& entry) {
  std::lock_guard lock(mutex_);
  auto [first, last] = entries_.equal_range(key);
  for (auto it = first; it != last; ++it)
    if (it->second == entry) {
      entries_.erase(it);
      return;
    }
}

std::size_t PipelineTable::size() const {
  std::lock_guard lock(mutex_);
  return std::size_t(std::ranges::count_if(entries_, [](const auto& e) {
    return e.second->ready.load(std::memory_order_acquire);
  }));
}

}  // namespace shapespline::vk
