#include <shapespline/gpu/kernels.h>

#include <shapespline/shaders/layout.h>
#include <shapespline/shaders/projection_layout.h>
#include <shapespline/vk/pipeline_table.h>
#include "shaders/alpha_eb_vertices_comp.h"
#include "shaders/alpha_eb_vertices_comp_f64.h"
#include "shaders/basis_table_comp.h"
#include "shaders/basis_table_comp_f64.h"
#include "shaders/bspline_curve_eval_comp.h"
#include "shaders/bspline_curve_eval_comp_f64.h"
#include "shaders/bspline_curve_grid_comp.h"
#include "shaders/bspline_curve_grid_comp_f64.h"
#include "shaders/bspline_surface_eval_comp.h"
#include "shaders/bspline_surface_eval_comp_f64.h"
#include "shaders/bspline_surface_grid_comp.h"
#include "shaders/bspline_surface_grid_comp_f64.h"
#include "shaders/closest_points_comp.h"
#include "shaders/closest_points_comp_f64.h"
#include "shaders/curve_eval_comp.h"
#include "shaders/curve_grid_comp.h"
#include "shaders/curve_grid_comp_f64.h"
#include "shaders/curve_grid_comp_f64_pk.h"
#include "shaders/curve_grid_comp_pk.h"
#include "shaders/curve_eval_comp_f64.h"
#include "shaders/surface_eval_comp.h"
#include "shaders/surface_eval_comp_f64.h"
#include "shaders/surface_grid_comp.h"
#include "shaders/surface_grid_comp_f64.h"
#include "shaders/surface_grid_comp_f64_pk.h"
#include "shaders/surface_grid_comp_pk.h"
#include "shaders/tess_adaptive_layout_comp.h"
#include "shaders/tess_adaptive_layout_comp_f64.h"
#include "shaders/tess_adaptive_mesh_comp.h"
#include "shaders/tess_adaptive_mesh_comp_f64.h"
#include "shaders/tess_adaptive_rates_comp.h"
#include "shaders/tess_adaptive_rates_comp_f64.h"
#include "shaders/tessellate_grid_comp.h"
#include "shaders/tessellate_grid_comp_f64.h"
#include "shaders/tessellate_grid_comp_f64_pk.h"
#include "shaders/tessellate_grid_comp_pk.h"
#include <shapespline/shaders/tess_layout.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace shapespline::gpu {

namespace {
// Value i of a REAL array at `out`. The REAL4 converters write straight into their result: a band
// of a 4096² net went through two temporary arrays of 32 bytes a point before.
void putReal(std::byte* out, size_t i, double value, Precision p) {
  if (p == Precision::Double) {
    std::memcpy(out + 8 * i, &value, 8);
  } else {
    const float f = static_cast<float>(value);
    std::memcpy(out + 4 * i, &f, 4);
  }
}
}  // namespace

std::vector<std::byte> toReal(std::span<const double> values, Precision p) {
  std::vector<std::byte> out(values.size() * realSize(p));
  for (size_t i = 0; i < values.size(); ++i) putReal(out.data(), i, values[i], p);
  return out;
}

void writeReal4(std::span<const glm::dvec3> points, Precision p, std::byte* out) {
  for (size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k) putReal(out, 4 * i + size_t(k), points[i][k], p);
    putReal(out, 4 * i + 3, 0.0, p);
  }
}

std::vector<std::byte> toReal4(std::span<const glm::dvec3> points, Precision p) {
  std::vector<std::byte> out(points.size() * 4 * realSize(p));
  writeReal4(points, p, out.data());
  return out;
}

std::vector<std::byte> toReal4(std::span<const glm::dvec4> records, Precision p) {
  std::vector<std::byte> out(records.size() * 4 * realSize(p));
  for (size_t i = 0; i < records.size(); ++i)
    for (int k = 0; k < 4; ++k) putReal(out.data(), 4 * i + size_t(k), records[i][k], p);
  return out;
}

void requirePrecision(const vk::Context& ctx, Precision p) {
  if (p == Precision::Double && !ctx.supportsFloat64())
    throw std::runtime_error("precision double needs shaderFloat64, which device '" + ctx.deviceName() +
                             "' does not support; use precision float");
}

static_assert(layout::kSpecUniformRates < tess_layout::kTessSpecListSources,
              "specialization-constant ids are unique across layout.h and tess_layout.h");

SpecValues basisSpec(const SpanBasis& u, const SpanBasis& v) {
  return {{layout::kSpecBasisCountU, uint32_t(u.count)},
          {layout::kSpecPolyDegreeU, uint32_t(u.degree)},
          {layout::kSpecBasisCountV, uint32_t(v.count)},
          {layout::kSpecPolyDegreeV, uint32_t(v.degree)}};
}

KernelSet::KernelSet(std::shared_ptr<vk::Context> ctx, Precision precision, uint32_t workgroupSize, bool packedStores)
    : ctx_(std::move(ctx)),
      precision_(precision),
      workgroupSize_(workgroupSize),
      packedStores_(packedStores && ctx_->supportsInt64()) {
  requirePrecision(*ctx_, precision_);
  dummy_ = vk::Buffer::create(*ctx_, 256, vk::kStorageUsage, vk::MemoryUse::DeviceLocal, "gpu.dummy");
}

const vk::ComputePipeline& KernelSet::pipeline(Kernel kernel, const SpecValues& spec) {
  if (spec.count(layout::kSpecWorkgroupSize))
    throw std::logic_error("KernelSet::pipeline: the workgroup size is the KernelSet's own constant");
  auto key = std::make_pair(kernel, spec);
  auto it = pipelines_.find(key);
  if (it != pipelines_.end()) return *it->second;
  const bool d = precision_ == Precision::Double;
  ShaderVariants code;
  uint32_t push = sizeof(layout::EvalPush);
  const char* label = "";
  switch (kernel) {
    case Kernel::CurveEval:
      code = {curve_eval_comp, curve_eval_comp_f64, {}, {}};
      label = "curve_eval";
      break;
    case Kernel::SurfaceEval:
      code = {surface_eval_comp, surface_eval_comp_f64, {}, {}};
      label = "surface_eval";
      break;
    case Kernel::BSplineCurveEval:
      code = {bspline_curve_eval_comp, bspline_curve_eval_comp_f64, {}, {}};
      push = sizeof(layout::KnotEvalPush);
      label = "bspline_curve_eval";
      break;
    case Kernel::BSplineSurfaceEval:
      code = {bspline_surface_eval_comp, bspline_surface_eval_comp_f64, {}, {}};
      push = sizeof(layout::KnotEvalPush);
      label = "bspline_surface_eval";
      break;
    case Kernel::BSplineCurveGrid:
      code = {bspline_curve_grid_comp, bspline_curve_grid_comp_f64, {}, {}};
      push = sizeof(layout::KnotEvalPush);
      label = "bspline_curve_grid";
      break;
    case Kernel::BSplineSurfaceGrid:
      code = {bspline_surface_grid_comp, bspline_surface_grid_comp_f64, {}, {}};
      push = sizeof(layout::KnotEvalPush);
      label = "bspline_surface_grid";
      break;
    case Kernel::SurfaceGrid:
      code = {surface_grid_comp, surface_grid_comp_f64, surface_grid_comp_pk, surface_grid_comp_f64_pk};
      label = "surface_grid";
      break;
    case Kernel::CurveGrid:
      code = {curve_grid_comp, curve_grid_comp_f64, curve_grid_comp_pk, curve_grid_comp_f64_pk};
      label = "curve_grid";
      break;
    case Kernel::TessellateGrid:
      code = {tessellate_grid_comp, tessellate_grid_comp_f64, tessellate_grid_comp_pk, tessellate_grid_comp_f64_pk};
      push = sizeof(tess_layout::TessGridPush);
      label = "tessellate_grid";
      break;
    case Kernel::AdaptiveRates:
      code = {tess_adaptive_rates_comp, tess_adaptive_rates_comp_f64, {}, {}};
      push = sizeof(tess_layout::AdaptivePush);
      label = "tess_adaptive_rates";
      break;
    case Kernel::AdaptiveLayout:
      code = {tess_adaptive_layout_comp, tess_adaptive_layout_comp_f64, {}, {}};
      push = sizeof(tess_layout::AdaptivePush);
      label = "tess_adaptive_layout";
      break;
    case Kernel::AdaptiveMesh:
      code = {tess_adaptive_mesh_comp, tess_adaptive_mesh_comp_f64, {}, {}};
      push = sizeof(tess_layout::AdaptivePush);
      label = "tess_adaptive_mesh";
      break;
    case Kernel::AlphaEBVertices:
      code = {alpha_eb_vertices_comp, alpha_eb_vertices_comp_f64, {}, {}};
      push = sizeof(layout::VertexPush);
      label = "alpha_eb_vertices";
      break;
    case Kernel::BasisTable:
      code = {basis_table_comp, basis_table_comp_f64, {}, {}};
      push = sizeof(layout::TablePush);
      label = "basis_table";
      break;
    case Kernel::ClosestPoints:
      code = {closest_points_comp, closest_points_comp_f64, {}, {}};
      push = sizeof(projection_layout::ProjectionPush);
      label = "closest_points";
      break;
  }
  vk::ComputePipelineDesc desc;
  desc.spirv = code.pick(d, packedStores_);
  desc.specConstants.push_back({layout::kSpecWorkgroupSize, workgroupSize_});
  for (const auto& [id, value] : spec) desc.specConstants.push_back({id, value});
  desc.pushConstantBytes = push;
  desc.storageBufferCount = kBindingCount;
  desc.label = std::string(label) + (d ? "_f64" : "_f32") + (packedStores_ && code.hasPacked() ? "_pk" : "");
  const vk::ComputePipeline& pipe = ctx_->pipelines().get(desc);
  pipelines_.emplace(key, &pipe);
  return pipe;
}

void KernelSet::dispatch(VkCommandBuffer cmd, uint64_t invocations) const {
  if (invocations == 0) return;
  const uint64_t groups = (invocations + workgroupSize_ - 1) / workgroupSize_;
  const uint64_t maxX = ctx_->limits().maxComputeWorkGroupCount[0];
  const uint64_t x = std::min<uint64_t>(groups, maxX);
  const uint64_t y = (groups + x - 1) / x;
  if (y > ctx_->limits().maxComputeWorkGroupCount[1])
    throw std::length_error("gpu dispatch of " + std::to_string(invocations) + " invocations exceeds the group limits");
  vkCmdDispatch(cmd, static_cast<uint32_t>(x), static_cast<uint32_t>(y), 1);
}

}  // namespace shapespline::gpu
