#include <shapespline/gpu/chunk_plan.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace shapespline::gpu {

uint32_t gridRunLength(const GridSpec& grid, FieldMask fields, bool surface) {
  // Rows (curves: spans) of up to 256 samples go whole to one invocation, several consecutive rows
  // of a patch (spans) per invocation while that stays within 512 samples (the net is then gathered
  // once per several rows: measured on lavapipe, bicubic P/du/dv at S = 32 runs 1.5x faster with 16
  // rows per invocation than with 4); longer rows are split into the longest run of 64, 32, 16, 8
  // or 4 samples dividing them.
  const uint32_t su = uint32_t(grid.samplesU), sv = uint32_t(grid.samplesV);
  const uint32_t rowLength = surface ? sv : su;
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
    while (rows < maxRows && (!surface || su % (rows * 2) == 0) && rowLength * rows * 2 <= maxRun) rows *= 2;
    run = rowLength * rows;
  }
  return run;
}

ChunkPlan planGridChunks(const GridSpec& grid, size_t items, bool surface, size_t granuleRows, size_t rs,
                         size_t budgetBytes, size_t hardLimit, Precision precision) {
  ChunkPlan p;
  p.firstItem = grid.firstItem;
  p.items = items;
  p.precision = precision;
  p.pointsPerItem = grid.pointsPerItem();
  p.rowsPerItem = size_t(grid.samplesU);
  p.pointsPerRow = surface ? size_t(grid.samplesV) : 1u;
  // Only the device's maxStorageBufferRange is a hard limit (one granule of rows must fit).
  const size_t rowBytes = p.pointsPerRow * 3 * rs, itemPlaneBytes = p.pointsPerItem * 3 * rs;
  const size_t cap = std::min(budgetBytes, hardLimit), usable = cap > 4 * rs ? cap - 4 * rs : 0;
  if (itemPlaneBytes <= usable) {
    p.itemsPerChunk = std::min(items, usable / itemPlaneBytes);
  } else {
    p.rowsPerChunk = std::max(granuleRows, usable / rowBytes / granuleRows * granuleRows);
    if (p.rowsPerChunk >= p.rowsPerItem) p.itemsPerChunk = 1, p.rowsPerChunk = 0;  // the kernel takes it whole
  }
  p.chunkPoints = p.itemsPerChunk ? p.itemsPerChunk * p.pointsPerItem : p.rowsPerChunk * p.pointsPerRow;
  if (p.chunkPoints * 3 * rs + 4 * rs > hardLimit)
    throw std::length_error("evaluateGrid: a chunk's plane (" + std::to_string(p.chunkPoints * 3 * rs) +
                            " bytes) exceeds the device's maxStorageBufferRange " + std::to_string(hardLimit));
  const size_t chunksPerItem = p.rowsPerChunk ? (p.rowsPerItem + p.rowsPerChunk - 1) / p.rowsPerChunk : 1;
  p.chunkCount = p.itemsPerChunk ? (items + p.itemsPerChunk - 1) / p.itemsPerChunk : items * chunksPerItem;
  return p;
}

GridChunk ChunkPlan::chunk(size_t c) const {
  GridChunk out;
  out.pointsPerItem = pointsPerItem;
  out.pointsPerRow = pointsPerRow;
  out.precision = precision;
  if (itemsPerChunk) {
    out.firstItem = firstItem + c * itemsPerChunk;
    out.itemCount = std::min(itemsPerChunk, firstItem + items - out.firstItem);
  } else {
    const size_t chunksPerItem = (rowsPerItem + rowsPerChunk - 1) / rowsPerChunk;
    out.firstItem = firstItem + c / chunksPerItem;
    out.itemCount = 1;
    out.firstRow = (c % chunksPerItem) * rowsPerChunk;
    out.rowCount = std::min(rowsPerChunk, rowsPerItem - out.firstRow);
  }
  return out;
}

}  // namespace shapespline::gpu
