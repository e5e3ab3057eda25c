#pragma once
// CPU fp64 grid sampling of curves and surfaces, delivered chunk by chunk (core/sample_grid.h).
//
// On a regular grid the basis values depend only on the sample position, not on the span or
// patch, so they are tabulated once per grid and every patch is a small tensor contraction
// (v first, then u). A chunk's rows are split among threads; each point is computed by the same code
// whatever the thread count or chunk size, so the output is byte-identical across both.
// Points where the fast path does not apply (knot-vector B-splines, α-EB corner samples, and
// degenerate normals) go through Curve::evaluate / Surface::evaluate.
#include <shapespline/core/curve.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/core/surface.h>

#include <array>
#include <vector>

namespace shapespline {

struct SamplerOptions {
  int threads = 0;                      // 0 = availableCores() (core/cores.h), less a RecordSink's own
  // Points per delivered chunk: whole items while they fit, else rows of one item (at least one
  // row of Sv points), so memory is 2 buffers x fields x 24 bytes x max(maxChunkPoints, Sv) for any
  // grid. Small enough that both chunk buffers stay in cache: at 2^20 the sampler becomes bound by
  // memory writes (24 vs 61 Mpts/s measured).
  size_t maxChunkPoints = size_t{1} << 15;
  SliceConsumer slice = {};             // optional (core/sample_grid.h)
  // Optional (core/sample_grid.h): the workers encode records into it instead of filling planes
  // and calling `slice`, whenever a row of points fits one of its blocks; the chunks then reach
  // the consumer without planes. Its fields must be the sampled fields, and `slice` must be set:
  // the points of a block that holds a value out of range are computed again into the planes and
  // handed to `slice`, which finds and reports it.
  RecordSink records = {};
  // Optional: fp64 planes of the whole job (point p of the job at [3p, 3p + 3)), one for every
  // sampled field, that the workers fill directly instead of chunk buffers: the caller's own
  // arrays (Python's sample()), so no copy follows. `slice` and the consumer then see the chunks
  // over these planes. Ignored when `records` takes the points.
  std::array<double*, kFieldCount> jobPlanes{};
};

// The sampled items: span indices of a curve (for knot-vector B-splines only non-empty intervals).
std::vector<int> curveGridItems(const Curve& curve);
// Patches (i, j) of a surface, row-major (i outer): every pair of a u index and a v index, so the
// list is held as its two factors (a 4096 x 4096 net has 16.8 million patches).
struct SurfaceGridItems {
  std::vector<int> u, v;  // patch indices per direction; knot-vector B-splines: non-empty intervals
  size_t size() const { return u.size() * v.size(); }
  bool empty() const { return size() == 0; }
  std::pair<int, int> operator[](size_t k) const { return {u[k / v.size()], v[k % v.size()]}; }

  class Iterator {
   public:
    Iterator(const SurfaceGridItems* items, size_t k) : items_(items), k_(k) {}
    std::pair<int, int> operator*() const { return (*items_)[k_]; }
    Iterator& operator++() {
      ++k_;
      return *this;
    }
    bool operator==(const Iterator& o) const { return k_ == o.k_; }

   private:
    const SurfaceGridItems* items_;
    size_t k_;
  };
  Iterator begin() const { return {this, 0}; }
  Iterator end() const { return {this, size()}; }
};
SurfaceGridItems surfaceGridItems(const Surface& surface);
// The same from the shape alone (a valid one: core/validate.h validateSurfaceShape).
SurfaceGridItems surfaceGridItems(const SurfaceShape& shape);

// Fields allowed: Point, D1, D2 (curves); Point, Du, Dv, Duu, Duv, Dvv, Normal (surfaces).
// Throws std::invalid_argument for another field, fewer than 2 samples, or an item range outside
// the model; chunks are delivered in increasing item order on the calling thread.
void sampleCurveGrid(const Curve& curve, const GridSpec& grid, FieldMask fields, const ChunkConsumer& consumer,
                     const SamplerOptions& options = {});
void sampleSurfaceGrid(const Surface& surface, const GridSpec& grid, FieldMask fields,
                       const ChunkConsumer& consumer, const SamplerOptions& options = {});

}  // namespace shapespline
