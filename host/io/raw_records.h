#pragma once
// The raw record path shared by the .f32/.f64 writer, the .npy writer and `merge`: one record per
// point, every requested field in Field order, x y z each, little-endian fp32 or fp64.
#include <shapespline/core/point_records.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/block_writer.h>
#include <shapespline/io/sample_writer.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace shapespline::io {

// The fields of `mask` in record order (the record encoding itself: core/point_records.h).
std::vector<Field> recordFields(FieldMask mask);

// The records of a raw or .npy file placed by point index (record k of the file at base + k x
// record size), written by an io::BlockWriter (on a thread of its own unless the job fits one
// block). They come from the CPU sampler's workers, encoded as they compute (sink(),
// SampleWriter::recordSink), or from any sampler's chunk planes: per slice (slice(),
// SampleWriter::writeSlice) or, when the caller delivers neither, from consume(). Chunks must be of
// the layout's items; finish() before the file is committed.
class PlacedRecords {
 public:
  PlacedRecords() = default;
  ~PlacedRecords();
  void begin(AtomicFile& out, const SampleLayout& layout, const std::vector<Field>& fields, bool float64, uint64_t base);
  // True when every value lies in the finite range of the file's precision (SampleWriter::writeSlice).
  bool slice(const GridChunk& chunk, size_t first, size_t count);
  void consume(const GridChunk& chunk);
  // Blocks of this file for the CPU sampler's records (core/sample_grid.h RecordSink); valid until
  // finish().
  RecordSink sink();
  void finish();

 private:
  uint64_t offsetOf(const GridChunk& chunk, size_t first) const;
  bool writeAt(const GridChunk& chunk, size_t first, size_t count);
  const SampleLayout* layout_ = nullptr;
  std::vector<Field> fields_;
  bool float64_ = true;
  uint64_t base_ = 0;
  size_t recordBytes_ = 0;
  std::atomic<bool> written_{false};  // records came from slices or a sink: consume() adds none
  std::unique_ptr<BlockWriter> writer_;
};

// The NumPy format 1.0 header (NEP 1, numpy.lib.format) of `records` raw records of `fieldNames`:
// magic, version 1.0, header length, then the dict {'descr': [('point', '<f8', (3,)), ...],
// 'fortran_order': False, 'shape': (records,), } padded with spaces and a newline to a multiple of
// 64 bytes. The data that follows is byte for byte the raw file's.
std::string npyHeader(const std::vector<std::string>& fieldNames, bool float64, uint64_t records);
// The same with each field's own number of components: ("uv", 2), ("point", 3), ...
std::string npyHeader(const std::vector<std::pair<std::string, int>>& fields, bool float64, uint64_t records);
// The same for a plain C-order float64 array of `shape` (what numpy.save writes for one).
std::string npyArrayHeader(const std::vector<uint64_t>& shape);

}  // namespace shapespline::io
