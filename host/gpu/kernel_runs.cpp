#include <shapespline/gpu/kernel_runs.h>

#include <shapespline/gpu/chunk_plan.h>
#include <shapespline/gpu/list_packing.h>
#include <shapespline/gpu/plane_pool.h>
#include <shapespline/vk/submit.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace shapespline::gpu {
namespace {

// Knot-vector kernels take the list flag as a push constant (grid and list share a pipeline).
constexpr uint32_t kNoListMode = ~0u;

// Constants of the evaluation kernels: bases, output fields, α-EB flag and list flag.
SpecValues evalSpec(const GpuModel& m, FieldMask fields, uint32_t listMode) {
  SpecValues spec = basisSpec(m.basisU(), m.basisV());
  spec[layout::kSpecOutputMask] = fields;
  spec[layout::kSpecAlphaEB] = m.alphaEB() ? 1u : 0u;
  if (m.knotVector()) {
    spec[layout::kSpecRational] = m.rational() ? 1u : 0u;
    spec[layout::kSpecKnotPatches] = 1u;  // read by the patch kernels (knotPatchGridJob) only
  }
  if (listMode != kNoListMode) spec[layout::kSpecListMode] = listMode;
  return spec;
}

// Records the α-EB vertex pass when the model's parameters changed since the last one.
void recordVertexPass(KernelSet& k, GpuModel& m, bool surface, VkCommandBuffer cmd,
                      std::vector<vk::DescriptorSet>& keep) {
  if (!m.alphaEB() || !m.verticesDirty()) return;
  keep.emplace_back();
  recordAlphaEBVertices(k, m, surface, cmd, keep.back());
}

}  // namespace


// Bindings a variant does not use still need a valid descriptor (validation), so every binding
// starts at the dummy buffer.
vk::DescriptorSet makeSet(KernelSet& k, const vk::ComputePipeline& pipe) {
  vk::DescriptorSet set = vk::DescriptorSet::create(k.context(), pipe);
  for (uint32_t b = 0; b < kBindingCount; ++b) set.bind(b, k.dummy());
  return set;
}

void recordAlphaEBVertices(KernelSet& k, const GpuModel& m, bool surface, VkCommandBuffer cmd, vk::DescriptorSet& set) {
  const auto& pipe = k.pipeline(Kernel::AlphaEBVertices, {{layout::kSpecSurface, surface ? 1u : 0u}});
  if (!set.handle()) {
    set = makeSet(k, pipe);
    set.bind(layout::kBindingNet, m.netBuffer())
        .bind(layout::kBindingParams, m.paramBuffer())
        .bind(layout::kBindingVerts, m.vertexBuffer());
  }
  const layout::VertexPush pc{m.vertexRows(), m.vertexCols(), m.netCols(), m.alphaOffset()};
  pipe.bind(cmd, set.handle());
  pipe.push(cmd, pc);
  k.dispatch(cmd, uint64_t(pc.rows) * pc.cols);
  vk::computeBarrier(cmd);
}

// A buffer of `reals` REALs rounded up to whole REAL4 so the shaders' REAL4 view covers every value.
size_t realBufferBytes(const KernelSet& k, size_t reals) {
  const size_t rs = realSize(k.precision());
  return std::max<size_t>(((reals + 3) / 4) * 4 * rs, 16 * rs);
}
vk::Buffer realBuffer(KernelSet& k, size_t reals, vk::MemoryUse use, const char* label) {
  return vk::Buffer::create(k.context(), realBufferBytes(k, reals), vk::kStorageUsage, use, label);
}

SpecValues basisTableSpec(const SpanBasis& b) {
  return {{layout::kSpecBasisCountU, uint32_t(b.count)}, {layout::kSpecPolyDegreeU, uint32_t(b.degree)}};
}

void recordTable(KernelSet& k, const GpuModel& m, const SpanBasis& b, uint32_t coefOffset, uint32_t samples,
                 uint32_t tableOffset, const vk::Buffer& table, VkCommandBuffer cmd,
                 std::vector<vk::DescriptorSet>& keep) {
  const auto& pipe = k.pipeline(Kernel::BasisTable, basisTableSpec(b));
  keep.push_back(makeSet(k, pipe));
  keep.back().bind(layout::kBindingParams, m.paramBuffer()).bind(layout::kBindingTable, table);
  layout::TablePush pc{samples, 0u, coefOffset, tableOffset};
  pipe.bind(cmd, keep.back().handle());
  pipe.push(cmd, pc);
  k.dispatch(cmd, samples);
}

void checkPrecision(const KernelSet& k, const GpuModel& m) {
  if (k.precision() != m.precision())
    throw std::invalid_argument("evaluator and model were created with different precisions");
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


layout::KnotEvalPush knotPush(const GpuModel& m, uint32_t itemsV, uint32_t netCols) {
  layout::KnotEvalPush p{};
  p.itemsV = itemsV;
  p.samplesU = 1;
  p.samplesV = 1;
  p.netCols = netCols;
  p.knotOffsetU = m.knotOffsetU();
  p.knotOffsetV = m.knotOffsetV();
  p.intervalOffsetU = m.intervalOffsetU();
  p.intervalOffsetV = m.intervalOffsetV();
  return p;
}

layout::EvalPush surfacePush(const GpuSurface& s) {
  layout::EvalPush p{};
  p.itemsV = uint32_t(s.gridItemsV());
  p.samplesU = 1;
  p.samplesV = 1;
  setSurfaceNetFields(p, s);
  p.invHOffset = layout::kNoOffset;
  return p;
}

namespace {

// Samples per invocation of bspline_surface_grid.comp: runs that divide a row share the net's u
// contraction; 8 at most (the contracted rows stay in registers).
uint32_t knotRunLength(uint32_t samplesV) {
  for (uint32_t run : {8u, 4u, 2u})
    if (samplesV % run == 0) return run;
  return 1u;
}

size_t knotTableLimit(const KernelSet& k) {
  constexpr size_t kMaxTableBytes = size_t{64} << 20;
  return std::min<size_t>(kMaxTableBytes, k.context().limits().maxStorageBufferRange) / realSize(k.precision());
}

}  // namespace

GridJob<layout::KnotEvalPush> knotGridJob(const KernelSet& k, const GpuCurve& c, const GridSpec& grid,
                                          std::optional<KnotGridTable>& table) {
  table = knotGridTable(c.curve(), grid.samplesU, knotTableLimit(k));
  GridJob<layout::KnotEvalPush> job{table ? Kernel::BSplineCurveGrid : Kernel::BSplineCurveEval, false, true,
                                    kCurveFields, knotPush(c, 1, 1), c.gridItemCount()};
  job.knotTable = table ? &*table : nullptr;
  return job;
}

GridJob<layout::KnotEvalPush> knotGridJob(const KernelSet& k, const GpuSurface& s, const GridSpec& grid,
                                          std::optional<KnotGridTable>& table) {
  table = knotGridTable(s.surface(), grid.samplesU, grid.samplesV, knotTableLimit(k));
  GridJob<layout::KnotEvalPush> job{table ? Kernel::BSplineSurfaceGrid : Kernel::BSplineSurfaceEval, true, true,
                                    kSurfaceFields, knotPush(s, uint32_t(s.gridItemsV()), s.netCols()),
                                    s.gridItemCount()};
  job.knotTable = table ? &*table : nullptr;
  if (table) job.push.tableOffsetV = table->offsetV;
  return job;
}

namespace {

// Whether every interior knot of one direction leaves the surface C^`smooth` (order - 1 -
// multiplicity >= smooth) and every non-empty interval is wide enough for 1/h^2 in `precision`.
bool smoothKnots(int order, const std::vector<double>& knots, int count, int smooth, Precision precision) {
  const double minWidth = precision == Precision::Double ? 1e-100 : 1e-12;
  for (int j = order - 1; j < count; ++j) {
    const double h = knots[j + 1] - knots[j];
    if (h > 0.0 && h < minWidth) return false;
  }
  for (int j = order; j < count;) {  // the interior knots t_order .. t_{count-1}
    int e = j;
    while (e + 1 < count && knots[e + 1] == knots[j]) ++e;
    if (order - 1 - (e - j + 1) < smooth) return false;
    j = e + 1;
  }
  return true;
}

}  // namespace

std::optional<GridJob<layout::EvalPush>> knotPatchGridJob(const GpuSurface& s, const GridSpec& grid, FieldMask fields) {
  if (!s.knotVector() || grid.samplesV % 4 != 0) return std::nullopt;
  const FieldMask second = fieldBit(Field::Duu) | fieldBit(Field::Duv) | fieldBit(Field::Dvv);
  const int smooth = (fields & second) ? 2 : (fields & ~fieldBit(Field::Point)) ? 1 : 0;
  const BSplineSurfaceData& d = s.surface().knotData();
  if (!smoothKnots(d.orderU, d.knotsU, d.rows, smooth, s.precision()) ||
      !smoothKnots(d.orderV, d.knotsV, d.cols, smooth, s.precision()))
    return std::nullopt;
  // knotVector: no basis table (the kernel takes the intervals' coefficients from PARAMS).
  return GridJob<layout::EvalPush>{Kernel::SurfaceGrid, true, true, kSurfaceFields, surfacePush(s), s.gridItemCount()};
}

// How a grid job's kernel walks its points, decided once per job: which TABLE it reads (the
// device-built basis table of the uniform families, a knot grid's host-built one, or none for
// bspline_*_eval.comp), how many samples each invocation takes, whether that run is a
// specialisation constant, and how many rows a chunk's row range must hold whole. (Not in an
// anonymous namespace: runGrid, a template of this module's interface, captures it.)
struct KernelShape {
  enum class Table { Basis, Knot, None } table = Table::None;
  bool gridKernel = false;       // surface_grid.comp / curve_grid.comp
  uint32_t run = 0;              // samples per invocation of a grid or knot-grid kernel
  bool runIsSpecialised = false;  // spec[kSpecRunLength] = run
  uint64_t perInvocation = 0;    // points one invocation takes
  size_t granule = 1;            // rows a chunk's row range holds whole
};

template <class Push>
KernelShape kernelShape(const GridJob<Push>& job, const GridSpec& grid, FieldMask fields) {
  KernelShape shape;
  const bool knotGrid = job.knotTable != nullptr;
  shape.table = !job.knotVector ? KernelShape::Table::Basis : knotGrid ? KernelShape::Table::Knot : KernelShape::Table::None;
  shape.gridKernel = job.kernel == Kernel::SurfaceGrid || job.kernel == Kernel::CurveGrid;
  const uint32_t su = uint32_t(grid.samplesU), sv = uint32_t(grid.samplesV);
  shape.run = shape.gridKernel ? gridRunLength(grid, fields, job.surface)
              : knotGrid       ? (job.surface ? knotRunLength(sv) : 1u)
                               : 0u;
  shape.runIsSpecialised = shape.gridKernel || (knotGrid && job.surface);
  // Grid kernels: `run` samples per invocation (whole rows or spans, or runs dividing a row; the
  // last invocation of a curve chunk may hold fewer spans).
  shape.perInvocation = shape.gridKernel || knotGrid ? shape.run : layout::kPointsPerInvocation;
  // Row ranges hold whole invocations of the grid kernel (rows of a patch, a run of a span).
  shape.granule = !shape.gridKernel ? 1u
                  : job.surface     ? std::max<size_t>(1, shape.run / sv)
                  : shape.run < su  ? shape.run
                                    : su;
  return shape;
}

template <class Push>
void runGrid(KernelSet& k, PlanePool& pool, GpuModel& m, const GridJob<Push>& job, const GridSpec& grid,
             FieldMask fields, const ChunkConsumer& consumer, size_t maxPlaneBytes) {
  if (fields == 0 || (fields & ~job.allowed) != 0)
    throw std::invalid_argument("evaluateGrid: fields mask " + std::to_string(fields) + " asks for fields this evaluator does not produce");
  if (grid.samplesU < 1 || grid.samplesV < 1 || (!job.surface && grid.samplesV != 1))
    throw std::invalid_argument("evaluateGrid: bad sample counts");
  if (grid.firstItem >= job.itemTotal) throw std::out_of_range("evaluateGrid: firstItem beyond the last item");
  const size_t count = grid.itemCount ? grid.itemCount : job.itemTotal - grid.firstItem;
  if (grid.firstItem + count > job.itemTotal) throw std::out_of_range("evaluateGrid: itemCount beyond the last item");

  const SpanBasis& bu = m.basisU();
  const SpanBasis& bv = m.basisV();
  const uint32_t su = uint32_t(grid.samplesU), sv = uint32_t(grid.samplesV);
  const uint32_t tableV = su * 3u * uint32_t(bu.count);
  const KernelShape shape = kernelShape(job, grid, fields);
  vk::Buffer table;
  if (shape.table == KernelShape::Table::Basis) {
    table = realBuffer(k, tableV + (job.surface ? sv * 3u * uint32_t(bv.count) : 0u), vk::MemoryUse::DeviceLocal,
                       "gpu.table");
  } else if (shape.table == KernelShape::Table::Knot) {
    table = realBuffer(k, job.knotTable->values.size(), vk::MemoryUse::DeviceLocal, "gpu.knot_table");
    table.upload(toReal(job.knotTable->values, k.precision()));
  }
  std::vector<int> active;
  for (int f = 0; f < kFieldCount; ++f)
    if (fields & fieldBit(Field(f))) active.push_back(f);
  SpecValues spec = evalSpec(m, fields, job.knotVector ? kNoListMode : 0u);
  if (shape.runIsSpecialised) spec[layout::kSpecRunLength] = shape.run;
  const auto& pipe = k.pipeline(job.kernel, spec);

  const size_t hardLimit = k.context().limits().maxStorageBufferRange;
  const ChunkPlan plan = planGridChunks(grid, count, job.surface, shape.granule, realSize(k.precision()), maxPlaneBytes,
                                        hardLimit, k.precision());

  std::vector<vk::DescriptorSet> keep;  // vertex pass / tables
  constexpr uint32_t kSlots = PlanePool::kSlots;
  const uint32_t slots = plan.chunkCount > 1 ? kSlots : 1;
  const VkDeviceSize planeBytes = realBufferBytes(k, plan.chunkPoints * 3);
  std::array<std::array<const vk::Buffer*, kFieldCount>, kSlots> planes{};
  vk::DescriptorSet sets[kSlots];
  for (uint32_t s = 0; s < slots; ++s) {
    for (int f : active) planes[s][f] = &pool.acquire(k.context(), int(s), f, planeBytes);
    sets[s] = makeSet(k, pipe);
    sets[s].bind(layout::kBindingNet, m.netBuffer())
        .bind(layout::kBindingParams, m.paramBuffer())
        .bind(layout::kBindingVerts, m.vertexBuffer());
    if (shape.table != KernelShape::Table::None) sets[s].bind(layout::kBindingTable, table);
    for (int f : active) sets[s].bind(layout::kBindingOutput + f, *planes[s][f]);
  }
  vk::SubmitRing ring(k.context(), slots);  // declared last: its destructor waits before anything it uses goes

  auto record = [&](size_t chunk) {
    const uint32_t slot = uint32_t(chunk % slots);
    const GridChunk c = plan.chunk(chunk);
    Push pc = job.push;
    pc.firstItem = uint32_t(c.firstItem);
    pc.itemCount = uint32_t(c.itemCount);
    pc.firstRow = uint32_t(c.firstRow);
    pc.rowCount = uint32_t(c.partial() ? c.rowCount : c.itemCount * plan.rowsPerItem);
    pc.samplesU = su;
    pc.samplesV = sv;
    if constexpr (std::is_same_v<Push, layout::EvalPush>) pc.tableOffsetV = tableV;
    VkCommandBuffer cmd = ring.begin(slot);
    if (chunk == 0) {
      // Later chunks are later in submission order on the same queue, so this barrier orders the
      // vertex pass / tables before their dispatches too.
      recordVertexPass(k, m, job.surface, cmd, keep);
      if (shape.table == KernelShape::Table::Basis) {
        recordTable(k, m, bu, layout::kParamCoefU, su, 0, table, cmd, keep);
        if (job.surface) recordTable(k, m, bv, layout::kParamCoefV, sv, tableV, table, cmd, keep);
      }
      vk::computeBarrier(cmd);
    }
    pipe.bind(cmd, sets[slot].handle());
    pipe.push(cmd, pc);
    k.dispatch(cmd, (uint64_t(c.pointCount()) + shape.perInvocation - 1) / shape.perInvocation);
    ring.submit(slot);
  };

  record(0);
  for (size_t chunk = 0; chunk < plan.chunkCount; ++chunk) {
    const uint32_t slot = uint32_t(chunk % slots);
    // The other slot's consumer call has returned: it may be overwritten while this one is read.
    if (chunk + 1 < plan.chunkCount) record(chunk + 1);
    ring.wait(slot);
    if (chunk == 0 && m.alphaEB() && m.verticesDirty()) m.markVerticesClean();
    GridChunk out = plan.chunk(chunk);
    for (int f : active) out.planes[f] = planes[slot][f]->mapped();
    consumer(out);
  }
  pool.trim(std::min<size_t>(maxPlaneBytes, hardLimit));
}

template <class Push>
std::vector<std::vector<double>> runList(KernelSet& k, GpuModel& m, Kernel kernel, bool surface, FieldMask fields,
                                         Push push, const std::vector<layout::ListSampleD>& samples,
                                         size_t maxPlaneBytes) {
  std::vector<std::vector<double>> out(kFieldCount);
  const size_t total = samples.size();
  if (total == 0) return out;
  const size_t rs = realSize(k.precision());
  const size_t limit = std::min<size_t>(maxPlaneBytes, k.context().limits().maxStorageBufferRange);
  const size_t perChunk = std::min(total, std::max<size_t>(4, (limit - 4 * rs) / (3 * rs)));
  std::vector<int> active;
  std::vector<vk::Buffer> planes(kFieldCount);
  for (int f = 0; f < kFieldCount; ++f) {
    if (!(fields & fieldBit(Field(f)))) continue;
    active.push_back(f);
    planes[f] = realBuffer(k, perChunk * 3, vk::MemoryUse::Readback, "gpu.plane");
    out[f].resize(total * 3);
  }
  const std::vector<std::byte> bytes = packListSamples(samples, k.precision());
  vk::Buffer sampleBuf = vk::Buffer::create(k.context(), bytes.size(), vk::kStorageUsage, vk::MemoryUse::Upload, "gpu.samples");
  sampleBuf.upload(bytes);
  // Knot-vector kernels read the list flag from the push constants, so grid and list share a pipeline.
  constexpr bool kKnot = std::is_same_v<Push, layout::KnotEvalPush>;
  if constexpr (kKnot) push.listMode = 1u;
  const auto& pipe = k.pipeline(kernel, evalSpec(m, fields, kKnot ? kNoListMode : 1u));
  vk::DescriptorSet set = makeSet(k, pipe);
  set.bind(layout::kBindingNet, m.netBuffer())
      .bind(layout::kBindingParams, m.paramBuffer())
      .bind(layout::kBindingVerts, m.vertexBuffer())
      .bind(layout::kBindingSamples, sampleBuf);
  for (int f : active) set.bind(layout::kBindingOutput + f, planes[f]);
  for (size_t first = 0; first < total; first += perChunk) {
    const size_t n = std::min(perChunk, total - first);
    Push pc = push;
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
    for (int f : active) readReals(planes[f].mapped(), k.precision(), n * 3, out[f].data() + first * 3);
  }
  return out;
}

template void runGrid<layout::EvalPush>(KernelSet&, PlanePool&, GpuModel&, const GridJob<layout::EvalPush>&,
                                        const GridSpec&, FieldMask, const ChunkConsumer&, size_t);
template void runGrid<layout::KnotEvalPush>(KernelSet&, PlanePool&, GpuModel&, const GridJob<layout::KnotEvalPush>&,
                                            const GridSpec&, FieldMask, const ChunkConsumer&, size_t);
template std::vector<std::vector<double>> runList<layout::EvalPush>(KernelSet&, GpuModel&, Kernel, bool, FieldMask,
                                                                    layout::EvalPush,
                                                                    const std::vector<layout::ListSampleD>&, size_t);
template std::vector<std::vector<double>> runList<layout::KnotEvalPush>(KernelSet&, GpuModel&, Kernel, bool, FieldMask,
                                                                        layout::KnotEvalPush,
                                                                        const std::vector<layout::ListSampleD>&, size_t);

}  // namespace shapespline::gpu
