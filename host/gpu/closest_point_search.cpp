#include <shapespline/gpu/closest_point_search.h>

#include <shapespline/gpu/kernel_runs.h>
#include <shapespline/gpu/kernels.h>
#include <shapespline/gpu/list_packing.h>
#include <shapespline/shaders/layout.h>
#include <shapespline/vk/submit.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace shapespline::gpu {

namespace pl = projection_layout;

namespace {

// A buffer holding `bytes` for the kernel to read, uploaded; std::length_error naming
// `what` past the device's storage-buffer range.
vk::Buffer uploaded(KernelSet& k, std::span<const std::byte> bytes, const char* what) {
  const uint64_t limit = k.context().limits().maxStorageBufferRange;
  if (bytes.size() > limit)
    throw std::length_error(std::string("closest points on the GPU: the tree's ") + what + " take " +
                            std::to_string(bytes.size()) + " bytes, over the device's storage-buffer range of " +
                            std::to_string(limit));
  // Whole REAL4s of fp64, as realBufferBytes rounds every evaluator buffer.
  const size_t size = std::max<size_t>((bytes.size() + 31) / 32 * 32, 32);
  vk::Buffer b = vk::Buffer::create(k.context(), size, vk::kStorageUsage, vk::MemoryUse::DeviceLocal, what);
  if (!bytes.empty()) b.upload(bytes);
  return b;
}

// llvmpipe ends every loop of a workgroup once the workgroup has run 65,535 loop iterations in all
// (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS, one counter per workgroup), and the results are then
// wrong. There a workgroup is one SIMD batch of 8 queries, each with an eighth of that, less a
// margin; a query past it is redone on the host. Other devices have no such limit.
constexpr uint32_t kLlvmpipeLoopLimit = 65535;
constexpr uint32_t kLlvmpipeWorkgroup = 8;

bool countsLoops(const vk::Context& ctx) { return ctx.deviceName().find("llvmpipe") != std::string::npos; }

}  // namespace

ClosestPointSearch::ClosestPointSearch(std::shared_ptr<vk::Context> ctx, Precision precision,
                                       const ProjectionTables& tables, EvaluatorOptions options)
    : kernels_(std::make_unique<KernelSet>(ctx, precision, countsLoops(*ctx) ? kLlvmpipeWorkgroup : options.workgroupSize,
                                           false)),
      loopBudget_(countsLoops(*ctx) ? kLlvmpipeLoopLimit / kLlvmpipeWorkgroup - 512 : UINT32_MAX),
      degreeU_(tables.degreeU),
      degreeV_(tables.degreeV),
      offsets_(tables.offsets) {
  KernelSet& k = *kernels_;
  coefficients_ = uploaded(k, toReal4(tables.coefficients, precision), "patch coefficients");
  reals_ = uploaded(k, toReal(tables.reals, precision), "cells and boxes");
  ints_ = uploaded(k, std::as_bytes(std::span(tables.ints)), "indices");
}

ClosestPointSearch::~ClosestPointSearch() = default;

void ClosestPointSearch::search(std::span<const glm::dvec3> queries, std::span<ProjectionHit> hits) {
  if (hits.size() != queries.size()) throw std::invalid_argument("ClosestPointSearch::search: one hit per query");
  if (queries.empty()) return;
  KernelSet& k = *kernels_;
  const size_t chunk = std::min(queries.size(), kQueriesPerDispatch);
  vk::Buffer queryBuf = realBuffer(k, chunk * 4, vk::MemoryUse::Upload, "projection.queries");
  vk::Buffer hitReals = realBuffer(k, chunk * pl::kProjHitReals, vk::MemoryUse::Readback, "projection.hit_reals");
  vk::Buffer hitInts = vk::Buffer::create(k.context(), chunk * pl::kProjHitInts * sizeof(uint32_t), vk::kStorageUsage,
                                          vk::MemoryUse::Readback, "projection.hit_ints");
  const auto& pipe = k.pipeline(Kernel::ClosestPoints, {{layout::kSpecPolyDegreeU, uint32_t(degreeU_)},
                                                        {layout::kSpecPolyDegreeV, uint32_t(degreeV_)}});
  vk::DescriptorSet set = makeSet(k, pipe);
  set.bind(pl::kProjBindingCoefficients, coefficients_)
      .bind(pl::kProjBindingReals, reals_)
      .bind(pl::kProjBindingInts, ints_)
      .bind(pl::kProjBindingQueries, queryBuf)
      .bind(pl::kProjBindingHitReals, hitReals)
      .bind(pl::kProjBindingHitInts, hitInts);
  std::vector<double> reals(chunk * pl::kProjHitReals);
  std::vector<uint32_t> ints(chunk * pl::kProjHitInts);
  std::vector<std::byte> bytes;
  for (size_t first = 0; first < queries.size(); first += chunk) {
    const size_t n = std::min(chunk, queries.size() - first);
    queryBuf.upload(toReal4(queries.subspan(first, n), k.precision()));
    pl::ProjectionPush push = offsets_;
    push.queryCount = static_cast<uint32_t>(n);
    push.loopBudget = loopBudget_;
    vk::runOneShot(k.context(), [&](VkCommandBuffer cmd) {
      pipe.bind(cmd, set.handle());
      pipe.push(cmd, push);
      k.dispatch(cmd, n);
      vk::computeBarrier(cmd);
    });
    bytes.resize(n * pl::kProjHitReals * realSize(k.precision()));
    hitReals.download(bytes);
    readReals(bytes.data(), k.precision(), n * pl::kProjHitReals, reals.data());
    hitInts.downloadSpan(std::span(ints.data(), n * pl::kProjHitInts));
    for (size_t q = 0; q < n; ++q) {
      const double* r = &reals[q * pl::kProjHitReals];
      const uint32_t* i = &ints[q * pl::kProjHitInts];
      ProjectionHit& h = hits[first + q];
      h.d2 = r[0];
      h.point = {r[1], r[2], r[3]};
      h.uv = {r[4], r[5]};
      h.local = {r[6], r[7]};
      h.du = {r[8], r[9], r[10]};
      h.dv = {r[11], r[12], r[13]};
      h.face = i[0], h.i = i[1], h.j = i[2], h.flags = i[3];
    }
  }
}

}  // namespace shapespline::gpu
