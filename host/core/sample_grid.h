#pragma once
// Regular sample grids and the chunk type every sampler (CPU fp64, Vulkan fp32/fp64) delivers.
//
// A grid places S samples on each curve span (t_s = s/(S-1), both ends included) or Su x Sv samples
// on each surface patch (u_a = a/(Su-1), v_b = b/(Sv-1)), so neighbouring spans/patches repeat
// their shared edge samples: every span/patch is a self-contained block, which is what lets a job be
// split into shards of whole items and lets a mesh writer emit each patch on its own (its faces
// are index arithmetic, so they need no points of an earlier chunk when a patch spans several).
// Items are spans (curves) or patches (surfaces, row-major over the patch range, u outer).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace shapespline {

enum class Field : uint32_t { Point = 0, D1, D2, Du, Dv, Duu, Duv, Dvv, Normal, Count };
inline constexpr int kFieldCount = static_cast<int>(Field::Count);
using FieldMask = uint32_t;
constexpr FieldMask fieldBit(Field f) { return 1u << static_cast<uint32_t>(f); }
// Every field a curve / a surface has.
inline constexpr FieldMask kCurveFields = fieldBit(Field::Point) | fieldBit(Field::D1) | fieldBit(Field::D2);
inline constexpr FieldMask kSurfaceFields = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv) |
                                            fieldBit(Field::Duu) | fieldBit(Field::Duv) | fieldBit(Field::Dvv) |
                                            fieldBit(Field::Normal);

enum class Precision { Float, Double };

struct GridSpec {
  int samplesU = 2;        // per span (curves) or per patch along u (surfaces); >= 2
  int samplesV = 1;        // per patch along v (surfaces); 1 for curves
  size_t firstItem = 0;    // first span/patch (index into the model's item list, 0-based)
  size_t itemCount = 0;    // 0 = all items from firstItem on
  size_t pointsPerItem() const { return static_cast<size_t>(samplesU) * static_cast<size_t>(samplesV); }
};

// One block of consecutive points of a job: whole items, or a range of rows of one item when the
// item alone exceeds the chunk budget (so memory stays bounded whatever the grid). A row is sample
// a of a patch (its Sv points b = 0..Sv-1) or one sample of a span (pointsPerRow = 1). Chunks come
// in item order and, within an item, in row order; the points of a job are the same sequence
// however it is cut. Each requested field is a tightly packed xyz plane (3 values per point; point
// p of the chunk is point pointInItem(p) = a * samplesV + b of item itemOf(p)).
struct GridChunk {
  size_t firstItem = 0;
  size_t itemCount = 0;       // items the chunk touches (1 for a row range)
  size_t pointsPerItem = 0;
  size_t firstRow = 0;        // row range [firstRow, firstRow + rowCount) of item firstItem ...
  size_t rowCount = 0;        // ... or 0: itemCount whole items
  size_t pointsPerRow = 1;    // samplesV (curves: 1)
  Precision precision = Precision::Double;
  std::array<const void*, kFieldCount> planes{};  // nullptr where the field was not requested

  bool partial() const { return rowCount != 0; }
  size_t pointCount() const { return partial() ? rowCount * pointsPerRow : itemCount * pointsPerItem; }
  // Index inside item firstItem of the chunk's first point (0 for whole items).
  size_t firstItemPoint() const { return partial() ? firstRow * pointsPerRow : 0; }
  size_t itemOf(size_t p) const { return firstItem + (firstItemPoint() + p) / pointsPerItem; }
  size_t pointInItem(size_t p) const { return (firstItemPoint() + p) % pointsPerItem; }
  // True when the chunk's last point is the last point of its item (always for whole items).
  bool endsItem() const { return !partial() || firstItemPoint() + pointCount() == pointsPerItem; }
  bool has(Field f) const { return planes[static_cast<size_t>(f)] != nullptr; }
  double coord(Field f, size_t point, int axis) const {
    const void* p = planes[static_cast<size_t>(f)];
    const size_t i = point * 3 + static_cast<size_t>(axis);
    return precision == Precision::Double ? static_cast<const double*>(p)[i]
                                          : static_cast<double>(static_cast<const float*>(p)[i]);
  }
};

// Receives chunks in increasing item order; the data is valid only during the call.
using ChunkConsumer = std::function<void(const GridChunk&)>;
// Called by the sampler's worker that computed points [first, first + count) of `chunk` (only those points of
// its planes hold values yet), concurrently with the other workers' slices of the chunk and with the
// consumer of the previous chunk; the chunk then goes to the consumer as usual. For per-point work
// that needs no order (checks, conversion into a file at a known offset): it runs on every core,
// with the values still in the cache of the core that computed them.
using SliceConsumer = std::function<void(const GridChunk& chunk, size_t first, size_t count)>;

// A file whose records the CPU sampler writes itself (core/point_records.h encoding): its workers
// encode each row of points as they compute it, straight from their registers and row buffers
// into a block of the file, instead of filling planes that a slice consumer then reads again to
// convert (the e2e .f32 job's largest stage besides the kernel's copy into the page cache).
// acquire() and submit() are called by the workers, concurrently; each submit() gives a block
// back with the records of points [first, first + count) of `chunk` at its start.
struct RecordBlock {
  char* data = nullptr;
  size_t token = 0;  // the sink's own
};
struct RecordSink {
  std::vector<Field> fields;  // a record: these fields in this order, x y z each
  bool float64 = false;       // fp64 values, else fp32 (rounded once)
  size_t maxPoints = 0;       // records one block holds
  // Threads the sink keeps busy itself (a thread that copies the blocks into the file): the
  // sampler's default worker count leaves their cores to them.
  int ownThreads = 0;
  std::function<RecordBlock()> acquire;
  std::function<void(RecordBlock block, const GridChunk& chunk, size_t first, size_t count)> submit;
};

}  // namespace shapespline
