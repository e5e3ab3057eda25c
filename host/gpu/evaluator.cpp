#include <shapespline/gpu/evaluator.h>
#include <shapespline/vk/fault.h>

#include <shapespline/core/bspline.h>
#include <shapespline/gpu/kernels.h>
#include <shapespline/gpu/plane_pool.h>
#include <shapespline/shaders/layout.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/error.h>
#include <shapespline/vk/pipeline.h>
#include <shapespline/vk/submit.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

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
size_t realBufferBytes(KernelSet& k, size_t reals) {
  const size_t rs = realSize(k.precision());
  return std::max<size_t>(((reals + 3) / 4) * 4 * rs, 16 * rs);
}
vk::Buffer realBuffer(KernelSet& k, size_t reals, vk::MemoryUse use, const char* label) {
  return vk::Buffer::create(k.context(), realBufferBytes(k, reals), vk::kStorageUsage, use, label);
}

SpecValues basisTableSpec(const SpanBasis& b) {
  return {{layout::kSpecBasisCountU, uint32_t(b.count)}, {layout::kSpecPolyDegreeU, uint32_t(b.degree)}};
}

// Knot-vector kernels take the list flag as a push constant (grid and list share a pipeline).
constexpr uint32_t kNoListMode = ~0u;

// Constants of the evaluation kernels: bases, output fields, α-EB flag and list flag.
SpecValues evalSpec(const GpuModel& m, FieldMask fields, uint32_t listMode) {
  SpecValues spec = basisSpec(m.basisU(), m.basisV());
  spec[layout::kSpecOutputMask] = fields;
  spec[layout::kSpecAlphaEB] = m.alphaEB() ? 1u : 0u;
  if (listMode != kNoListMode) spec[layout::kSpecListMode] = listMode;
  return spec;
}

// Records the α-EB vertex pass when the model's parameters changed since the last one.
void recordVertexPass(KernelSet& k, GpuModel& m, bool surface, VkCommandBuffer cmd,
                      std::vector<vk::DescriptorSet>& keep) {
  if (!m.alphaEB() || !m.verticesDirty()) return;
  const auto& pipe = k.pipeline(Kernel::AlphaEBVertices, {{layout::kSpecSurface, surface ? 1u : 0u}});
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
  const auto& pipe = k.pipeline(Kernel::BasisTable, basisTableSpec(b));
  keep.push_back(makeSet(k, pipe));
  keep.back().bind(layout::kBindingParams, m.paramBuffer()).bind(layout::kBindingTable, table);
  layout::TablePush pc{samples, 0u, coefOffset, tableOffset};
  pipe.bind(cmd, keep.back().handle());
  pipe.push(cmd, pc);
  k.dispatch(cmd, samples);
}

// Two output slots (planes, descriptor set, command buffer, fence each) so that the GPU computes
// chunk k+1 while the consumer reads chunk k. A slot is re-recorded only after its previous chunk
// was handed to the consumer and the consumer returned, so it is never overwritten while read;
// device and host memory stay at 2 x (planes of one chunk) whatever the job size.
class ChunkRing {
 public:
  static constexpr int kSlots = 2;

  explicit ChunkRing(vk::Context& ctx) : ctx_(ctx) {
    VkCommandPoolCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT | VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    info.queueFamilyIndex = ctx.queueFamily();
    VkCommandPool pool = VK_NULL_HANDLE;
    vk::check(vkCreateCommandPool(ctx.device(), &info, nullptr, &pool), "vkCreateCommandPool (chunk ring)");
    pool_ = vk::CommandPoolHandle(ctx.device(), pool);
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = kSlots;
    vk::check(vkAllocateCommandBuffers(ctx.device(), &alloc, cmd_), "vkAllocateCommandBuffers (chunk ring)");
    for (int i = 0; i < kSlots; ++i) {
      VkFenceCreateInfo f{};
      f.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
      VkFence fence = VK_NULL_HANDLE;
      vk::check(vkCreateFence(ctx.device(), &f, nullptr, &fence), "vkCreateFence (chunk ring)");
      fence_[i] = vk::FenceHandle(ctx.device(), fence);
    }
  }
  ChunkRing(const ChunkRing&) = delete;
  ChunkRing& operator=(const ChunkRing&) = delete;
  // A consumer that throws leaves a chunk in flight: wait for it before the buffers and the pool go.
  ~ChunkRing() {
    for (int i = 0; i < kSlots; ++i)
      if (pending_[i] && !ctx_.deviceLost()) {
        VkFence f = fence_[i].get();
        if (vkWaitForFences(ctx_.device(), 1, &f, VK_TRUE, uint64_t(vk::kDefaultFenceTimeout.count()) * 1000000ull) !=
            VK_SUCCESS) {
          fence_[i].release();  // still in use by a hung device: leak rather than destroy
          pool_.release();
        }
      }
  }

  VkCommandBuffer begin(int slot) {
    vk::check(vkResetCommandBuffer(cmd_[slot], 0), "vkResetCommandBuffer (chunk ring)");
    VkCommandBufferBeginInfo b{};
    b.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    b.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk::check(vkBeginCommandBuffer(cmd_[slot], &b), "vkBeginCommandBuffer (chunk ring)");
    return cmd_[slot];
  }

  void submit(int slot) {
    VkMemoryBarrier toHost{};
    toHost.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    toHost.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd_[slot], VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost,
                         0, nullptr, 0, nullptr);
    vk::check(vkEndCommandBuffer(cmd_[slot]), "vkEndCommandBuffer (chunk ring)");
    VkFence f = fence_[slot].get();
    vk::check(vkResetFences(ctx_.device(), 1, &f), "vkResetFences (chunk ring)");
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd_[slot];
    std::lock_guard<std::recursive_mutex> lock(ctx_.submitMutex());  // the queue is externally synchronized
    if (ctx_.deviceLost()) throw vk::VulkanError(VK_ERROR_DEVICE_LOST, "submitting a chunk");
    if (vk::deviceLostFaultDue()) {  // test-only fault injection, as in vk::OneShot (vk/fault.h)
      ctx_.markDeviceLost();
      throw vk::VulkanError(VK_ERROR_DEVICE_LOST, std::string("vkQueueSubmit (chunk ring)") + vk::kInjectedNote);
    }
    const VkResult r = vkQueueSubmit(ctx_.queue(), 1, &submit, f);
    if (r == VK_ERROR_DEVICE_LOST) ctx_.markDeviceLost();
    vk::check(r, "vkQueueSubmit (chunk ring)");
    pending_[slot] = true;
  }

  void wait(int slot) {
    VkFence f = fence_[slot].get();
    const VkResult r =
        vkWaitForFences(ctx_.device(), 1, &f, VK_TRUE, uint64_t(vk::kDefaultFenceTimeout.count()) * 1000000ull);
    if (r == VK_ERROR_DEVICE_LOST) ctx_.markDeviceLost();
    vk::check(r, "vkWaitForFences (chunk ring)");
    pending_[slot] = false;
  }

 private:
  vk::Context& ctx_;
  vk::CommandPoolHandle pool_;
  VkCommandBuffer cmd_[kSlots] = {};
  vk::FenceHandle fence_[kSlots];
  bool pending_[kSlots] = {};
};

template <class Push>
struct GridJob {
  Kernel kernel;
  bool surface;
  bool knotVector;  // no basis table: bspline_*_eval.comp evaluates de Boor-Cox per point
  FieldMask allowed;
  Push push;  // model part filled in; chunk part set per chunk
  size_t itemTotal;
};

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

  const size_t rs = realSize(k.precision());
  const size_t ppi = grid.pointsPerItem();

  const SpanBasis& bu = m.basisU();
  const SpanBasis& bv = m.basisV();
  const uint32_t su = uint32_t(grid.samplesU), sv = uint32_t(grid.samplesV);
  const uint32_t tableV = su * 3u * uint32_t(bu.count);
  vk::Buffer table;
  if (!job.knotVector)
    table = realBuffer(k, tableV + (job.surface ? sv * 3u * uint32_t(bv.count) : 0u), vk::MemoryUse::DeviceLocal,
                       "gpu.table");
  std::vector<int> active;
  for (int f = 0; f < kFieldCount; ++f)
    if (fields & fieldBit(Field(f))) active.push_back(f);
  // surface_grid.comp / curve_grid.comp (RUN_LENGTH samples per invocation): rows (curves: spans)
  // of up to 256 samples go whole to one invocation, several consecutive rows of a patch (spans)
  // per invocation while that stays within 512 samples (the net is then gathered once per several
  // rows: measured on lavapipe, bicubic P/du/dv at S = 32 runs 1.5x faster with 16 rows per
  // invocation than with 4); longer rows are split into the longest run of 64, 32, 16, 8 or 4
  // samples dividing them.
  const bool gridKernel = job.kernel == Kernel::SurfaceGrid || job.kernel == Kernel::CurveGrid;
  const uint32_t rowLength = job.surface ? sv : su;
  uint32_t run = rowLength % 64 == 0   ? 64u
                 : rowLength % 32 == 0 ? 32u
                 : rowLength % 16 == 0 ? 16u
                 : rowLength % 8 == 0  ? 8u
                                       : 4u;
  if (rowLength <= 256) {
    // Normal jobs also pay one masked pass of the fallback-normal loop per invocation
    // (surface_grid.comp): up to 1024 samples amortise it (2048 measured slower). Curve spans need
    // not divide anything.
    const bool normals = (fields & fieldBit(Field::Normal)) != 0;
    const uint32_t maxRows = 16u, maxRun = normals ? 1024u : 512u;
    uint32_t rows = 1;
    while (rows < maxRows && (!job.surface || su % (rows * 2) == 0) && rowLength * rows * 2 <= maxRun) rows *= 2;
    run = rowLength * rows;
  }
  SpecValues spec = evalSpec(m, fields, job.knotVector ? kNoListMode : 0u);
  if (gridKernel) spec[layout::kSpecRunLength] = run;
  const auto& pipe = k.pipeline(job.kernel, spec);

  // The chunks, in rows (a row: the Sv samples of one u sample of a patch, or one sample of a
  // span). Items whose planes fit maxPlaneBytes go whole, as many per chunk as fit; a larger item
  // goes in row ranges of a whole number of the grid kernel's invocations (rowsPer rows of a patch,
  // a run of a span), so device and host memory are bounded by the plane budget and not by the
  // grid. Only the device's maxStorageBufferRange is a hard limit (one granule of rows must fit).
  const size_t rowsPerItem = su, rowPoints = job.surface ? sv : 1u;
  const size_t rowBytes = rowPoints * 3 * rs, itemPlaneBytes = ppi * 3 * rs;
  const size_t hardLimit = k.context().limits().maxStorageBufferRange;
  const size_t cap = std::min(maxPlaneBytes, hardLimit), usable = cap > 4 * rs ? cap - 4 * rs : 0;
  const size_t granule = !gridKernel ? 1u : job.surface ? std::max<size_t>(1, run / sv) : run < su ? run : su;
  size_t perChunk = 0, rowsPerChunk = 0;  // whole items per chunk, or rows per row-range chunk
  if (itemPlaneBytes <= usable) {
    perChunk = std::min(count, usable / itemPlaneBytes);
  } else {
    rowsPerChunk = std::max(granule, usable / rowBytes / granule * granule);
    if (rowsPerChunk >= rowsPerItem) perChunk = 1, rowsPerChunk = 0;  // the kernel takes it whole
  }
  const size_t chunkPoints = perChunk ? perChunk * ppi : rowsPerChunk * rowPoints;
  if (chunkPoints * 3 * rs + 4 * rs > hardLimit)
    throw std::length_error("evaluateGrid: a chunk's plane (" + std::to_string(chunkPoints * 3 * rs) +
                            " bytes) exceeds the device's maxStorageBufferRange " + std::to_string(hardLimit));
  const size_t chunksPerItem = rowsPerChunk ? (rowsPerItem + rowsPerChunk - 1) / rowsPerChunk : 1;
  const size_t chunkCount = perChunk ? (count + perChunk - 1) / perChunk : count * chunksPerItem;
  // Chunk c as delivered (firstItem, itemCount, firstRow, rowCount; rowCount 0 for whole items).
  auto chunkAt = [&](size_t c) {
    GridChunk out;
    out.pointsPerItem = ppi;
    out.pointsPerRow = rowPoints;
    out.precision = k.precision();
    if (perChunk) {
      out.firstItem = grid.firstItem + c * perChunk;
      out.itemCount = std::min(perChunk, grid.firstItem + count - out.firstItem);
    } else {
      out.firstItem = grid.firstItem + c / chunksPerItem;
      out.itemCount = 1;
      out.firstRow = (c % chunksPerItem) * rowsPerChunk;
      out.rowCount = std::min(rowsPerChunk, rowsPerItem - out.firstRow);
    }
    return out;
  };

  std::vector<vk::DescriptorSet> keep;  // vertex pass / tables
  const int slots = chunkCount > 1 ? ChunkRing::kSlots : 1;
  static_assert(PlanePool::kSlots == ChunkRing::kSlots);
  const VkDeviceSize planeBytes = realBufferBytes(k, chunkPoints * 3);
  std::array<std::array<const vk::Buffer*, kFieldCount>, ChunkRing::kSlots> planes{};
  vk::DescriptorSet sets[ChunkRing::kSlots];
  for (int s = 0; s < slots; ++s) {
    for (int f : active) planes[s][f] = &pool.acquire(k.context(), s, f, planeBytes);
    sets[s] = makeSet(k, pipe);
    sets[s].bind(layout::kBindingNet, m.netBuffer())
        .bind(layout::kBindingParams, m.paramBuffer())
        .bind(layout::kBindingVerts, m.vertexBuffer());
    if (!job.knotVector) sets[s].bind(layout::kBindingTable, table);
    for (int f : active) sets[s].bind(layout::kBindingOutput + f, *planes[s][f]);
  }
  ChunkRing ring(k.context());  // declared last: its destructor waits before anything it uses goes

  auto record = [&](size_t chunk) {
    const int slot = int(chunk % slots);
    const GridChunk c = chunkAt(chunk);
    Push pc = job.push;
    pc.firstItem = uint32_t(c.firstItem);
    pc.itemCount = uint32_t(c.itemCount);
    pc.firstRow = uint32_t(c.firstRow);
    pc.rowCount = uint32_t(c.partial() ? c.rowCount : c.itemCount * rowsPerItem);
    pc.samplesU = su;
    pc.samplesV = sv;
    if constexpr (std::is_same_v<Push, layout::EvalPush>) pc.tableOffsetV = tableV;
    VkCommandBuffer cmd = ring.begin(slot);
    if (chunk == 0) {
      // Later chunks are later in submission order on the same queue, so this barrier orders the
      // vertex pass / tables before their dispatches too.
      recordVertexPass(k, m, job.surface, cmd, keep);
      if (!job.knotVector) {
        recordTable(k, m, bu, layout::kParamCoefU, su, 0, table, cmd, keep);
        if (job.surface) recordTable(k, m, bv, layout::kParamCoefV, sv, tableV, table, cmd, keep);
      }
      vk::computeBarrier(cmd);
    }
    pipe.bind(cmd, sets[slot].handle());
    pipe.push(cmd, pc);
    // Grid kernels: `run` samples per invocation (whole rows or spans, or runs dividing a row; the
    // last invocation of a curve chunk may hold fewer spans).
    const uint64_t perInvocation = gridKernel ? run : layout::kPointsPerInvocation;
    k.dispatch(cmd, (uint64_t(c.pointCount()) + perInvocation - 1) / perInvocation);
    ring.submit(slot);
  };

  record(0);
  for (size_t chunk = 0; chunk < chunkCount; ++chunk) {
    const int slot = int(chunk % slots);
    // The other slot's consumer call has returned: it may be overwritten while this one is read.
    if (chunk + 1 < chunkCount) record(chunk + 1);
    ring.wait(slot);
    if (chunk == 0 && m.alphaEB() && m.verticesDirty()) m.markVerticesClean();
    GridChunk out = chunkAt(chunk);
    for (int f : active) out.planes[f] = planes[slot][f]->mapped();
    consumer(out);
  }
  pool.trim(std::min<size_t>(maxPlaneBytes, hardLimit));
}

// List mode: samples (host ListSample bytes) -> planes of every allowed field, read back as doubles.
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
  // Samples in REAL precision (ListSampleF/D of layout.h).
  std::vector<std::byte> bytes;
  if (k.precision() == Precision::Double) {
    bytes.resize(total * sizeof(layout::ListSampleD));
    std::memcpy(bytes.data(), samples.data(), bytes.size());
  } else {
    std::vector<layout::ListSampleF> f(total);
    for (size_t i = 0; i < total; ++i)
      f[i] = {samples[i].i,        samples[i].j,        samples[i].intervalU,         samples[i].intervalV,
              float(samples[i].u), float(samples[i].v), float(samples[i].localU), float(samples[i].localV)};
    bytes.resize(total * sizeof(layout::ListSampleF));
    std::memcpy(bytes.data(), f.data(), bytes.size());
  }
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

// The span core/bspline.h evalBSplineCurve/Surface uses at knot parameter x, and x clamped to the
// domain, as a (span, parameter) pair for the SAMPLES buffer.
std::pair<uint32_t, double> knotSpanOf(int order, const std::vector<double>& knots, int count, double x) {
  const int span = findKnotSpan(order, knots, count, x);
  return {uint32_t(span), std::clamp(x, knots[order - 1], knots[count])};
}

void checkPrecision(const KernelSet& k, const GpuModel& m) {
  if (k.precision() != m.precision())
    throw std::invalid_argument("evaluator and model were created with different precisions");
}

std::vector<CurvePoint> runCurveList(KernelSet& k, GpuCurve& curve, const std::vector<layout::ListSampleD>& s,
                                     size_t maxPlaneBytes) {
  const auto planes = curve.knotVector() ? runList(k, curve, Kernel::BSplineCurveEval, false, kCurveFields,
                                                   knotPush(curve, 1, 1), s, maxPlaneBytes)
                                         : runList(k, curve, Kernel::CurveEval, false, kCurveFields,
                                                   curvePush(curve), s, maxPlaneBytes);
  std::vector<CurvePoint> out(s.size());
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].point = at(planes[int(Field::Point)], i);
    out[i].d1 = at(planes[int(Field::D1)], i);
    out[i].d2 = at(planes[int(Field::D2)], i);
  }
  return out;
}

}  // namespace

layout::EvalPush surfacePush(const GpuSurface& s) {
  layout::EvalPush p{};
  p.itemsV = uint32_t(s.patchesV());
  p.samplesU = 1;
  p.samplesV = 1;
  setSurfaceNetFields(p, s);
  p.invHOffset = layout::kNoOffset;
  return p;
}

// ---- CurveEvaluator -----------------------------------------------------------------------------

CurveEvaluator::CurveEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision, EvaluatorOptions options)
    : kernels_(std::make_unique<KernelSet>(std::move(ctx), precision, options.workgroupSize, options.packedStores)),
      planes_(std::make_unique<PlanePool>()),
      options_(options) {}
CurveEvaluator::~CurveEvaluator() = default;
Precision CurveEvaluator::precision() const { return kernels_->precision(); }

void CurveEvaluator::evaluateGrid(GpuCurve& curve, const GridSpec& grid, FieldMask fields,
                                  const ChunkConsumer& consumer) {
  checkPrecision(*kernels_, curve);
  if (curve.knotVector()) {
    GridJob<layout::KnotEvalPush> job{Kernel::BSplineCurveEval, false, true, kCurveFields, knotPush(curve, 1, 1),
                                      curve.gridItemCount()};
    runGrid(*kernels_, *planes_, curve, job, grid, fields, consumer, options_.maxPlaneBytes);
    return;
  }
  // curve_grid.comp when the samples come in whole groups of 4 (the packed stores of 4 points).
  const bool fast = grid.samplesU % 4 == 0 && !options_.generalKernelsOnly;
  GridJob<layout::EvalPush> job{fast ? Kernel::CurveGrid : Kernel::CurveEval, false, false, kCurveFields,
                                curvePush(curve), curve.spanCount()};
  runGrid(*kernels_, *planes_, curve, job, grid, fields, consumer, options_.maxPlaneBytes);
}

std::vector<CurvePoint> CurveEvaluator::evaluateList(GpuCurve& curve, std::span<const CurveSample> samples) {
  checkPrecision(*kernels_, curve);
  std::vector<layout::ListSampleD> s(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const CurveSample& x = samples[i];
    if (x.span < curve.spans().first || x.span > curve.spans().last || !(x.t >= 0.0 && x.t <= 1.0))
      throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " (span " + std::to_string(x.span) +
                              ", t " + std::to_string(x.t) + ") is outside the curve");
    if (curve.knotVector()) {
      // core/curve.cpp Curve::evaluate: the knot parameter a + t (b - a), then findKnotSpan.
      const auto& kn = curve.model().knots;
      const double a = kn[x.span], b = kn[x.span + 1];
      if (!(b > a))
        throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " lies on the empty knot interval " +
                                std::to_string(x.span));
      const auto [span, u] = knotSpanOf(curve.model().family.order, kn, int(curve.model().points.size()),
                                        a + x.t * (b - a));
      s[i] = {span, 0u, 0u, 0u, u, 0.0, 0.0, 0.0};
      continue;
    }
    s[i] = {uint32_t(x.span), 0u, 0u, 0u, x.t, 0.0, 0.0, 0.0};
  }
  return runCurveList(*kernels_, curve, s, options_.maxPlaneBytes);
}

std::vector<CurvePoint> CurveEvaluator::evaluateListAt(GpuCurve& curve, std::span<const double> u) {
  checkPrecision(*kernels_, curve);
  const auto [lo, hi] = curve.parameterRange();
  std::vector<layout::ListSampleD> s(u.size());
  std::vector<CurveSample> local;
  for (size_t i = 0; i < u.size(); ++i) {
    const double x = u[i];
    if (!(x >= lo && x <= hi))
      throw std::out_of_range("evaluateListAt: u[" + std::to_string(i) + "] = " + std::to_string(x) +
                              " outside the parameter range");
    if (curve.knotVector()) {
      // core/curve.cpp Curve::evaluateAt: evalBSplineCurve at the knot parameter itself.
      const auto [span, xc] =
          knotSpanOf(curve.model().family.order, curve.model().knots, int(curve.model().points.size()), x);
      s[i] = {span, 0u, 0u, 0u, xc, 0.0, 0.0, 0.0};
      continue;
    }
    // core/curve.cpp Curve::spanOfParameter.
    const SpanRange r = curve.spans();
    const auto& kn = curve.spanKnots();
    CurveSample cs;
    if (!kn.empty()) {
      int sp = int(std::upper_bound(kn.begin(), kn.end(), x) - kn.begin()) - 1;
      sp = std::clamp(sp, 0, int(kn.size()) - 2);
      cs = {r.first + sp, std::clamp((x - kn[sp]) / (kn[sp + 1] - kn[sp]), 0.0, 1.0)};
    } else {
      const int j = std::clamp(int(std::floor(x)), r.first, r.last);
      cs = {j, std::clamp(x - j, 0.0, 1.0)};
    }
    local.push_back(cs);
  }
  if (!curve.knotVector()) return evaluateList(curve, local);
  return runCurveList(*kernels_, curve, s, options_.maxPlaneBytes);
}

// ---- SurfaceEvaluator ---------------------------------------------------------------------------

SurfaceEvaluator::SurfaceEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision, EvaluatorOptions options)
    : kernels_(std::make_unique<KernelSet>(std::move(ctx), precision, options.workgroupSize, options.packedStores)),
      planes_(std::make_unique<PlanePool>()),
      options_(options) {}
SurfaceEvaluator::~SurfaceEvaluator() = default;
Precision SurfaceEvaluator::precision() const { return kernels_->precision(); }

void SurfaceEvaluator::evaluateGrid(GpuSurface& surface, const GridSpec& grid, FieldMask fields,
                                    const ChunkConsumer& consumer) {
  checkPrecision(*kernels_, surface);
  if (surface.knotVector()) {
    GridJob<layout::KnotEvalPush> job{Kernel::BSplineSurfaceEval, true, true, kSurfaceFields,
                                      knotPush(surface, uint32_t(surface.gridItemsV()), surface.netCols()),
                                      surface.gridItemCount()};
    runGrid(*kernels_, *planes_, surface, job, grid, fields, consumer, options_.maxPlaneBytes);
    return;
  }
  // surface_grid.comp: tensor and α-EB surfaces, with or without normals, RUN_LENGTH samples (whole
  // rows) per invocation sharing the patch net, the α-EB corner data and the u contraction (needs
  // samplesV % 4 == 0; rare normals fall back to the §5.3 code shared with surface_eval.comp).
  const bool fast = grid.samplesV % 4 == 0 && !options_.generalKernelsOnly;
  GridJob<layout::EvalPush> job{fast ? Kernel::SurfaceGrid : Kernel::SurfaceEval, true, false, kSurfaceFields,
                                surfacePush(surface), surface.patchCount()};
  runGrid(*kernels_, *planes_, surface, job, grid, fields, consumer, options_.maxPlaneBytes);
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
    if (surface.knotVector()) {
      // core/surface.cpp evalPatch: knot parameters u0 + u (u1 - u0), then evalBSplineSurface.
      const SurfaceModel& m = surface.model();
      const int ku = m.family.order, kv = m.orderV > 0 ? m.orderV : m.family.order;
      const double u0 = m.knotsU[x.i], u1 = m.knotsU[x.i + 1], v0 = m.knotsV[x.j], v1 = m.knotsV[x.j + 1];
      if (!(u1 > u0) || !(v1 > v0))
        throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " lies on an empty knot interval");
      const auto [spanU, xu] = knotSpanOf(ku, m.knotsU, m.rows, u0 + x.u * (u1 - u0));
      const auto [spanV, xv] = knotSpanOf(kv, m.knotsV, m.cols, v0 + x.v * (v1 - v0));
      s[i] = {spanU, spanV, uint32_t(x.i), uint32_t(x.j), xu, xv, x.u, x.v};
      continue;
    }
    s[i] = {uint32_t(x.i), uint32_t(x.j), 0u, 0u, x.u, x.v, 0.0, 0.0};
  }
  const auto planes =
      surface.knotVector()
          ? runList(*kernels_, surface, Kernel::BSplineSurfaceEval, true, kSurfaceFields,
                    knotPush(surface, uint32_t(surface.gridItemsV()), surface.netCols()), s, options_.maxPlaneBytes)
          : runList(*kernels_, surface, Kernel::SurfaceEval, true, kSurfaceFields, surfacePush(surface), s,
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

std::vector<SurfacePoint> SurfaceEvaluator::evaluateListAt(GpuSurface& surface,
                                                           std::span<const std::pair<double, double>> uv) {
  const auto [ulo, uhi] = surface.parameterRangeU();
  const auto [vlo, vhi] = surface.parameterRangeV();
  const SurfaceModel& m = surface.model();
  const PatchRange r = surface.patches();
  std::vector<SurfaceSample> local(uv.size());
  for (size_t i = 0; i < uv.size(); ++i) {
    const auto [U, V] = uv[i];
    if (!(U >= ulo && U <= uhi) || !(V >= vlo && V <= vhi))
      throw std::out_of_range("evaluateListAt: sample " + std::to_string(i) + " outside the parameter range");
    if (surface.knotVector()) {
      // core/surface.cpp Surface::evaluateAt: knot spans, then local parameters.
      const int ku = m.family.order, kv = m.orderV > 0 ? m.orderV : m.family.order;
      const int a = findKnotSpan(ku, m.knotsU, m.rows, U), b = findKnotSpan(kv, m.knotsV, m.cols, V);
      const double u = (U - m.knotsU[a]) / (m.knotsU[a + 1] - m.knotsU[a]);
      const double v = (V - m.knotsV[b]) / (m.knotsV[b + 1] - m.knotsV[b]);
      local[i] = {a, b, std::clamp(u, 0.0, 1.0), std::clamp(v, 0.0, 1.0)};
      continue;
    }
    // core/surface.cpp Surface::patchOf.
    const int a = std::clamp(int(std::floor(U)), r.u.first, r.u.last);
    const int b = std::clamp(int(std::floor(V)), r.v.first, r.v.last);
    local[i] = {a, b, std::clamp(U - a, 0.0, 1.0), std::clamp(V - b, 0.0, 1.0)};
  }
  return evaluateList(surface, local);
}

// ---- BasisTableEvaluator ------------------------------------------------------------------------

BasisTableEvaluator::BasisTableEvaluator(std::shared_ptr<vk::Context> ctx, Precision precision,
                                         EvaluatorOptions options)
    : kernels_(std::make_unique<KernelSet>(std::move(ctx), precision, options.workgroupSize, options.packedStores)) {}
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
  const auto& pipe = k.pipeline(Kernel::BasisTable, basisTableSpec(basis));
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
