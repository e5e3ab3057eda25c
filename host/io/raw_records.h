#pragma once
// The raw record path shared by the .f32/.f64 writer, the .npy writer and `merge`: one record per
// point, every requested field in Field order, x y z each, little-endian fp32 or fp64.
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

// Stores v at e as a little-endian fp64 or fp32 (rounded once) and returns the end: the one value
// encoding of the binary sample files (raw, .npy, binary PLY).
inline char* putBinaryValue(char* e, double v, bool float64) {
  if (float64) {
    std::memcpy(e, &v, 8);
    return e + 8;
  }
  const float x = static_cast<float>(v);
  std::memcpy(e, &x, 4);
  return e + 4;
}

// The fields of `mask` in record order.
std::vector<Field> recordFields(FieldMask mask);
// Appends the records of every point of `chunk` to `out`.
void writeRecords(AtomicFile& out, const GridChunk& chunk, const std::vector<Field>& fields, bool float64);
// The records of a raw or .npy file placed by point index (record k of the file at base + k x
// record size), written by an io::BlockWriter thread: from the sampler's workers (slice(),
// SampleWriter::writeSlice) or, when the caller delivers no slices, from consume(). Chunks must be
// of the layout's items; finish() before the file is committed.
class PlacedRecords {
 public:
  PlacedRecords() = default;
  ~PlacedRecords();
  void begin(AtomicFile& out, const SampleLayout& layout, const std::vector<Field>& fields, bool float64, uint64_t base);
  // True when every value lies in the finite range of the file's precision (SampleWriter::writeSlice).
  bool slice(const GridChunk& chunk, size_t first, size_t count);
  void consume(const GridChunk& chunk);
  void finish();

 private:
  uint64_t offsetOf(const GridChunk& chunk, size_t first) const;
  const SampleLayout* layout_ = nullptr;
  std::vector<Field> fields_;
  bool float64_ = true;
  uint64_t base_ = 0;
  size_t recordBytes_ = 0;
  std::atomic<bool> sliced_{false};
  std::unique_ptr<BlockWriter> writer_;
};

// The NumPy format 1.0 header (NEP 1, numpy.lib.format) of `records` raw records of `fieldNames`:
// magic, version 1.0, header length, then the dict {'descr': [('point', '<f8', (3,)), ...],
// 'fortran_order': False, 'shape': (records,), } padded with spaces and a newline to a multiple of
// 64 bytes. The data that follows is byte for byte the raw file's.
std::string npyHeader(const std::vector<std::string>& fieldNames, bool float64, uint64_t records);

}  // namespace shapespline::io
