#pragma once
// PipelineTable: the compute pipelines compiled on one Context, each distinct ComputePipelineDesc
// once. Every evaluator, tessellator and sampler asks for the same few kernels, and a compile is
// expensive (lavapipe: 0.1-1 s a pipeline; a GPU driver: milliseconds even when its VkPipelineCache
// has the shader), so compiling them again for each new evaluator made creating one cost more than
// using it. Owned by the Context (Context::pipelines()) and destroyed before its device: a
// pipeline lives as long as its Context. The table holds one entry per distinct kernel variant
// asked for (kernel x precision x specialization), a set bounded by the shaders and their
// specialization constants. Thread-safe.
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
  // Pipelines compiled so far.
  std::size_t size() const;

 private:
  struct Entry;
  Context& ctx_;
  mutable std::mutex mutex_;
  std::unordered_multimap<std::size_t, std::unique_ptr<Entry>> entries_;  // by hash of the desc
};

}  // namespace shapespline::vk
