#include <shapespline/core/grid_sampler.h>

#include <shapespline/core/cores.h>
#include <shapespline/core/knot_table.h>
#include <shapespline/core/point_math.h>
#include <shapespline/core/point_records.h>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <iterator>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

namespace shapespline {
namespace {

constexpr FieldMask kCurveFields = fieldBit(Field::Point) | fieldBit(Field::D1) | fieldBit(Field::D2);
constexpr FieldMask kSurfaceFields = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv) |
                                     fieldBit(Field::Duu) | fieldBit(Field::Duv) | fieldBit(Field::Dvv) |
                                     fieldBit(Field::Normal);

bool wants(FieldMask mask, Field f) { return (mask & fieldBit(f)) != 0; }

// Row k of a surface sampler's row buffers is the partial of u-order kPartialOrders[k][0] and
// v-order kPartialOrders[k][1]: point, du, dv, duu, duv, dvv.
constexpr int kPartialOrders[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};

double gridParameter(int a, int samples) { return samples > 1 ? static_cast<double>(a) / (samples - 1) : 0.0; }

// Basis (and singular blend) values of one direction at every grid parameter, laid out so that the
// inner loops run over contiguous samples: b[d][r * samples + a] = B_r^(d)(t_a).
struct DirectionTable {
  int count = 0, samples = 0;
  std::vector<double> b[3];
  std::vector<glm::dvec3> blend;  // (S, S', S'')(t_a)

  const double* row(int d, int r) const { return b[d].data() + static_cast<size_t>(r) * samples; }
};

DirectionTable tabulate(const SpanBasis& basis, int samples) {
  DirectionTable tab;
  tab.count = basis.count;
  tab.samples = samples;
  for (auto& v : tab.b) v.assign(static_cast<size_t>(basis.count) * samples, 0.0);
  tab.blend.resize(samples);
  for (int a = 0; a < samples; ++a) {
    const double t = gridParameter(a, samples);
    double v[3][kMaxBasisCount];
    evalSpanBasis(basis, t, v[0], v[1], v[2]);
    for (int d = 0; d < 3; ++d)
      for (int r = 0; r < basis.count; ++r) tab.b[d][static_cast<size_t>(r) * samples + a] = v[d][r];
    tab.blend[a] = pm::singularBlend(t);
  }
  return tab;
}

// Output planes of one chunk buffer: plane[f] holds 3 doubles per point, or is empty. Not zeroed:
// pages a job never writes (all of them when a RecordSink takes the points) are never touched.
struct ChunkBuffer {
  std::unique_ptr<double[]> planes[kFieldCount];
  void allocate(FieldMask fields, size_t points) {
    for (int f = 0; f < kFieldCount; ++f)
      if (fields & (1u << f)) planes[f] = std::make_unique_for_overwrite<double[]>(points * 3);
  }
  double* plane(Field f) const { return planes[static_cast<int>(f)].get(); }
};

void put(double* plane, size_t point, const glm::dvec3& v) {
  if (!plane) return;
  plane[point * 3 + 0] = v.x;
  plane[point * 3 + 1] = v.y;
  plane[point * 3 + 2] = v.z;
}

// The two hot loops of surface sampling are also compiled for AVX2 and picked at run time. No FMA
// in either clone (the "avx2" target does not enable it), so both give identical bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SHAPESPLINE_HOT_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SHAPESPLINE_HOT_CLONES
#endif

// dst[b] = sum_s rows[s][b] * t[s] over the samples b < n, summed in order s = 0, 1, ... starting
// from 0.0 (the order fixes the bits; rows[s] is a tabulated basis row). The 4-function families
// (all Xu-Wang and α-EB bases, cubic B-splines) get an unrolled loop that keeps the sum in registers.
SHAPESPLINE_HOT_CLONES
void contractRows4(const double* const* rows, const double* t, int n, double* dst) {
  const double *r0 = rows[0], *r1 = rows[1], *r2 = rows[2], *r3 = rows[3];
  const double t0 = t[0], t1 = t[1], t2 = t[2], t3 = t[3];
  for (int b = 0; b < n; ++b) {
    double acc = 0.0;
    acc += r0[b] * t0;
    acc += r1[b] * t1;
    acc += r2[b] * t2;
    acc += r3[b] * t3;
    dst[b] = acc;
  }
}

void contractRows(const double* const* rows, const double* t, int m, int n, double* dst) {
  if (m == 4) return contractRows4(rows, t, n, dst);
  for (int b = 0; b < n; ++b) {
    double acc = 0.0;
    for (int s = 0; s < m; ++s) acc += rows[s][b] * t[s];
    dst[b] = acc;
  }
}

// dst[3b + c] = (x, y, z)[c][b]: structure-of-arrays rows into an interleaved xyz plane.
SHAPESPLINE_HOT_CLONES
void interleaveRows(const double* x, const double* y, const double* z, int n, double* dst) {
  for (int b = 0; b < n; ++b) {
    dst[3 * b + 0] = x[b];
    dst[3 * b + 1] = y[b];
    dst[3 * b + 2] = z[b];
  }
}

// Where the samplers put computed points (point: index in the chunk). Rows come as structure of
// arrays: rows[f][c] is axis c of field f for Sv consecutive points (nullptr for a field not
// computed). PlaneOut fills a chunk buffer's planes; RecordOut encodes records into a block of a
// RecordSink and remembers whether every value was in range.
struct PlaneOut {
  double* plane[kFieldCount];
  explicit PlaneOut(const ChunkBuffer& buffer) {
    for (int f = 0; f < kFieldCount; ++f) plane[f] = buffer.plane(static_cast<Field>(f));
  }
  void put(Field f, size_t point, const glm::dvec3& v) const { shapespline::put(plane[static_cast<int>(f)], point, v); }
  void putRows(const double* const (*rows)[3], int n, size_t point) const {
    for (int f = 0; f < kFieldCount; ++f)
      if (plane[f] && rows[f][0]) interleaveRows(rows[f][0], rows[f][1], rows[f][2], n, plane[f] + point * 3);
  }
};

struct RecordOut {
  char* data;         // the block: records of points firstPoint, firstPoint + 1, ...
  size_t firstPoint;  // chunk point of the block's first record
  const RecordSink& sink;
  size_t recordBytes, valueBytes;
  int slot[kFieldCount];  // field -> position in the record, or -1
  bool inRange = true;

  RecordOut(char* block, size_t first, const RecordSink& s)
      : data(block), firstPoint(first), sink(s), recordBytes(shapespline::recordBytes(s.fields.size(), s.float64)),
        valueBytes(s.float64 ? 8 : 4) {
    std::fill(std::begin(slot), std::end(slot), -1);
    for (size_t k = 0; k < s.fields.size(); ++k) slot[static_cast<int>(s.fields[k])] = static_cast<int>(k);
  }
  char* record(size_t point) const { return data + (point - firstPoint) * recordBytes; }
  void put(Field f, size_t point, const glm::dvec3& v) {
    const int k = slot[static_cast<int>(f)];
    if (k >= 0) encodeValue3(record(point) + static_cast<size_t>(k) * 3 * valueBytes, v, sink.float64, inRange);
  }
  void putRows(const double* const (*rows)[3], int n, size_t point) {
    const double* ordered[3 * kFieldCount];
    for (size_t k = 0; k < sink.fields.size(); ++k)
      for (int c = 0; c < 3; ++c) ordered[3 * k + c] = rows[static_cast<int>(sink.fields[k])][c];
    inRange &= encodeRowRecords(record(point), ordered, sink.fields.size(), sink.float64, static_cast<size_t>(n));
  }
};

// The chunks of a job over the rows [firstItem * rowsPerItem, (firstItem + itemCount) * rowsPerItem)
// of the model's items (a row: Sv points of a patch, or one sample of a span). Items that fit the
// point budget go whole, as many per chunk as fit; a larger item is cut into row ranges of at most
// max(1, budget / pointsPerRow) rows, so a chunk never holds more than max(budget, pointsPerRow) points.
struct ChunkPlan {
  size_t firstItem, itemCount, rowsPerItem, pointsPerRow;
  size_t itemsPerChunk = 0;  // whole-item chunks (0: items are cut into row ranges)
  size_t rowsPerChunk = 0;   // row-range chunks
  size_t chunksPerItem = 1;

  ChunkPlan(size_t first, size_t count, size_t rows, size_t rowPoints, size_t budget)
      : firstItem(first), itemCount(count), rowsPerItem(rows), pointsPerRow(rowPoints) {
    const size_t ppi = rows * rowPoints;
    budget = std::max<size_t>(budget, 1);
    if (ppi <= budget) {
      itemsPerChunk = std::clamp<size_t>(budget / std::max<size_t>(ppi, 1), 1, std::max<size_t>(count, 1));
    } else {
      rowsPerChunk = std::max<size_t>(1, budget / rowPoints);
      chunksPerItem = (rows + rowsPerChunk - 1) / rowsPerChunk;
    }
  }
  size_t chunkCount() const {
    return itemsPerChunk ? (itemCount + itemsPerChunk - 1) / itemsPerChunk : itemCount * chunksPerItem;
  }
  size_t capacityPoints() const {
    return itemsPerChunk ? itemsPerChunk * rowsPerItem * pointsPerRow : rowsPerChunk * pointsPerRow;
  }
  // Global rows [begin, end) of chunk c.
  std::pair<size_t, size_t> rows(size_t c) const {
    if (itemsPerChunk) {
      const size_t b = firstItem + c * itemsPerChunk, e = std::min(b + itemsPerChunk, firstItem + itemCount);
      return {b * rowsPerItem, e * rowsPerItem};
    }
    const size_t item = firstItem + c / chunksPerItem, r0 = (c % chunksPerItem) * rowsPerChunk;
    return {item * rowsPerItem + r0, item * rowsPerItem + std::min(rowsPerItem, r0 + rowsPerChunk)};
  }
  GridChunk chunk(size_t c) const {
    const auto [b, e] = rows(c);
    GridChunk out;
    out.firstItem = b / rowsPerItem;
    out.pointsPerItem = rowsPerItem * pointsPerRow;
    out.pointsPerRow = pointsPerRow;
    if (itemsPerChunk) {
      out.itemCount = (e - b) / rowsPerItem;
    } else {
      out.itemCount = 1;
      out.firstRow = b % rowsPerItem;
      out.rowCount = e - b;
    }
    return out;
  }
};

// Calls body(item, a0, a1, point) for the rows a0..a1-1 of each item that global rows [begin, end)
// touch; `point` is the buffer index of (item, a0), counted from `firstPoint` at row `begin`.
template <class Body>
void forEachItemRows(size_t begin, size_t end, size_t rowsPerItem, size_t pointsPerRow, size_t firstPoint,
                     Body body) {
  size_t point = firstPoint;
  for (size_t r = begin; r < end;) {
    const size_t item = r / rowsPerItem, a0 = r % rowsPerItem, a1 = std::min(rowsPerItem, a0 + (end - r));
    body(item, static_cast<int>(a0), static_cast<int>(a1), point);
    point += (a1 - a0) * pointsPerRow;
    r += a1 - a0;
  }
}

// Chunk `chunk` of `plan` as delivered: its item/row range over the planes of `buffer` (none
// without a buffer: a RecordSink took the points).
GridChunk deliverable(const ChunkPlan& plan, const ChunkBuffer* buffer, size_t chunk) {
  GridChunk out = plan.chunk(chunk);
  out.precision = Precision::Double;
  if (buffer)
    for (int f = 0; f < kFieldCount; ++f) out.planes[f] = buffer->plane(static_cast<Field>(f));
  return out;
}

// The sink the workers encode records into, or nullptr: without one, or when one row of points
// does not fit a block (then the slices carry the records, cut to the blocks' size).
const RecordSink* usableSink(const SamplerOptions& options, FieldMask fields, size_t pointsPerRow) {
  const RecordSink& sink = options.records;
  if (!sink.acquire) return nullptr;
  FieldMask sinkFields = 0;
  for (Field f : sink.fields) sinkFields |= fieldBit(f);
  if (sinkFields != fields || sink.fields.size() > static_cast<size_t>(kFieldCount))
    throw std::invalid_argument("a record sink's fields must be the sampled fields, each once");
  if (!options.slice) throw std::invalid_argument("a record sink needs a slice consumer (to report values out of range)");
  return pointsPerRow <= sink.maxPoints ? &sink : nullptr;
}

// Chunk buffers in flight: the workers may run up to kChunkBuffers - 1 chunks ahead of the consumer.
// With 2, a worker delayed on one chunk (a preemption on a 2-core VM) stalled the other within a
// chunk; with 4, 2 threads over 1 went from 1.56-1.69x to 1.74-1.78x (bench/ bspline3 and knot3, S =
// 32 and 64; two independent processes reach 1.8-1.96x on this machine). Pages of a buffer a job
// never writes (a record sink takes the points) are never touched.
constexpr size_t kChunkBuffers = 4;

// Runs compute(out, rowBegin, rowEnd, firstPointInChunk) over every chunk of `plan` (`out`: a
// PlaneOut over a chunk buffer or, with a record sink, a RecordOut over one of its blocks), each chunk's
// rows split into one slice per worker (threads share the rows of one patch just as they share
// whole patches), and hands finished chunks to the consumer in order on the calling thread while
// the workers fill the other buffers. The workers live for the whole job (no thread start per
// chunk), so chunks can be small enough for their buffers to stay in cache.
template <class Compute>
void runChunked(const ChunkPlan& plan, FieldMask fields, const SamplerOptions& options, const ChunkConsumer& consumer,
                Compute compute) {
  if (plan.itemCount == 0) return;
  const RecordSink* sink = usableSink(options, fields, plan.pointsPerRow);
  // By default a worker per core, less the cores a record sink keeps busy: on two cores, two
  // workers beside the sink's writer thread made the e2e .f32 job 10% slower than one (3 runs of
  // 16 interleaved pairs; the three threads preempted each other).
  const int cores = availableCores();
  const int threads = options.threads > 0 ? options.threads : std::max(1, cores - (sink ? sink->ownThreads : 0));
  const size_t chunkCount = plan.chunkCount();
  const size_t maxRows = plan.itemsPerChunk ? plan.itemsPerChunk * plan.rowsPerItem : plan.rowsPerChunk;
  const size_t workers = std::min<size_t>(static_cast<size_t>(threads), maxRows);
  ChunkBuffer buffers[kChunkBuffers];
  for (auto& b : buffers) b.allocate(fields, plan.capacityPoints());

  // Shared state: slices finished per chunk, chunks consumed, and the first failure.
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<size_t> slicesDone(chunkCount, 0);
  size_t consumed = 0;
  bool stop = false;
  std::exception_ptr failure;

  // Rows [b, e) of `chunk` straight into records, a block at a time. A block that holds a value
  // out of range is computed again into the planes and handed to the slice consumer, which finds
  // and reports it (the same bits: every point is computed by the same code either way).
  auto encodeRows = [&](size_t chunk, size_t b, size_t e) {
    const size_t begin = plan.rows(chunk).first;
    const size_t rowsPerBlock = sink->maxPoints / plan.pointsPerRow;
    const GridChunk where = deliverable(plan, nullptr, chunk);
    for (size_t pb = b; pb < e; pb += rowsPerBlock) {
      const size_t pe = std::min(e, pb + rowsPerBlock);
      const size_t first = (pb - begin) * plan.pointsPerRow, count = (pe - pb) * plan.pointsPerRow;
      const RecordBlock block = sink->acquire();
      RecordOut out(block.data, first, *sink);
      compute(out, pb, pe, first);
      sink->submit(block, where, first, count);
      if (!out.inRange) {
        compute(PlaneOut(buffers[chunk % kChunkBuffers]), pb, pe, first);
        options.slice(deliverable(plan, &buffers[chunk % kChunkBuffers], chunk), first, count);
      }
    }
  };

  auto work = [&](size_t w) {
    for (size_t chunk = 0; chunk < chunkCount; ++chunk) {
      {
        // Buffer chunk % kChunkBuffers is free once chunk - kChunkBuffers has been consumed.
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return stop || consumed + kChunkBuffers > chunk; });
        if (stop) return;
      }
      const auto [begin, end] = plan.rows(chunk);
      const size_t n = end - begin;
      const size_t b = begin + n * w / workers, e = begin + n * (w + 1) / workers;
      try {
        if (b < e && sink) {
          encodeRows(chunk, b, e);
        } else if (b < e) {
          compute(PlaneOut(buffers[chunk % kChunkBuffers]), b, e, (b - begin) * plan.pointsPerRow);
          if (options.slice) {
            options.slice(deliverable(plan, &buffers[chunk % kChunkBuffers], chunk), (b - begin) * plan.pointsPerRow,
                          (e - b) * plan.pointsPerRow);
          }
        }
      } catch (...) {
        std::lock_guard lock(mutex);
        if (!failure) failure = std::current_exception();
        stop = true;
        changed.notify_all();
        return;
      }
      std::lock_guard lock(mutex);
      if (++slicesDone[chunk] == workers) changed.notify_all();
    }
  };
  std::vector<std::thread> pool;
  auto shutdown = [&] {
    {
      std::lock_guard lock(mutex);
      stop = true;
    }
    changed.notify_all();
    for (auto& t : pool) t.join();
  };
  try {
    for (size_t w = 0; w < workers; ++w) pool.emplace_back(work, w);
  } catch (...) {
    shutdown();
    throw;
  }

  for (size_t chunk = 0; chunk < chunkCount; ++chunk) {
    {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return failure || slicesDone[chunk] == workers; });
      if (failure) break;
    }
    const GridChunk out = deliverable(plan, sink ? nullptr : &buffers[chunk % kChunkBuffers], chunk);
    try {
      consumer(out);
    } catch (...) {
      shutdown();  // no worker may outlive the buffers
      throw;
    }
    {
      std::lock_guard lock(mutex);
      consumed = chunk + 1;
    }
    changed.notify_all();
  }
  shutdown();
  if (failure) std::rethrow_exception(failure);
}

void checkGrid(const GridSpec& grid, size_t items, bool surface, size_t& first, size_t& count) {
  if (grid.samplesU < 2) throw std::invalid_argument("samplesU must be >= 2, got " + std::to_string(grid.samplesU));
  if (surface && grid.samplesV < 2)
    throw std::invalid_argument("samplesV must be >= 2, got " + std::to_string(grid.samplesV));
  if (!surface && grid.samplesV != 1) throw std::invalid_argument("curves sample with samplesV = 1");
  first = grid.firstItem;
  count = grid.itemCount == 0 ? (first <= items ? items - first : 0) : grid.itemCount;
  if (first > items || count > items - first)
    throw std::invalid_argument("item range [" + std::to_string(first) + ", " + std::to_string(first + count) +
                                ") outside the model's " + std::to_string(items) + " items");
}

}  // namespace

std::vector<int> curveGridItems(const Curve& curve) {
  std::vector<int> items;
  const SpanRange r = curve.spans();
  for (int j = r.first; j <= r.last; ++j) {
    if (curve.usesKnotVector()) {
      const auto& k = curve.model().knots;
      if (!(k[j] < k[j + 1])) continue;
    }
    items.push_back(j);
  }
  return items;
}

std::vector<std::pair<int, int>> surfaceGridItems(const Surface& surface) {
  std::vector<std::pair<int, int>> items;
  const PatchRange r = surface.patches();
  const auto& m = surface.model();
  for (int i = r.u.first; i <= r.u.last; ++i) {
    if (surface.usesKnotVector() && !(m.knotsU[i] < m.knotsU[i + 1])) continue;
    for (int j = r.v.first; j <= r.v.last; ++j) {
      if (surface.usesKnotVector() && !(m.knotsV[j] < m.knotsV[j + 1])) continue;
      items.emplace_back(i, j);
    }
  }
  return items;
}

namespace {

// The α-EB data of a span's two vertices (docs/math.md §4.2); `alphaEB` false for plain families.
struct SpanEnds {
  bool alphaEB = false;
  glm::dvec3 v0{0.0}, v1{0.0};
  double a0 = 0.0, a1 = 0.0;
};

// Rows [aBegin, aEnd) of one uniform curve span at points point, point + 1, ...: the table sums
// and, for α-EB, the blend. A function of its own (not inside the sampler's lambda) so that GCC
// keeps the table pointers and sums in registers: inlined into the lambda it spilled them to the
// stack in the r loop (17 stack accesses per iteration), and the CPU α-EB curve rate fell ~10%.
template <class Out>
void sampleSpanRows(const DirectionTable& tab, const glm::dvec3* P, const SpanEnds& ends, double invH, int aBegin,
                    int aEnd, size_t point, Out& out) {
  const size_t S = static_cast<size_t>(tab.samples);
  const double* b0 = tab.b[0].data();
  const double* b1 = tab.b[1].data();
  const double* b2 = tab.b[2].data();
  for (int a = aBegin; a < aEnd; ++a, ++point) {
    glm::dvec3 c0(0.0), c1(0.0), c2(0.0);
    for (int r = 0; r < tab.count; ++r) {
      const size_t k = static_cast<size_t>(r) * S + static_cast<size_t>(a);
      pm::accumulate3(c0, c1, c2, b0[k], b1[k], b2[k], P[r]);
    }
    if (ends.alphaEB) pm::alphaEBBlendCurve(tab.blend[a], ends.v0, ends.v1, ends.a0, ends.a1, c0, c1, c2);
    out.put(Field::Point, point, c0);
    out.put(Field::D1, point, c1 * invH);
    out.put(Field::D2, point, c2 * (invH * invH));
  }
}

// Rows [aBegin, aEnd) of one knot interval of a knot-vector curve: each sample's tabulated basis
// against the control points of its span (the same sums, in the same order, as evalBSplineCurve;
// with `weights`, a rational curve: homogeneous sums and the quotient rule).
template <class Out>
void sampleKnotSpanRows(const KnotTable& tab, const glm::dvec3* points, const double* weights, int aBegin, int aEnd,
                        size_t point, Out& out) {
  for (int a = aBegin; a < aEnd; ++a, ++point) {
    const size_t first = static_cast<size_t>(tab.span[static_cast<size_t>(a)] - tab.order + 1);
    glm::dvec3 c0(0.0), c1(0.0), c2(0.0);
    double w0 = 0.0, w1 = 0.0, w2 = 0.0;
    for (int r = 0; r < tab.order; ++r) {
      const double b0 = tab.row(0, r)[a], b1 = tab.row(1, r)[a], b2 = tab.row(2, r)[a];
      if (!weights) {
        pm::accumulate3(c0, c1, c2, b0, b1, b2, points[first + r]);
        continue;
      }
      const double w = weights[first + r];
      pm::accumulate3(c0, c1, c2, b0, b1, b2, w * points[first + r]);
      w0 += b0 * w, w1 += b1 * w, w2 += b2 * w;
    }
    if (weights) pm::rationalCurve(c0, c1, c2, w0, w1, w2);
    out.put(Field::Point, point, c0);
    out.put(Field::D1, point, c1);
    out.put(Field::D2, point, c2);
  }
}

// Row a of knot interval pair (i, j) of a knot-vector surface: the partials need[k] (kPartialOrders)
// at every v sample into the structure-of-arrays rows row(k, c), c < 3 (a dvec3 net) or c < 4 (the
// homogeneous net (w P, w) of a rational surface). As in the uniform path, the net is contracted in
// u with row a's tabulated basis, then each needed row is one contraction over the v basis rows;
// once per run of v samples that share a span (the last sample may lie on the next).
template <class Vec, class RowFn>
void knotRowPartials(const KnotTable& tu, const KnotTable& tv, const Vec* net, int cols, int a, const bool need[6],
                     RowFn row) {
  constexpr int kCoords = Vec::length();
  const int mu = tu.order, mv = tv.order;
  const Vec* P = net + static_cast<size_t>(tu.span[static_cast<size_t>(a)] - mu + 1) * cols;
  const bool needD[3] = {true, need[1] || need[4], need[3]};
  for (int b0 = 0; b0 < tv.samples;) {
    const int b1 = tv.runEnd(b0);
    const int firstV = tv.span[static_cast<size_t>(b0)] - mv + 1;
    Vec T[3][kMaxBasisCount];
    for (int s = 0; s < mv; ++s) {
      T[0][s] = T[1][s] = T[2][s] = Vec(0.0);
      for (int r = 0; r < mu; ++r) {
        const Vec& p = P[static_cast<size_t>(r) * cols + firstV + s];
        for (int d = 0; d < 3; ++d)
          if (needD[d]) T[d][s] += tu.row(d, r)[a] * p;
      }
    }
    for (int k = 0; k < 6; ++k) {
      if (!need[k]) continue;
      const int du = kPartialOrders[k][0], dv = kPartialOrders[k][1];
      const double* basisRows[kMaxBasisCount];
      for (int s = 0; s < mv; ++s) basisRows[s] = tv.row(dv, s) + b0;
      for (int c = 0; c < kCoords; ++c) {
        double t[kMaxBasisCount];
        for (int s = 0; s < mv; ++s) t[s] = T[du][s][c];
        contractRows(basisRows, t, mv, b1 - b0, row(k, c) + b0);
      }
    }
    b0 = b1;
  }
}

// The homogeneous partials of a rational row (coordinates 0-2: A, coordinate 3: W) become the
// surface's, in place, sample by sample (point_math.h rationalSurface).
template <class RowFn>
void rationalRows(const bool need[6], int samples, RowFn row) {
  for (int b = 0; b < samples; ++b) {
    glm::dvec3 q[6];
    double w[6];
    for (int k = 0; k < 6; ++k) {
      q[k] = need[k] ? glm::dvec3(row(k, 0)[b], row(k, 1)[b], row(k, 2)[b]) : glm::dvec3(0.0);
      w[k] = need[k] ? row(k, 3)[b] : 0.0;
    }
    pm::rationalSurface(q[0], q[1], q[2], q[3], q[4], q[5], w[0], w[1], w[2], w[3], w[4], w[5]);
    for (int k = 0; k < 6; ++k)
      if (need[k])
        for (int c = 0; c < 3; ++c) row(k, c)[b] = q[k][c];
  }
}

}  // namespace

void sampleCurveGrid(const Curve& curve, const GridSpec& grid, FieldMask fields, const ChunkConsumer& consumer,
                     const SamplerOptions& options) {
  if (fields & ~kCurveFields) throw std::invalid_argument("curves provide the fields point, d1 and d2 only");
  const std::vector<int> items = curveGridItems(curve);
  size_t first = 0, count = 0;
  checkGrid(grid, items.size(), false, first, count);
  const int S = grid.samplesU;
  const DirectionTable tab = tabulate(curve.basis(), S);
  const bool alphaEB = curve.model().family.construction == Construction::AlphaEB;
  const auto& knots = curve.spanKnots();
  const int firstSpan = curve.spans().first;
  const int n = static_cast<int>(curve.model().points.size());

  std::optional<KnotTables> knotTables;
  if (curve.usesKnotVector()) {
    const BSplineCurveData& d = curve.knotData();
    knotTables.emplace(d.order, d.knots, static_cast<int>(d.points.size()), S);
  }

  auto computeItem = [&](auto& out, KnotTable& scratch, size_t item, int aBegin, int aEnd, size_t point) {
    const int span = items[item];
    if (curve.usesKnotVector()) {
      const KnotTable& tab = knotTables->of(span, scratch);
      if (!tab.scaled) {
        const BSplineCurveData& d = curve.knotData();
        sampleKnotSpanRows(tab, d.points.data(), d.weights.empty() ? nullptr : d.weights.data(), aBegin, aEnd, point,
                           out);
        return;
      }
      for (int a = aBegin; a < aEnd; ++a, ++point) {
        const CurvePoint cp = curve.evaluate(span, gridParameter(a, S));
        out.put(Field::Point, point, cp.point), out.put(Field::D1, point, cp.d1), out.put(Field::D2, point, cp.d2);
      }
      return;
    }
    const glm::dvec3* P = curve.spanPoints().data() + span + curve.spanPointOffset();
    const double invH = knots.empty() ? 1.0 : 1.0 / (knots[span - firstSpan + 1] - knots[span - firstSpan]);
    SpanEnds ends;
    if (alphaEB) {
      const int j1 = (span + 1) % n;
      ends = {true, curve.alphaV()[span], curve.alphaV()[j1], curve.alphas()[span], curve.alphas()[j1]};
    }
    sampleSpanRows(tab, P, ends, invH, aBegin, aEnd, point, out);
  };
  auto compute = [&](auto&& out, size_t begin, size_t end, size_t firstPoint) {
    KnotTable scratch;  // a knot interval's table when the job's tables are over their budget
    forEachItemRows(begin, end, static_cast<size_t>(S), 1, firstPoint, [&](size_t item, int a0, int a1, size_t point) {
      computeItem(out, scratch, item, a0, a1, point);
    });
  };
  runChunked(ChunkPlan(first, count, static_cast<size_t>(S), 1, options.maxChunkPoints), fields, options, consumer,
             compute);
}

void sampleSurfaceGrid(const Surface& surface, const GridSpec& grid, FieldMask fields,
                       const ChunkConsumer& consumer, const SamplerOptions& options) {
  if (fields & ~kSurfaceFields)
    throw std::invalid_argument("surfaces provide the fields point, du, dv, duu, duv, dvv and normal only");
  const auto items = surfaceGridItems(surface);
  size_t first = 0, count = 0;
  checkGrid(grid, items.size(), true, first, count);
  const int Su = grid.samplesU, Sv = grid.samplesV;
  const DirectionTable tu = tabulate(surface.basisU(), Su), tv = tabulate(surface.basisV(), Sv);
  const SurfaceModel& model = surface.model();
  const bool alphaEB = model.family.construction == Construction::AlphaEB;
  const bool normal = wants(fields, Field::Normal);
  // Which partials of the base surface the requested fields need (α-EB second partials need the
  // first ones too, docs/math.md §5.3).
  const bool needUU = wants(fields, Field::Duu), needVV = wants(fields, Field::Dvv), needUV = wants(fields, Field::Duv);
  // A rational surface (weights) is sampled from its homogeneous net (w P, w): four coordinates,
  // then the quotient rule per sample, whose second partials use the first ones too.
  const bool rational = surface.usesKnotVector() && !surface.knotData().weights.empty();
  const bool needU = wants(fields, Field::Du) || normal || ((needUU || needUV) && (alphaEB || rational));
  const bool needV = wants(fields, Field::Dv) || normal || ((needVV || needUV) && (alphaEB || rational));
  const int mu = tu.count, mv = tv.count;
  static constexpr int kOutputField[6] = {int(Field::Point), int(Field::Du),  int(Field::Dv),
                                          int(Field::Duu),   int(Field::Duv), int(Field::Dvv)};
  const bool need[6] = {true, needU, needV, needUU, needUV, needVV};
  std::optional<KnotTables> knotsU, knotsV;
  std::vector<glm::dvec4> homogeneous;
  if (surface.usesKnotVector()) {
    const BSplineSurfaceData& d = surface.knotData();
    knotsU.emplace(d.orderU, d.knotsU, d.rows, Su);
    knotsV.emplace(d.orderV, d.knotsV, d.cols, Sv);
    for (size_t k = 0; rational && k < d.points.size(); ++k) homogeneous.emplace_back(d.weights[k] * d.points[k], d.weights[k]);
  }

  auto compute = [&](auto&& out, size_t rowBegin, size_t rowEnd, size_t firstPoint) {
    // Row buffers (structure of arrays over v samples): C, Cu, Cv, Cuu, Cuv, Cvv per coordinate.
    std::vector<double> rows(static_cast<size_t>(6 * 4) * Sv);  // coordinate 3: W of a rational surface
    auto row = [&](int k, int c) { return rows.data() + static_cast<size_t>(k * 4 + c) * Sv; };
    const double* fieldRows[kFieldCount][3] = {};  // the rows of each computed output field
    for (int k = 0; k < 6; ++k)
      if (need[k])
        for (int c = 0; c < 3; ++c) fieldRows[kOutputField[k]][c] = row(k, c);
    KnotTable scratchU, scratchV;  // knot interval tables when the job's are over their budget
    forEachItemRows(rowBegin, rowEnd, static_cast<size_t>(Su), static_cast<size_t>(Sv), firstPoint,
                    [&](size_t item, int aBegin, int aEnd, size_t point) {
      const auto [i, j] = items[item];
      const KnotTable* knotU = nullptr;
      const KnotTable* knotV = nullptr;
      if (surface.usesKnotVector()) {
        knotU = &knotsU->of(i, scratchU);
        knotV = &knotsV->of(j, scratchV);
      }
      if (knotU && (knotU->scaled || knotV->scaled)) {
        // Knot intervals near 1e-310: per point, through the scaled partials of evalBSplineSurface.
        for (int a = aBegin; a < aEnd; ++a)
          for (int b = 0; b < Sv; ++b, ++point) {
            const SurfacePoint sp = surface.evaluate(i, j, gridParameter(a, Su), gridParameter(b, Sv));
            out.put(Field::Point, point, sp.point), out.put(Field::Du, point, sp.du), out.put(Field::Dv, point, sp.dv);
            out.put(Field::Duu, point, sp.duu), out.put(Field::Duv, point, sp.duv);
            out.put(Field::Dvv, point, sp.dvv), out.put(Field::Normal, point, sp.normal);
          }
        return;
      }
      const int stride = knotU ? surface.knotData().cols : surface.netCols();
      const glm::dvec3* P = knotU ? surface.knotData().points.data()
                                  : surface.patchNet().data() + static_cast<size_t>(i + surface.netOffsetU()) * stride +
                                        (j + surface.netOffsetV());
      double alpha[4] = {0, 0, 0, 0};
      glm::dvec3 V[4] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
      if (alphaEB) {  // corners (i,j), (i,j+1), (i+1,j), (i+1,j+1), wrapped in closed directions
        const int i1 = (i + 1) % model.rows, j1 = (j + 1) % model.cols;
        const int idx[4] = {i * model.cols + j, i * model.cols + j1, i1 * model.cols + j, i1 * model.cols + j1};
        for (int k = 0; k < 4; ++k) alpha[k] = surface.alphas()[idx[k]], V[k] = surface.alphaV()[idx[k]];
      }
      for (int a = aBegin; a < aEnd; ++a) {
        if (knotU) {
          if (rational) {
            knotRowPartials(*knotU, *knotV, homogeneous.data(), stride, a, need, row);
            rationalRows(need, Sv, row);
          } else {
            knotRowPartials(*knotU, *knotV, P, stride, a, need, row);
          }
        } else {
          // u-contraction: T_d[s] = sum_r B_r^(d)(u_a) P[r][s].
          glm::dvec3 T[3][kMaxBasisCount];
          for (int s = 0; s < mv; ++s) {
            T[0][s] = T[1][s] = T[2][s] = glm::dvec3(0.0);
            for (int r = 0; r < mu; ++r) {
              const glm::dvec3& p = P[static_cast<size_t>(r) * stride + s];
              T[0][s] += tu.row(0, r)[a] * p;
              if (needU || needUV) T[1][s] += tu.row(1, r)[a] * p;
              if (needUU) T[2][s] += tu.row(2, r)[a] * p;
            }
          }
          // v-expansion over the whole row of samples: each needed (field, coordinate) row is one
          // register-accumulated contraction over the basis rows (contiguous, vectorisable).
          for (int k = 0; k < 6; ++k) {
            if (!need[k]) continue;
            const int du = kPartialOrders[k][0], dv = kPartialOrders[k][1];
            const double* basisRows[kMaxBasisCount];
            for (int s = 0; s < mv; ++s) basisRows[s] = tv.row(dv, s);
            for (int c = 0; c < 3; ++c) {
              double t[kMaxBasisCount];
              for (int s = 0; s < mv; ++s) t[s] = T[du][s][c];
              contractRows(basisRows, t, mv, Sv, row(k, c));
            }
          }
        }
        if (!alphaEB && !normal) {
          // Plain partials: the rows go out as they are (into interleaved planes, or records).
          out.putRows(fieldRows, Sv, point);
          point += static_cast<size_t>(Sv);
          continue;
        }
        const pm::BlendFactors fu = pm::blendFactors(tu.blend[a]);
        const double uA = gridParameter(a, Su);
        for (int b = 0; b < Sv; ++b, ++point) {
          glm::dvec3 q[6];
          for (int k = 0; k < 6; ++k) q[k] = need[k] ? glm::dvec3(row(k, 0)[b], row(k, 1)[b], row(k, 2)[b]) : glm::dvec3(0.0);
          if (alphaEB) {
            // docs/math.md §5.3, only the orders the requested fields need (need[] already includes
            // the first partials that α-EB second partials use); the skipped ones feed no output.
            const pm::BlendFactors fv = pm::blendFactors(tv.blend[b]);
            pm::AlphaEBWeights w = pm::alphaEBWeightsZero();
            pm::cornerBlend(fu.f00, fu.f01, fv.f00, fv.f01, alpha, V, w.a00, w.L00);
            if (need[1]) pm::cornerBlend(fu.f10, fu.f11, fv.f00, fv.f01, alpha, V, w.a10, w.L10);
            if (need[2]) pm::cornerBlend(fu.f00, fu.f01, fv.f10, fv.f11, alpha, V, w.a01, w.L01);
            if (need[3]) pm::cornerBlend(fu.f20, fu.f21, fv.f00, fv.f01, alpha, V, w.a20, w.L20);
            if (need[4]) pm::cornerBlend(fu.f10, fu.f11, fv.f10, fv.f11, alpha, V, w.a11, w.L11);
            if (need[5]) pm::cornerBlend(fu.f00, fu.f01, fv.f20, fv.f21, alpha, V, w.a02, w.L02);
            if (need[3] || need[4] || need[5]) pm::alphaEBBlendSecond(w, q[0], q[1], q[2], q[3], q[4], q[5]);
            pm::alphaEBBlendFirst(w, q[0], q[1], q[2]);
          }
          for (int k = 0; k < 6; ++k) out.put(static_cast<Field>(kOutputField[k]), point, q[k]);
          if (normal) {
            const bool corner = (a == 0 || a == Su - 1) && (b == 0 || b == Sv - 1);
            glm::dvec3 n;
            // Corners of α-EB patches and degenerate crosses follow the full §5.3 convention.
            if ((alphaEB && corner) || !unitNormal(q[1], q[2], n))
              out.put(Field::Normal, point, surface.evaluate(i, j, uA, gridParameter(b, Sv)).normal);
            else
              out.put(Field::Normal, point, n);
          }
        }
      }
    });
  };
  runChunked(ChunkPlan(first, count, static_cast<size_t>(Su), static_cast<size_t>(Sv), options.maxChunkPoints), fields,
             options, consumer, compute);
}

}  // namespace shapespline
