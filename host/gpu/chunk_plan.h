#pragma once
// Internal to host/gpu: how a grid job (core/sample_grid.h GridSpec) is cut into chunks. A chunk is
// a whole number of items (spans/patches) whose output planes each fit the plane budget, or, for an
// item larger than that, a range of its rows in whole kernel invocations, so device and host memory
// are bounded by the budget and not by the grid. Also the run length of the grid kernels
// (surface_grid.comp / curve_grid.comp: RUN_LENGTH samples per invocation).
#include <shapespline/core/sample_grid.h>

#include <cstddef>
#include <cstdint>

namespace shapespline::gpu {

// Samples per invocation of the grid kernels for a job with this grid and fields.
uint32_t gridRunLength(const GridSpec& grid, FieldMask fields, bool surface);

struct ChunkPlan {
  size_t firstItem = 0, items = 0;  // the job's items
  size_t pointsPerItem = 0, rowsPerItem = 0, pointsPerRow = 0;
  size_t itemsPerChunk = 0;  // whole items per chunk, or 0: row ranges of one item
  size_t rowsPerChunk = 0;   // rows per row-range chunk (itemsPerChunk == 0)
  size_t chunkPoints = 0;    // points of the largest chunk (plane size)
  size_t chunkCount = 0;
  Precision precision = Precision::Float;

  // Chunk c as delivered to the consumer (planes left empty).
  GridChunk chunk(size_t c) const;
};

// granuleRows: rows the kernel evaluates together (a chunk of row ranges holds a multiple);
// budgetBytes: the plane budget; hardLimit: the device's maxStorageBufferRange (throws
// std::length_error when one granule does not fit it).
ChunkPlan planGridChunks(const GridSpec& grid, size_t items, bool surface, size_t granuleRows, size_t realBytes,
                         size_t budgetBytes, size_t hardLimit, Precision precision);

}  // namespace shapespline::gpu
