#pragma once
// PipelineTable: the compute pipelines compiled on one Context, each distinct ComputePipelineDesc
// once. Every evaluator, tessellator and sampler asks for the same few kernels, and a compile is
// expensive (lavapipe: 0.1-1 s a pipeline; a GPU driver: milliseconds even when its VkPipelineCache
// has the shader), so compiling them again for each new evaluator made creating one cost more than
// using it. Owned by the Context (Context::pipelines()) and destroyed before its device: a
// pipeline lives as long as its Context. The table holds one entry per distinct kernel variant
// asked for (kernel x precision x specialization), a set bounded by the shaders and their
// specialization constants. Thread-safe: a pipeline compiles outside the table's lock, so a thread
// that asks for another pipeline, or for one compiled already, does not wait for it; threads that
// ask for the same new pipeline wait for its one compile.
#include <shapespline/vk/pipeline.h>

#include <cstddef>
#include <memory>
#include <mutex>
#include <unordered_map>

namespace shapespline::vk {

class PipelineTable {
 public:
  explicit PipelineTable(Context& ctx);
  ~PipelineTable();
  PipelineTable(const PipelineTable&) = delete;
  PipelineTable& operator=(const PipelineTable&) = delete;

  // The pipeline of `desc`, compiled on its first request (ComputePipeline::create, which throws for
  // a bad desc; nothing is stored then). Equal descs (same SPIR-V words, specialization constants,
  // push-constant size, binding count and label) share one pipeline. The reference stays valid for
  // the table's life.
  const ComputePipeline& get(const ComputePipelineDesc& desc);
  // Pipelines compiled so far (not those still compiling).
  std::size_t size() const;

 private:
  struct Entry;
  void forget(std::size_t key, const std::shared_ptr<Entry>& entry);

  Context& ctx_;
  mutable std::mutex mutex_;  // guards entries_, not the compiles
  // By hash of the desc. Shared: a thread compiling an entry keeps it alive if the entry's compile
  // fails and it leaves the table meanwhile.
  std::unordered_multimap<std::size_t, std::shared_ptr<Entry>> entries_;
};

}  // namespace shapespline::vk
