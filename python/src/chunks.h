#pragma once
// sample_chunks(): a grid job streamed chunk by chunk in bounded memory. A producer thread runs
// sampling::Session::sampleGrid on a snapshot of the model; its consumer copies each chunk (in the
// output precision) into a bounded queue and waits while the queue is full, so at most
// capacity + 2 chunks exist at once (the queue, the one being filled, the one Python holds).
// Closing the iterator (or dropping it) cancels the job. No Python object is touched off the
// calling thread; the GIL is released while waiting.
#include <shapespline/core/sample_grid.h>
#include <shapespline/sampling/report.h>

#include <array>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace shapespline::python {

struct ChunkData {
  size_t firstItem = 0, itemCount = 0, firstRow = 0, rowCount = 0;
  size_t firstPoint = 0;  // index of the chunk's first point in the whole job
  size_t points = 0;
  std::array<std::vector<double>, kFieldCount> f64;
  std::array<std::vector<float>, kFieldCount> f32;
};

class ChunkStream {
 public:
  using Job = std::function<sampling::Report(const ChunkConsumer&)>;
  // grid: the job's grid (firstItem and pointsPerItem place each chunk); starts the producer.
  ChunkStream(Job job, const GridSpec& grid, FieldMask fields, Precision output, size_t capacity, bool surface);
  ~ChunkStream();
  ChunkStream(const ChunkStream&) = delete;
  ChunkStream& operator=(const ChunkStream&) = delete;

  // The next chunk, or nullopt at the end; rethrows the job's exception. Blocks (call without the GIL).
  std::optional<ChunkData> next();
  // Cancels the job and waits for the producer (idempotent).
  void close();
  std::optional<sampling::Report> report() const;
  FieldMask fields() const { return fields_; }
  Precision precision() const { return output_; }
  bool surface() const { return surface_; }

 private:
  void consume(const GridChunk& chunk);

  GridSpec grid_;
  FieldMask fields_;
  Precision output_;
  size_t capacity_;
  bool surface_;
  mutable std::mutex mutex_;
  std::condition_variable space_, data_;
  std::deque<ChunkData> queue_;
  bool done_ = false, cancel_ = false;
  std::exception_ptr error_;
  std::optional<sampling::Report> report_;
  std::thread producer_;
};

}  // namespace shapespline::python
