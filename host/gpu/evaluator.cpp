#include "gpu/evaluator.h"

#include "gpu/kernels.h"
#include "layout.h"
#include "vk/buffer.h"
#include "vk/pipeline.h"
#include "vk/submit.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace shapespline::gpu {
namespace {

constexpr FieldMask kCurveFields = fieldBit(Field::Point) | fieldBit(Field::D1) | fieldBit(Field::D2);
constexpr FieldMask kSurfaceFields = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv) |
                                     fieldBit(Field::Duu) | fieldBit(Field::Duv) | fieldBit(Field::Dvv) |
                                     fieldBit(Field::Normal);

// Bindings a variant does not use still need a valid descriptor (validation), so every binding
// starts at the dummy buffer.
vk::DescriptorSet makeSet(KernelSet& k, const vk::ComputePipeline& pipe) {
  vk::DescriptorSet set = vk::DescriptorSet::create(k.context(), pipe);
  for (uint32_t b = 0; b < kBindingCount; ++b) set.bind(b, k.dummy());
  return set;
}

// A buffer of `reals` REALs rounded up to whole REAL4 so the shaders' REAL4 view covers every value.
vk::Buffer realBuffer(KernelSet& k, size_t reals, vk::MemoryUse use, const char* label) {
  const size_t rs = realSize(k.precision());
  const size_t bytes = std::max<size_t>(((reals + 3) / 4) * 4 * rs, 16 * rs);
  return vk::Buffer::create(k.context(), bytes, vk::kStorageUsage, use, label);
}

// Records the α-EB vertex pass when the model's parameters changed since the last one.
void recordVertexPass(KernelSet& k, GpuModel& m, bool surface, VkCommandBuffer cmd,
                      std::vector<vk::DescriptorSet>& keep) {
  if (!m.alphaEB() || !m.verticesDirty()) return;
  const SpanBasis& bu = m.basisU();
  const SpanBasis& bv = m.basisV();
  const auto& pipe = k.pipeline(Kernel::AlphaEBVertices, {uint32_t(bu.count), uint32_t(bu.degree), uint32_t(bv.count),
                                                          uint32_t(bv.degree), 0u, 1u, 0u, surface ? 1u : 0u});
  keep.push_back(makeSet(k, pipe));
  keep.back().bind(layout::kBindingNet, m.netBuffer())
      .bind(layout::kBindingParams, m.paramBuffer())
      .bind(layout::kBindingVerts, m.vertexBuffer());
  layout::VertexPush pc{m.vertexRows(), m.vertexCols(), m.netCols(), m.alphaOffset()};
  pipe.bind(cmd, keep.back().handle());
  pipe.push(cmd, pc);
  k.dispatch(cmd, uint64_t(pc.rows) * pc.cols);
  vk::computeBarrier(cmd);
}

// Records the basis table of one direction (coefficients at coefOffset) into `table`.
void recordTable(KernelSet& k, const GpuModel& m, const SpanBasis& b, uint32_t coefOffset, uint32_t samples,
                 uint32_t tableOffset, const vk::Buffer& table, VkCommandBuffer cmd,
                 std::vector<vk::DescriptorSet>& keep) {
  const auto& pipe = k.pipeline(Kernel::BasisTable, {uint32_t(b.count), uint32_t(b.degree)});
  keep.push_back(makeSet(k, pipe));
  keep.back().bind(layout::kBindingParams, m.paramBuffer()).bind(layout::kBindingTable, table);
  layout::TablePush pc{samples, 0u, coefOffset, tableOffset};
  pipe.bind(cmd, keep.back().handle());
  pipe.push(cmd, pc);
  k.dispatch(cmd, samples);
}

struct GridJob {
  Kernel kernel;
  bool surface;
  FieldMask allowed;
  layout::EvalPush push;  // model part filled in; chunk part set per chunk
  size_t itemTotal;
};

void runGrid(KernelSet& k, GpuModel& m, const GridJob& job, const GridSpec& grid, FieldMask fields,
             const ChunkConsumer& consumer, size_t maxPlaneBytes) {
  if (fields == 0 || (fields & ~job.allowed) != 0)
    throw std::invalid_argument("evaluateGrid: fields mask " + std::to_string(fields) + " asks for fields this evaluator does not produce");
  if (grid.samplesU < 1 || grid.samplesV < 1 || (!job.surface && grid.samplesV != 1))
    throw std::invalid_argument("evaluateGrid: bad sample counts");
  if (grid.firstItem >= job.itemTotal) throw std::out_of_range("evaluateGrid: firstItem beyond the last item");
  const size_t count = grid.itemCount ? grid.itemCount : job.itemTotal - grid.firstItem;
  if (grid.firstItem + count > job.itemTotal) throw std::out_of_range("evaluateGrid: itemCount beyond the last item");

  const size_t rs = realSize(k.precision());
  const size_t ppi = grid.pointsPerItem();
  const size_t itemPlaneBytes = ppi * 3 * rs;
  const size_t limit = std::min<size_t>(maxPlaneBytes, k.context().limits().maxStorageBufferRange);
  if (itemPlaneBytes + 4 * rs > limit)
    throw std::length_error("evaluateGrid: one item's plane (" + std::to_string(itemPlaneBytes) +
                            " bytes) exceeds the chunk limit " + std::to_string(limit));
  const size_t perChunk = std::min(count, std::max<size_t>(1, (limit - 4 * rs) / itemPlaneBytes));

  const SpanBasis& bu = m.basisU();
  const SpanBasis& bv = m.basisV();
  const uint32_t su = uint32_t(grid.samplesU), sv = uint32_t(grid.samplesV);
  const uint32_t tableV = su * 3u * uint32_t(bu.count);
  const vk::Buffer table =
      realBuffer(k, tableV + (job.surface ? sv * 3u * uint32_t(bv.count) : 0u), vk::MemoryUse::DeviceLocal, "gpu.table");
  std::vector<int> active;
  std::vector<vk::Buffer> planes(kFieldCount);
  for (int f = 0; f < kFieldCount; ++f) {
    if (!(fields & fieldBit(Field(f)))) continue;
    active.push_back(f);
    planes[f] = realBuffer(k, perChunk * ppi * 3, vk::MemoryUse::Readback, "gpu.plane");
  }
  const auto& pipe = k.pipeline(job.kernel, {uint32_t(bu.count), uint32_t(bu.degree), uint32_t(bv.count),
                                             uint32_t(bv.degree), fields, m.alphaEB() ? 1u : 0u, 0u,
                                             job.surface ? 1u : 0u});
  vk::DescriptorSet set = makeSet(k, pipe);
  set.bind(layout::kBindingNet, m.netBuffer())
      .bind(layout::kBindingParams, m.paramBuffer())
      .bind(layout::kBindingVerts, m.vertexBuffer())
      .bind(layout::kBindingTable, table);
  for (int f : active) set.bind(layout::kBindingOutput + f, planes[f]);

  for (size_t first = grid.firstItem; first < grid.firstItem + count; first += perChunk) {
    const size_t n = std::min(perChunk, grid.firstItem + count - first);
    layout::EvalPush pc = job.push;
    pc.firstItem = uint32_t(first);
    pc.itemCount = uint32_t(n);
    pc.samplesU = su;
    pc.samplesV = sv;
    pc.tableOffsetV = tableV;
    std::vector<vk::DescriptorSet> keep;
    {
      vk::OneShot shot(k.context());
      VkCommandBuffer cmd = shot.cmd();
      recordVertexPass(k, m, job.surface, cmd, keep);
      if (first == grid.firstItem) {
        recordTable(k, m, bu, layout::kParamCoefU, su, 0, table, cmd, keep);
        if (job.surface) recordTable(k, m, bv, layout::kParamCoefV, sv, tableV, table, cmd, keep);
        vk::computeBarrier(cmd);
      }
      pipe.bind(cmd, set.handle());
      pipe.push(cmd, pc);
      k.dispatch(cmd, (uint64_t(n) * ppi + layout::kPointsPerInvocation - 1) / layout::kPointsPerInvocation);
      shot.submitAndWait();
    }
    if (m.alphaEB() && m.verticesDirty()) m.markVerticesClean();
    GridChunk chunk;
    chunk.firstItem = first;
    chunk.itemCount = n;
    chunk.pointsPerItem = ppi;
    chunk.precision = k.precision();
    for (int f : active) chunk.planes[f] = planes[f].mapped();
    consumer(chunk);
  }
}

// List mode: samples (host ListSample bytes) -> planes of every allowed field, read back as doubles.
std::vector<std::vector<double>> runList(KernelSet& k, GpuModel& m, Kernel kernel, bool surface, FieldMask fields,
                                         layout::EvalPush push, const std::vector<layout::ListSampleD>& samples,
                                         size_t maxPlaneBytes) {
  std::vector<std::vector<double>> out(kFieldCount);
  const size_t total = samples.size();
  if (total == 0) return out;
  const size_t rs = realSize(k.precision());
  const size_t limit = std::min<size_t>(maxPlaneBytes, k.context().limits().maxStorageBufferRange);
  const size_t perChunk = std::min(total, std::max<size_t>(4, (limit - 4 * rs) / (3 * rs)));
  const SpanBasis& bu = m.basisU();
  const SpanBasis& bv = m.basisV();
  std::vector<int> active;
  std::vector<vk::Buffer> planes(kFieldCount);
  for (int f = 0; f < kFieldCount; ++f) {
    if (!(fields & fieldBit(Field(f)))) continue;
    active.push_back(f);
    planes[f] = realBuffer(k, perChunk * 3, vk::MemoryUse::Readback, "gpu.plane");
    out[f].resize(total * 3);
  }
  // Samples in REAL precision (ListSampleF/D of layout.h).
  std::vector<std::byte> bytes;
  if (k.precision() == Precision::Double) {
    bytes.resize(total * sizeof(layout::ListSampleD));
    std::memcpy(bytes.data(), samples.data(), bytes.size());
  } else {
    std::vector<layout::ListSampleF> f(total);
    for (size_t i = 0; i < total; ++i)
      f[i] = {samples[i].i, samples[i].j, 0, 0, float(samples[i].u), float(samples[i].v), 0.f, 0.f};
    bytes.resize(total * sizeof(layout::ListSampleF));
    std::memcpy(bytes.data(), f.data(), bytes.size());
  }
  vk::Buffer sampleBuf = vk::Buffer::create(k.context(), bytes.size(), vk::kStorageUsage, vk::MemoryUse::Upload, "gpu.samples");
  sampleBuf.upload(bytes);
  const auto& pipe = k.pipeline(kernel, {uint32_t(bu.count), uint32_t(bu.degree), uint32_t(bv.count), uint32_t(bv.degree),
                                         fields, m.alphaEB() ? 1u : 0u, 1u, surface ? 1u : 0u});
  vk::DescriptorSet set = makeSet(k, pipe);
  set.bind(layout::kBindingNet, m.netBuffer())
      .bind(layout::kBindingParams, m.paramBuffer())
      .bind(layout::kBindingVerts, m.vertexBuffer())
      .bind(layout::kBindingSamples, sampleBuf);
  for (int f : active) set.bind(layout::kBindingOutput + f, planes[f]);
  for (size_t first = 0; first < total; first += perChunk) {
    const size_t n = std::min(perChunk, total - first);
    layout::EvalPush pc = push;
    pc.firstItem = uint32_t(first);
    pc.itemCount = uint32_t(n);
    std::vector<vk::DescriptorSet> keep;
    {
      vk::OneShot shot(k.context());
      recordVertexPass(k, m, surface, shot.cmd(), keep);
      pipe.bind(shot.cmd(), set.handle());
      pipe.push(shot.cmd(), pc);
      k.dispatch(shot.cmd(), (n + layout::kPointsPerInvocation - 1) / layout::kPointsPerInvocation);
      shot.submitAndWait();
    }
    if (m.alphaEB() && m.verticesDirty()) m.markVerticesClean();
    for (int f : active) {
      const std::byte* p = planes[f].mapped();
      for (size_t i = 0; i < n * 3; ++i) {
        double v;
        if (rs == 8) {
          std::memcpy(&v, p + 8 * i, 8);
        } else {
          float x;
          std::memcpy(&x, p + 4 * i, 4);
          v = x;
        }
        out[f][first * 3 + i] = v;
      }
    }
  }
  return out;
}

glm::dvec3 at(const std::vector<double>& plane, size_t i) {
  return plane.empty() ? glm::dvec3(0.0) : glm::dvec3(plane[3 * i], plane[3 * i + 1], plane[3 * i + 2]);
}

layout::EvalPush curvePush(const GpuCurve& c) {
  layout::EvalPush p{};
  p.itemsV = 1;
  p.samplesU = 1;
  p.samplesV = 1;
  p.firstSpanU = uint32_t(c.spans().first);
  p.netCols = 1;
  p.netOffsetU = c.netOffset();
  p.rows = c.vertexRows();
  p.cols = 1;
  p.alphaOffset = c.alphaOffset();
  p.invHOffset = c.invHOffset();
  return p;
}

layout::EvalPush surfacePush(const GpuSurface& s) {
  layout::EvalPush p{};
  p.itemsV = uint32_t(s.patchesV());
  p.samplesU = 1;
  p.samplesV = 1;
  p.firstSpanU = uint32_t(s.patches().u.first);
  p.firstSpanV = uint32_t(s.patches().v.first);
  p.netCols = s.netCols();
  p.netOffsetU = s.netOffsetU();
  p.netOffsetV = s.netOffsetV();
  p.rows = s.vertexRows();
  p.cols = s.vertexCols();
  p.alphaOffset = s.alphaOffset();
  p.invHOffset = layout::kNoOffset;
  return p;
}

void checkPrecision(const KernelSet& k, const GpuModel& m) {
  if (k.precision() != m.precision())
    throw std::invalid_argument("evaluator and model were created with different precisions");
}

}  // namespace

// ---- CurveEvaluator -----------------------------------------------------------------------------

CurveEvaluator::CurveEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision, EvaluatorOptions options)
    : kernels_(std::make_unique<KernelSet>(std::move(ctx), precision, options.workgroupSize)), options_(options) {}
CurveEvaluator::~CurveEvaluator() = default;
Precision CurveEvaluator::precision() const { return kernels_->precision(); }

void CurveEvaluator::evaluateGrid(GpuCurve& curve, const GridSpec& grid, FieldMask fields,
                                  const ChunkConsumer& consumer) {
  checkPrecision(*kernels_, curve);
  GridJob job{Kernel::CurveEval, false, kCurveFields, curvePush(curve), curve.spanCount()};
  runGrid(*kernels_, curve, job, grid, fields, consumer, options_.maxPlaneBytes);
}

std::vector<CurvePoint> CurveEvaluator::evaluateList(GpuCurve& curve, std::span<const CurveSample> samples) {
  checkPrecision(*kernels_, curve);
  std::vector<layout::ListSampleD> s(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const CurveSample& x = samples[i];
    if (x.span < curve.spans().first || x.span > curve.spans().last || !(x.t >= 0.0 && x.t <= 1.0))
      throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " (span " + std::to_string(x.span) +
                              ", t " + std::to_string(x.t) + ") is outside the curve");
    s[i] = {uint32_t(x.span), 0u, 0u, 0u, x.t, 0.0, 0.0, 0.0};
  }
  const auto planes = runList(*kernels_, curve, Kernel::CurveEval, false, kCurveFields, curvePush(curve), s,
                              options_.maxPlaneBytes);
  std::vector<CurvePoint> out(samples.size());
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].point = at(planes[int(Field::Point)], i);
    out[i].d1 = at(planes[int(Field::D1)], i);
    out[i].d2 = at(planes[int(Field::D2)], i);
  }
  return out;
}

// ---- SurfaceEvaluator ---------------------------------------------------------------------------

SurfaceEvaluator::SurfaceEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision, EvaluatorOptions options)
    : kernels_(std::make_unique<KernelSet>(std::move(ctx), precision, options.workgroupSize)), options_(options) {}
SurfaceEvaluator::~SurfaceEvaluator() = default;
Precision SurfaceEvaluator::precision() const { return kernels_->precision(); }

void SurfaceEvaluator::evaluateGrid(GpuSurface& surface, const GridSpec& grid, FieldMask fields,
                                    const ChunkConsumer& consumer) {
  checkPrecision(*kernels_, surface);
  GridJob job{Kernel::SurfaceEval, true, kSurfaceFields, surfacePush(surface), surface.patchCount()};
  runGrid(*kernels_, surface, job, grid, fields, consumer, options_.maxPlaneBytes);
}

std::vector<SurfacePoint> SurfaceEvaluator::evaluateList(GpuSurface& surface, std::span<const SurfaceSample> samples) {
  checkPrecision(*kernels_, surface);
  const PatchRange r = surface.patches();
  std::vector<layout::ListSampleD> s(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const SurfaceSample& x = samples[i];
    if (x.i < r.u.first || x.i > r.u.last || x.j < r.v.first || x.j > r.v.last || !(x.u >= 0.0 && x.u <= 1.0) ||
        !(x.v >= 0.0 && x.v <= 1.0))
      throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " (patch " + std::to_string(x.i) + "," +
                              std::to_string(x.j) + ") is outside the surface");
    s[i] = {uint32_t(x.i), uint32_t(x.j), 0u, 0u, x.u, x.v, 0.0, 0.0};
  }
  const auto planes = runList(*kernels_, surface, Kernel::SurfaceEval, true, kSurfaceFields, surfacePush(surface), s,
                              options_.maxPlaneBytes);
  std::vector<SurfacePoint> out(samples.size());
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].point = at(planes[int(Field::Point)], i);
    out[i].du = at(planes[int(Field::Du)], i);
    out[i].dv = at(planes[int(Field::Dv)], i);
    out[i].duu = at(planes[int(Field::Duu)], i);
    out[i].duv = at(planes[int(Field::Duv)], i);
    out[i].dvv = at(planes[int(Field::Dvv)], i);
    out[i].normal = at(planes[int(Field::Normal)], i);
  }
  return out;
}

// ---- BasisTableEvaluator ------------------------------------------------------------------------

BasisTableEvaluator::BasisTableEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision,
                                         EvaluatorOptions options)
    : kernels_(std::make_unique<KernelSet>(std::move(ctx), precision, options.workgroupSize)) {}
BasisTableEvaluator::~BasisTableEvaluator() = default;

std::vector<double> BasisTableEvaluator::evaluate(const SpanBasis& basis, int sampleCount) {
  return run(basis, sampleCount, {});
}

std::vector<double> BasisTableEvaluator::evaluateAt(const SpanBasis& basis, std::span<const double> t) {
  if (t.empty()) return {};
  return run(basis, static_cast<int>(t.size()), t);
}

std::vector<double> BasisTableEvaluator::run(const SpanBasis& basis, int sampleCount, std::span<const double> list) {
  if (sampleCount < 1) throw std::invalid_argument("BasisTableEvaluator: sampleCount must be >= 1");
  KernelSet& k = *kernels_;
  vk::Buffer sampleBuf;
  if (!list.empty()) {
    std::vector<std::byte> bytes;
    if (k.precision() == Precision::Double) {
      std::vector<layout::ListSampleD> s(list.size());
      for (size_t i = 0; i < list.size(); ++i) s[i] = {0, 0, 0, 0, list[i], 0.0, 0.0, 0.0};
      bytes.resize(s.size() * sizeof(s[0]));
      std::memcpy(bytes.data(), s.data(), bytes.size());
    } else {
      std::vector<layout::ListSampleF> s(list.size());
      for (size_t i = 0; i < list.size(); ++i) s[i] = {0, 0, 0, 0, float(list[i]), 0.f, 0.f, 0.f};
      bytes.resize(s.size() * sizeof(s[0]));
      std::memcpy(bytes.data(), s.data(), bytes.size());
    }
    sampleBuf = vk::Buffer::create(k.context(), bytes.size(), vk::kStorageUsage, vk::MemoryUse::Upload, "gpu.samples");
    sampleBuf.upload(bytes);
  }
  const size_t rs = realSize(k.precision());
  std::vector<double> coef(layout::kParamHeader, 0.0);
  for (int r = 0; r < basis.count; ++r)
    for (int d = 0; d <= basis.degree; ++d) coef[r * layout::kCoefStride + d] = basis.coef[r][d];
  vk::Buffer params = realBuffer(k, coef.size(), vk::MemoryUse::Upload, "gpu.table_params");
  params.upload(toReal(coef, k.precision()));
  const size_t n = size_t(sampleCount) * 3 * basis.count;
  vk::Buffer table = realBuffer(k, n, vk::MemoryUse::Readback, "gpu.table");
  const auto& pipe = k.pipeline(Kernel::BasisTable, {uint32_t(basis.count), uint32_t(basis.degree)});
  vk::DescriptorSet set = makeSet(k, pipe);
  set.bind(layout::kBindingParams, params).bind(layout::kBindingTable, table);
  if (!list.empty()) set.bind(layout::kBindingSamples, sampleBuf);
  layout::TablePush pc{uint32_t(sampleCount), list.empty() ? 0u : 1u, layout::kParamCoefU, 0u};
  vk::runOneShot(k.context(), [&](VkCommandBuffer cmd) {
    pipe.bind(cmd, set.handle());
    pipe.push(cmd, pc);
    k.dispatch(cmd, uint64_t(sampleCount));
  });
  std::vector<double> out(n);
  const std::byte* p = table.mapped();
  std::vector<std::byte> tmp;
  if (!p) {
    tmp.resize(table.size());
    table.download(tmp);
    p = tmp.data();
  }
  for (size_t i = 0; i < n; ++i) {
    if (rs == 8) {
      std::memcpy(&out[i], p + 8 * i, 8);
    } else {
      float x;
      std::memcpy(&x, p + 4 * i, 4);
      out[i] = x;
    }
  }
  return out;
}

}  // namespace shapespline::gpu
