#include <shapespline/vk/pipeline_table.h>

#include <algorithm>
#include <functional>
#include <vector>

namespace shapespline::vk {

// A desc by value: the SPIR-V is copied, so a caller's buffer may go away after get().
struct PipelineTable::Entry {
  std::vector<uint32_t> spirv;
  std::vector<SpecConstant> spec;
  uint32_t pushConstantBytes;
  uint32_t storageBufferCount;
  std::string label;
  ComputePipeline pipeline;

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
  std::lock_guard lock(mutex_);
  auto [first, last] = entries_.equal_range(key);
  for (auto it = first; it != last; ++it)
    if (it->second->matches(desc)) return it->second->pipeline;
  auto entry = std::make_unique<Entry>(Entry{std::vector<uint32_t>(desc.spirv.begin(), desc.spirv.end()),
                                             desc.specConstants, desc.pushConstantBytes, desc.storageBufferCount,
                                             desc.label, ComputePipeline::create(ctx_, desc)});
  return entries_.emplace(key, std::move(entry))->second->pipeline;
}

std::size_t PipelineTable::size() const {
  std::lock_guard lock(mutex_);
  return entries_.size();
}

}  // namespace shapespline::vk
