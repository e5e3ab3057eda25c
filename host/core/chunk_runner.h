#pragma once
// The CPU grid samplers' chunk machinery (core/grid_sampler.cpp; private to core): the chunk plan
// of a job, chunk buffers, where computed rows go (a chunk's planes or a record sink's blocks), and
// runChunked, the worker pool that fills chunks ahead of the consumer. The row kernels stay in
// grid_sampler.cpp.
#include <shapespline/core/cores.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/point_records.h>
#include <shapespline/core/sample_grid.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <condition_variable>
#include <exception>
#include <iterator>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace shapespline::sampler {

// dst[3b + c] = (x, y, z)[c][b] (grid_sampler.cpp: AVX2 where the CPU has it).
void interleaveRows(const double* x, const double* y, const double* z, int n, double* dst);

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

inline void put(double* plane, size_t point, const glm::dvec3& v) {
  if (!plane) return;
  plane[point * 3 + 0] = v.x;
  plane[point * 3 + 1] = v.y;
  plane[point * 3 + 2] = v.z;
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
  // The job's own planes (SamplerOptions::jobPlanes), from job point `first` on.
  PlaneOut(const std::array<double*, kFieldCount>& planes, size_t first) {
    for (int f = 0; f < kFieldCount; ++f) plane[f] = planes[f] ? planes[f] + first * 3 : nullptr;
  }
  void put(Field f, size_t point, const glm::dvec3& v) const { sampler::put(plane[static_cast<int>(f)], point, v); }
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
inline GridChunk deliverable(const ChunkPlan& plan, const ChunkBuffer* buffer, size_t chunk) {
  GridChunk out = plan.chunk(chunk);
  out.precision = Precision::Double;
  if (buffer)
    for (int f = 0; f < kFieldCount; ++f) out.planes[f] = buffer->plane(static_cast<Field>(f));
  return out;
}

// The job point of chunk `chunk`'s first point (its offset in SamplerOptions::jobPlanes).
inline size_t jobPointOf(const ChunkPlan& plan, size_t chunk) {
  return (plan.rows(chunk).first - plan.firstItem * plan.rowsPerItem) * plan.pointsPerRow;
}

// Whether the workers write the job's planes: given for every sampled field (and only those).
inline bool usesJobPlanes(const SamplerOptions& options, FieldMask fields) {
  FieldMask given = 0;
  for (int f = 0; f < kFieldCount; ++f)
    if (options.jobPlanes[f]) given |= fieldBit(static_cast<Field>(f));
  if (given == 0) return false;
  if (given != fields) throw std::invalid_argument("jobPlanes must be given for exactly the sampled fields");
  return true;
}

// The sink the workers encode records into, or nullptr: without one, or when one row of points
// does not fit a block (then the slices carry the records, cut to the blocks' size).
inline const RecordSink* usableSink(const SamplerOptions& options, FieldMask fields, size_t pointsPerRow) {
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

// The fewest points of a job per default worker, about 0.3 ms of sampling (bicubic, points only): a
// batch of 1,000 models of 25,600 points each started a worker and a writer thread per model for
// 0.25 ms of sampling (docs/performance.md, batches).
constexpr size_t kMinWorkerPoints = 32768;

// Runs compute(out, rowBegin, rowEnd, firstPointInChunk) over every chunk of `plan` (`out`: a
// PlaneOut over a chunk buffer or, with a record sink, a RecordOut over one of its blocks), each chunk's
// rows split into one slice per worker (threads share the rows of one patch just as they share
// whole patches), and hands finished chunks to the consumer in order on the calling thread while
// the workers fill the other buffers. The workers live for the whole job (no thread start per
// chunk), so chunks can be small enough for their buffers to stay in cache. A job that one worker
// does in one chunk runs on the calling thread.
template <class Compute>
void runChunked(const ChunkPlan& plan, FieldMask fields, const SamplerOptions& options, const ChunkConsumer& consumer,
                Compute compute) {
  if (plan.itemCount == 0) return;
  const RecordSink* sink = usableSink(options, fields, plan.pointsPerRow);
  // By default a worker per core, less the cores a record sink keeps busy: on two cores, two
  // workers beside the sink's writer thread made the e2e .f32 job 10% slower than one (3 runs of
  // 16 interleaved pairs; the three threads preempted each other).
  const int cores = availableCores();
  // By default, too, a worker per kMinWorkerPoints of the job at most: a thread's start and wake-ups
  // (tens of microseconds each on a VM) outweigh what it computes for a small job.
  const size_t jobPoints = plan.itemCount * plan.rowsPerItem * plan.pointsPerRow;
  const size_t freeCores = static_cast<size_t>(std::max(1, cores - (sink ? sink->ownThreads : 0)));
  const size_t worthThreads = std::max<size_t>(1, jobPoints / kMinWorkerPoints);
  const size_t threads =
      options.threads > 0 ? static_cast<size_t>(options.threads) : std::min(freeCores, worthThreads);
  const size_t chunkCount = plan.chunkCount();
  const size_t maxRows = plan.itemsPerChunk ? plan.itemsPerChunk * plan.rowsPerItem : plan.rowsPerChunk;
  const size_t workers = std::min(threads, maxRows);
  const bool onCaller = workers == 1 && chunkCount == 1;  // nothing to overlap: no thread
  // Without a record sink, the job's own planes when the caller gives them, else chunk buffers.
  const bool direct = !sink && usesJobPlanes(options, fields);
  ChunkBuffer buffers[kChunkBuffers];
  if (!direct)
    for (auto& b : buffers) b.allocate(fields, plan.capacityPoints());
  auto planesOf = [&](size_t chunk) {
    return direct ? PlaneOut(options.jobPlanes, jobPointOf(plan, chunk)) : PlaneOut(buffers[chunk % kChunkBuffers]);
  };
  auto delivered = [&](size_t chunk) {
    if (!direct) return deliverable(plan, &buffers[chunk % kChunkBuffers], chunk);
    GridChunk out = deliverable(plan, nullptr, chunk);
    const PlaneOut at = planesOf(chunk);
    for (int f = 0; f < kFieldCount; ++f) out.planes[f] = at.plane[f];
    return out;
  };

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
          compute(planesOf(chunk), b, e, (b - begin) * plan.pointsPerRow);
          if (options.slice) options.slice(delivered(chunk), (b - begin) * plan.pointsPerRow, (e - b) * plan.pointsPerRow);
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
    if (onCaller) work(0);
    else
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
    const GridChunk out = sink ? deliverable(plan, nullptr, chunk) : delivered(chunk);
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

}  // namespace shapespline::sampler
