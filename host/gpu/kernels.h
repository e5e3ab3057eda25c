#pragma once
// Internal to host/gpu: the embedded SPIR-V of every evaluation kernel in both precisions, the
// pipeline of a (kernel, specialization constants) pair from the context's table (each variant is
// compiled once per context, whichever evaluator asks first), and the helpers every evaluator
// shares (REAL conversion, dispatch sizing, a dummy buffer for bindings a variant does not use).
#include <shapespline/core/sample_grid.h>
#include <shapespline/gpu/gpu_model.h>

#include <glm/vec3.hpp>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/context.h>
#include <shapespline/vk/pipeline.h>
#include <shapespline/shaders/layout.h>

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <vector>

namespace shapespline::gpu {

enum class Kernel { CurveEval, SurfaceEval, AlphaEBVertices, BasisTable, BSplineCurveEval, BSplineSurfaceEval,
                    BSplineCurveGrid, BSplineSurfaceGrid, SurfaceGrid, CurveGrid, TessellateGrid, AdaptiveRates, AdaptiveLayout, AdaptiveMesh,
                    ClosestPoints };

// Bytes of one REAL.
inline size_t realSize(Precision p) { return p == Precision::Double ? 8 : 4; }

// Converts fp64 values to REAL bytes.
std::vector<std::byte> toReal(std::span<const double> values, Precision p);
// xyz of each point into REAL4 bytes (w = 0).
std::vector<std::byte> toReal4(std::span<const glm::dvec3> points, Precision p);
// The same into `out` (points.size() * 4 REALs, w = +0.0): for an upload that converts in place.
void writeReal4(std::span<const glm::dvec3> points, Precision p, std::byte* out);
std::vector<std::byte> toReal4(std::span<const glm::dvec4> records, Precision p);

// Throws std::runtime_error naming the device when Double is asked of a device without shaderFloat64.
void requirePrecision(const vk::Context& ctx, Precision p);

// The compiled variants of one shader (shaders/CMakeLists.txt): fp32, fp64 and, for shaders marked
// packed-stores, the same with 64-bit packed output stores (empty spans where there are none).
struct ShaderVariants {
  std::span<const uint32_t> f32, f64, f32Packed, f64Packed;
  bool hasPacked() const { return !f32Packed.empty(); }
  std::span<const uint32_t> pick(bool fp64, bool packed) const {
    if (packed && hasPacked()) return fp64 ? f64Packed : f32Packed;
    return fp64 ? f64 : f32;
  }
};

// Specialization constants of one pipeline variant keyed by their shaders/layout.h (tess_layout.h)
// ids; KernelSet adds kSpecWorkgroupSize. A kernel is given only the constants it reads.
using SpecValues = std::map<uint32_t, uint32_t>;
// kSpecBasisCountU .. kSpecPolyDegreeV of the u and v span bases.
SpecValues basisSpec(const SpanBasis& u, const SpanBasis& v);

class KernelSet {
 public:
  // packedStores: use the packed-store variants where the device has shaderInt64.
  KernelSet(std::shared_ptr<vk::Context> ctx, Precision precision, uint32_t workgroupSize, bool packedStores);

  vk::Context& context() const { return *ctx_; }
  Precision precision() const { return precision_; }
  uint32_t workgroupSize() const { return workgroupSize_; }
  // Whether the packed-store variants are in use (asked for and shaderInt64 present).
  bool packedStores() const { return packedStores_; }
  // The pipeline of `kernel` specialised with `spec` (compiled on the context's first request).
  const vk::ComputePipeline& pipeline(Kernel kernel, const SpecValues& spec);
  // 256-byte buffer bound to every binding a pipeline variant does not use.
  const vk::Buffer& dummy() const { return dummy_; }
  // Records a dispatch of `invocations` 1-D invocations (x then y when over the group limit).
  void dispatch(VkCommandBuffer cmd, uint64_t invocations) const;

 private:
  std::shared_ptr<vk::Context> ctx_;
  Precision precision_;
  uint32_t workgroupSize_;
  bool packedStores_;
  // This set's lookups into the context's vk::PipelineTable, so that a repeated request skips
  // hashing the SPIR-V.
  std::map<std::pair<Kernel, SpecValues>, const vk::ComputePipeline*> pipelines_;
  vk::Buffer dummy_;
};

// The net, patch-range and α-EB fields that layout::EvalPush and tess_layout::TessGridPush share
// (same names), from a surface.
template <class Push>
void setSurfaceNetFields(Push& p, const GpuSurface& s) {
  // Knot-vector surfaces (knot patches, layout.h): patch i is the i-th non-empty interval.
  p.firstSpanU = s.knotVector() ? 0u : uint32_t(s.patches().u.first);
  p.firstSpanV = s.knotVector() ? 0u : uint32_t(s.patches().v.first);
  p.netCols = s.netCols();
  p.netOffsetU = s.netOffsetU();
  p.netOffsetV = s.netOffsetV();
  p.rows = s.vertexRows();
  p.cols = s.vertexCols();
  p.alphaOffset = s.alphaOffset();
}

// EvalPush fields of a surface's net, patch range and α-EB data (items and samples left to the caller).
layout::EvalPush surfacePush(const GpuSurface& s);

// Number of storage-buffer bindings of every evaluation pipeline (layout.h: outputs 5..13).
inline constexpr uint32_t kBindingCount = 14;

}  // namespace shapespline::gpu
