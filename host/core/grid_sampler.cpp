#include <shapespline/core/grid_sampler.h>

#include <shapespline/core/point_math.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <mutex>
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

// Output planes of one chunk buffer: plane[f] holds 3 doubles per point, or is empty.
struct ChunkBuffer {
  std::vector<double> planes[kFieldCount];
  void allocate(FieldMask fields, size_t points) {
    for (int f = 0; f < kFieldCount; ++f)
      if (fields & (1u << f)) planes[f].resize(points * 3);
  }
  double* plane(Field f) {
    auto& p = planes[static_cast<int>(f)];
    return p.empty() ? nullptr : p.data();
  }
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

// Chunk `chunk` of `plan` as delivered: its item/row range over the planes of `buffer`.
GridChunk deliverable(const ChunkPlan& plan, ChunkBuffer& buffer, size_t chunk) {
  GridChunk out = plan.chunk(chunk);
  out.precision = Precision::Double;
  for (int f = 0; f < kFieldCount; ++f) out.planes[f] = buffer.plane(static_cast<Field>(f));
  return out;
}

// Runs compute(buffer, rowBegin, rowEnd, firstPointInBuffer) over every chunk of `plan`, each chunk's
// rows split into one slice per worker (threads share the rows of one patch just as they share
// whole patches), and hands finished chunks to the consumer in order on the calling thread while
// the workers fill the other buffer. The workers live for the whole job (no thread start per
// chunk), so chunks can be small enough for their buffers to stay in cache.
template <class Compute>
void runChunked(const ChunkPlan& plan, FieldMask fields, const SamplerOptions& options, const ChunkConsumer& consumer,
                Compute compute) {
  if (plan.itemCount == 0) return;
  const int threads = options.threads > 0 ? options.threads
                                          : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const size_t chunkCount = plan.chunkCount();
  const size_t maxRows = plan.itemsPerChunk ? plan.itemsPerChunk * plan.rowsPerItem : plan.rowsPerChunk;
  const size_t workers = std::min<size_t>(static_cast<size_t>(threads), maxRows);
  ChunkBuffer buffers[2];
  for (auto& b : buffers) b.allocate(fields, plan.capacityPoints());

  // Shared state: slices finished per chunk, chunks consumed, and the first failure.
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<size_t> slicesDone(chunkCount, 0);
  size_t consumed = 0;
  bool stop = false;
  std::exception_ptr failure;

  auto work = [&](size_t w) {
    for (size_t chunk = 0; chunk < chunkCount; ++chunk) {
      {
        // Buffer chunk % 2 is free once chunk - 2 has been consumed.
        std::unique_lock lock(mutex);
        changed.wait(lock, [&] { return stop || consumed + 2 > chunk; });
        if (stop) return;
      }
      const auto [begin, end] = plan.rows(chunk);
      const size_t n = end - begin;
      const size_t b = begin + n * w / workers, e = begin + n * (w + 1) / workers;
      try {
        if (b < e) {
          compute(buffers[chunk % 2], b, e, (b - begin) * plan.pointsPerRow);
          if (options.slice) {
            options.slice(deliverable(plan, buffers[chunk % 2], chunk), (b - begin) * plan.pointsPerRow,
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
    const GridChunk out = deliverable(plan, buffers[chunk % 2], chunk);
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
void sampleSpanRows(const DirectionTable& tab, const glm::dvec3* P, const SpanEnds& ends, double invH, int aBegin,
                    int aEnd, size_t point, double* outP, double* outD1, double* outD2) {
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
    put(outP, point, c0);
    put(outD1, point, c1 * invH);
    put(outD2, point, c2 * (invH * invH));
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

  auto computeItem = [&](ChunkBuffer& buffer, size_t item, int aBegin, int aEnd, size_t point) {
    double* outP = buffer.plane(Field::Point);
    double* outD1 = buffer.plane(Field::D1);
    double* outD2 = buffer.plane(Field::D2);
    const int span = items[item];
    if (curve.usesKnotVector()) {
      for (int a = aBegin; a < aEnd; ++a, ++point) {
        const CurvePoint cp = curve.evaluate(span, gridParameter(a, S));
        put(outP, point, cp.point), put(outD1, point, cp.d1), put(outD2, point, cp.d2);
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
    sampleSpanRows(tab, P, ends, invH, aBegin, aEnd, point, outP, outD1, outD2);
  };
  auto compute = [&](ChunkBuffer& buffer, size_t begin, size_t end, size_t firstPoint) {
    forEachItemRows(begin, end, static_cast<size_t>(S), 1, firstPoint, [&](size_t item, int a0, int a1, size_t point) {
      computeItem(buffer, item, a0, a1, point);
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
  const bool needU = wants(fields, Field::Du) || normal || ((needUU || needUV) && alphaEB);
  const bool needV = wants(fields, Field::Dv) || normal || ((needVV || needUV) && alphaEB);
  const int mu = tu.count, mv = tv.count;
  // Row k of the v-expansion is the partial of u-order kOrders[k][0] and v-order kOrders[k][1].
  static constexpr int kOrders[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
  static constexpr int kOutputField[6] = {int(Field::Point), int(Field::Du),  int(Field::Dv),
                                          int(Field::Duu),   int(Field::Duv), int(Field::Dvv)};
  const bool need[6] = {true, needU, needV, needUU, needUV, needVV};

  auto compute = [&](ChunkBuffer& buffer, size_t rowBegin, size_t rowEnd, size_t firstPoint) {
    double* out[kFieldCount];
    for (int f = 0; f < kFieldCount; ++f) out[f] = buffer.plane(static_cast<Field>(f));
    // Row buffers (structure of arrays over v samples): C, Cu, Cv, Cuu, Cuv, Cvv per coordinate.
    std::vector<double> rows(static_cast<size_t>(6 * 3) * Sv);
    auto row = [&](int k, int c) { return rows.data() + static_cast<size_t>(k * 3 + c) * Sv; };
    forEachItemRows(rowBegin, rowEnd, static_cast<size_t>(Su), static_cast<size_t>(Sv), firstPoint,
                    [&](size_t item, int aBegin, int aEnd, size_t point) {
      const auto [i, j] = items[item];
      if (surface.usesKnotVector()) {
        for (int a = aBegin; a < aEnd; ++a)
          for (int b = 0; b < Sv; ++b, ++point) {
            const SurfacePoint sp = surface.evaluate(i, j, gridParameter(a, Su), gridParameter(b, Sv));
            put(out[0], point, sp.point), put(out[int(Field::Du)], point, sp.du), put(out[int(Field::Dv)], point, sp.dv);
            put(out[int(Field::Duu)], point, sp.duu), put(out[int(Field::Duv)], point, sp.duv);
            put(out[int(Field::Dvv)], point, sp.dvv), put(out[int(Field::Normal)], point, sp.normal);
          }
        return;
      }
      const int stride = surface.netCols();
      const glm::dvec3* P = surface.patchNet().data() + static_cast<size_t>(i + surface.netOffsetU()) * stride +
                            (j + surface.netOffsetV());
      double alpha[4] = {0, 0, 0, 0};
      glm::dvec3 V[4] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
      if (alphaEB) {  // corners (i,j), (i,j+1), (i+1,j), (i+1,j+1), wrapped in closed directions
        const int i1 = (i + 1) % model.rows, j1 = (j + 1) % model.cols;
        const int idx[4] = {i * model.cols + j, i * model.cols + j1, i1 * model.cols + j, i1 * model.cols + j1};
        for (int k = 0; k < 4; ++k) alpha[k] = surface.alphas()[idx[k]], V[k] = surface.alphaV()[idx[k]];
      }
      for (int a = aBegin; a < aEnd; ++a) {
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
          const int du = kOrders[k][0], dv = kOrders[k][1];
          const double* basisRows[kMaxBasisCount];
          for (int s = 0; s < mv; ++s) basisRows[s] = tv.row(dv, s);
          for (int c = 0; c < 3; ++c) {
            double t[kMaxBasisCount];
            for (int s = 0; s < mv; ++s) t[s] = T[du][s][c];
            contractRows(basisRows, t, mv, Sv, row(k, c));
          }
        }
        if (!alphaEB && !normal) {
          // Plain partials: copy the rows into the interleaved xyz planes.
          for (int k = 0; k < 6; ++k) {
            double* plane = out[kOutputField[k]];
            if (!plane) continue;
            interleaveRows(row(k, 0), row(k, 1), row(k, 2), Sv, plane + point * 3);
          }
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
          put(out[int(Field::Point)], point, q[0]);
          put(out[int(Field::Du)], point, q[1]);
          put(out[int(Field::Dv)], point, q[2]);
          put(out[int(Field::Duu)], point, q[3]);
          put(out[int(Field::Duv)], point, q[4]);
          put(out[int(Field::Dvv)], point, q[5]);
          if (normal) {
            const bool corner = (a == 0 || a == Su - 1) && (b == 0 || b == Sv - 1);
            glm::dvec3 n;
            // Corners of α-EB patches and degenerate crosses follow the full §5.3 convention.
            if ((alphaEB && corner) || !unitNormal(q[1], q[2], n))
              put(out[int(Field::Normal)], point, surface.evaluate(i, j, uA, gridParameter(b, Sv)).normal);
            else
              put(out[int(Field::Normal)], point, n);
          }
        }
      }
    });
  };
  runChunked(ChunkPlan(first, count, static_cast<size_t>(Su), static_cast<size_t>(Sv), options.maxChunkPoints), fields,
             options, consumer, compute);
}

}  // namespace shapespline
