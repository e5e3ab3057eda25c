#pragma once
// Welded meshes from a sampled grid: every distinct grid point once, shared by index.
//
// Neighbouring items (patches, spans) repeat their shared boundary samples (core/sample_grid.h),
// and a closed direction repeats its first samples at its end. The welded vertex of such a point
// is decided by its place in the parameter grid, never by distance:
//  * position, texture coordinate and every field but the normal come from its canonical sample,
//    the first one in item order (the lower patch index, as the GPU tessellator does);
//  * the normal is the normalised sum, in item order, of the unit normals of every sample of the
//    point (gpu/tessellator.h: at regular points they agree, at an α = 1 vertex it is the mean of
//    the patches' diagonal limits); a sum too short to normalise keeps the canonical normal.
// Vertex order: the point belongs to the last item that contains it (its owner), and each item
// lists the points it owns row-major (u outer). So a vertex is complete when its owner arrives:
// the writer streams in item order holding only the points still waiting for a later item (one
// patch row of boundary points, plus the first row while a closed u direction waits for the last).
//
// A file covering items [first, end) of the job (a shard; the whole job: [0, total)) lists first
// the points owned by its items, in the whole job's order, then its foreign points (points of its
// items owned by later items), in the whole job's order. `merge` keeps each shard's owned points
// and regenerates the faces, which gives the unsharded file byte for byte. For the foreign points,
// and for the points of its first items that earlier items share, a shard also samples its
// context: the items outside the shard that share a point with it (contextItems()); their chunks
// go into the same stream in item order, so a shard's vertices equal the unsharded ones bitwise.
#include <shapespline/core/sample_grid.h>

#include <array>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <utility>
#include <vector>

namespace shapespline::io {

// The global point grid of a job: patchesU x patchesV items (curves: spans x 1, samplesV = 1),
// samplesU x samplesV samples each.
class WeldGrid {
 public:
  struct Point {
    uint64_t row = 0, column = 0;
    bool operator==(const Point&) const = default;
  };

  WeldGrid(uint64_t patchesU, uint64_t patchesV, int samplesU, int samplesV, bool closedU, bool closedV);

  uint64_t patchesU() const { return patchesU_; }
  uint64_t patchesV() const { return patchesV_; }
  uint64_t items() const { return patchesU_ * patchesV_; }
  int samplesU() const { return su_; }
  int samplesV() const { return sv_; }
  bool closedU() const { return closedU_; }
  bool closedV() const { return closedV_; }
  bool curve() const { return sv_ == 1; }
  uint64_t rows() const;     // distinct point rows (u)
  uint64_t columns() const;  // distinct point columns (v; curves: 1)
  uint64_t pointCount() const { return rows() * columns(); }

  Point pointOf(uint64_t item, int a, int b) const;
  // The last item containing the point, and whether sample (a, b) of `item` is the one that
  // emits it (false for the other samples of the point, including a second one in the owner).
  uint64_t ownerOf(Point p) const;
  bool emits(uint64_t item, int a, int b) const;
  // Number of samples (item, a, b) of the whole job that land on the point (1, 2 or 4; more when a
  // closed direction has one patch).
  int sampleCount(Point p) const;
  // Items that contain the point (each once), increasing.
  std::vector<uint64_t> itemsContaining(Point p) const;
  // Position of the point in the whole job's vertex order, and the first index of item's points.
  uint64_t globalIndex(Point p) const;
  uint64_t firstIndexOf(uint64_t item) const;  // item <= items()
  // The samples item emits: rows [row0, row1] x columns [col0, col1], numbered row-major from
  // firstIndexOf(item).
  struct Owned {
    int row0, row1, col0, col1;
  };
  Owned owned(uint64_t item) const {
    const uint64_t r = item / patchesV_, c = item % patchesV_;
    return {firstOwnedRow(r), lastOwnedRow(r), firstOwnedColumn(c), lastOwnedColumn(c)};
  }

 private:
  int firstOwnedRow(uint64_t r) const;
  int lastOwnedRow(uint64_t r) const;
  int firstOwnedColumn(uint64_t c) const;
  int lastOwnedColumn(uint64_t c) const;
  uint64_t rowsBefore(uint64_t r) const;
  uint64_t columnsBefore(uint64_t c) const;

  uint64_t patchesU_, patchesV_;
  int su_, sv_;
  bool closedU_, closedV_;
};

// The vertex numbering of one file: items [first, end) of the grid.
class WeldedNumbering {
 public:
  WeldedNumbering(const WeldGrid& grid, uint64_t first, uint64_t end);

  const WeldGrid& grid() const { return grid_; }
  uint64_t first() const { return first_; }
  uint64_t end() const { return end_; }
  bool whole() const { return first_ == 0 && end_ == grid_.items(); }
  uint64_t ownedCount() const { return ownedCount_; }
  uint64_t foreignCount() const { return foreign_.size(); }
  uint64_t vertexCount() const { return ownedCount_ + foreign_.size(); }
  bool contains(uint64_t item) const { return item >= first_ && item < end_; }
  // True when the point lies in one of the file's items.
  bool touches(WeldGrid::Point p) const;
  // 0-based index of a point of one of the file's items.
  uint64_t localIndex(WeldGrid::Point p) const;
  // The foreign points' global indices, increasing.
  const std::vector<uint64_t>& foreignPoints() const { return foreignOrder_; }

  // Triangles: 2 (Su-1)(Sv-1) per item, counter-clockwise seen from du x dv (reversed: clockwise),
  // as local indices; `emit(i0, i1, i2)`.
  uint64_t triangleCount() const;
  template <class Emit>
  void forEachTriangle(bool reversed, Emit&& emit) const {
    forEachTriangleRow(reversed, [&](const uint64_t* t, size_t n) {
      for (size_t k = 0; k < n; ++k) emit(t[3 * k], t[3 * k + 1], t[3 * k + 2]);
    });
  }
  // The same, one row of cells of an item at a time: `emit(indices, triangles)`, 3 indices each.
  void forEachTriangleRow(bool reversed, const std::function<void(const uint64_t*, size_t)>& emit) const;
  // Curves: the polyline through the file's points in parameter order, each point once; a closed
  // curve sampled whole ends with its first point again (a loop). `emit(local index)`.
  uint64_t polylineLength() const;
  void forEachPolylinePoint(const std::function<void(uint64_t)>& emit) const;

  // Items outside [first, end) that share a point with the file's items, as increasing disjoint
  // ranges [a, b); empty for the whole job.
  std::vector<std::pair<uint64_t, uint64_t>> contextItems() const;

 private:
  // Local indices of row a of item (its samples b = 0..Sv-1): the emitted ones by arithmetic, the
  // shared ones through localIndex.
  void rowIndices(uint64_t item, int a, uint64_t* out) const;
  WeldGrid grid_;
  uint64_t first_, end_;
  uint64_t ownedCount_ = 0;
  std::unordered_map<uint64_t, uint64_t> foreign_;  // global index -> local index
  std::vector<uint64_t> foreignOrder_;
};

// One welded vertex as a writer formats it: `value(f, axis)` for every field of the layout
// (normals already averaged and, when `reversed`, negated), and the canonical sample
// (item, a, b) for texture coordinates (SampleLayout::texCoord).
struct WeldedVertex {
  const double* values = nullptr;  // 3 per field present, in Field order
  const std::array<int, kFieldCount>* slot = nullptr;
  uint64_t item = 0;
  int a = 0, b = 0;
  double value(Field f, int axis) const { return values[(*slot)[static_cast<size_t>(f)] * 3 + axis]; }
};

// Turns the chunks of a file's items and of its context (in item order) into its welded vertices,
// in the file's order: `emit` gets each vertex once; finish() emits the foreign points and throws
// std::logic_error if a point missed one of its samples.
class WeldedVertexStream {
 public:
  using Emit = std::function<void(const WeldedVertex&)>;
  WeldedVertexStream(const WeldedNumbering& numbering, FieldMask fields, bool reversed, Emit emit);

  void consume(const GridChunk& chunk);
  void finish();
  // Points held for a later item now (for the memory-bound test).
  size_t pendingPoints() const { return pending_.size(); }

 private:
  struct Pending {
    std::vector<double> values;  // canonical sample's fields
    double normalSum[3] = {0, 0, 0};
    int seen = 0;
    uint64_t item = 0;
    int a = 0, b = 0;
  };
  void finishVertex(Pending& p);

  const WeldedNumbering& numbering_;
  FieldMask fields_;
  bool reversed_;
  Emit emit_;
  std::array<int, kFieldCount> slot_{};
  int fieldCount_ = 0;
  std::unordered_map<uint64_t, Pending> pending_;  // by global index
  std::vector<double> scratch_;
  uint64_t emitted_ = 0;
};

}  // namespace shapespline::io
