// Welded mesh numbering and the vertex stream (io/welded_mesh.h).
#include <shapespline/io/welded_mesh.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace shapespline::io {
namespace {

// The samples (patch index, local index) of one direction that land on global line `line`, at most
// two; `count` = patches, `samples` = samples per patch (>= 2), or samples == 1 (a curve's v).
struct LineSamples {
  uint64_t patch[2];
  int local[2];
  int n = 0;
};

LineSamples lineSamples(uint64_t line, uint64_t count, int samples, bool closed) {
  LineSamples s;
  if (samples == 1) {  // a curve's v direction: one column
    s.patch[0] = 0;
    s.local[0] = 0;
    s.n = 1;
    return s;
  }
  const uint64_t step = static_cast<uint64_t>(samples - 1);
  const uint64_t k = line / step;
  const int off = static_cast<int>(line % step);
  if (off != 0) {
    s.patch[0] = k;
    s.local[0] = off;
    s.n = 1;
    return s;
  }
  // A patch boundary: the end of the previous patch (wrapped when closed), then the start of patch k.
  if (k > 0) {
    s.patch[s.n] = k - 1;
    s.local[s.n++] = samples - 1;
  } else if (closed) {
    s.patch[s.n] = count - 1;
    s.local[s.n++] = samples - 1;
  }
  if (k < count) {
    s.patch[s.n] = k;
    s.local[s.n++] = 0;
  }
  return s;
}

// The sample of a line that emits it: the last patch, and in it the last local index.
std::pair<uint64_t, int> emitter(const LineSamples& s) {
  std::pair<uint64_t, int> best{s.patch[0], s.local[0]};
  for (int i = 1; i < s.n; ++i) best = std::max(best, std::pair<uint64_t, int>{s.patch[i], s.local[i]});
  return best;
}

}  // namespace

WeldGrid::WeldGrid(uint64_t patchesU, uint64_t patchesV, int samplesU, int samplesV, bool closedU, bool closedV)
    : patchesU_(patchesU), patchesV_(patchesV), su_(samplesU), sv_(samplesV), closedU_(closedU), closedV_(closedV) {
  if (patchesU == 0 || patchesV == 0 || samplesU < 2 || samplesV < 1 || (samplesV == 1 && (patchesV != 1 || closedV))) {
    throw std::invalid_argument("WeldGrid: " + std::to_string(patchesU) + "x" + std::to_string(patchesV) +
                                " items of " + std::to_string(samplesU) + "x" + std::to_string(samplesV) +
                                " samples is not a grid");
  }
}

uint64_t WeldGrid::rows() const { return patchesU_ * static_cast<uint64_t>(su_ - 1) + (closedU_ ? 0 : 1); }

uint64_t WeldGrid::columns() const {
  return sv_ == 1 ? 1 : patchesV_ * static_cast<uint64_t>(sv_ - 1) + (closedV_ ? 0 : 1);
}

WeldGrid::Point WeldGrid::pointOf(uint64_t item, int a, int b) const {
  const uint64_t r = item / patchesV_, c = item % patchesV_;
  Point p;
  p.row = r * static_cast<uint64_t>(su_ - 1) + static_cast<uint64_t>(a);
  if (closedU_) p.row %= rows();
  p.column = sv_ == 1 ? 0 : c * static_cast<uint64_t>(sv_ - 1) + static_cast<uint64_t>(b);
  if (closedV_) p.column %= columns();
  return p;
}

uint64_t WeldGrid::ownerOf(Point p) const {
  const auto [r, a] = emitter(lineSamples(p.row, patchesU_, su_, closedU_));
  const auto [c, b] = emitter(lineSamples(p.column, patchesV_, sv_, closedV_));
  (void)a;
  (void)b;
  return r * patchesV_ + c;
}

bool WeldGrid::emits(uint64_t item, int a, int b) const {
  const Point p = pointOf(item, a, b);
  const auto [r, ea] = emitter(lineSamples(p.row, patchesU_, su_, closedU_));
  const auto [c, eb] = emitter(lineSamples(p.column, patchesV_, sv_, closedV_));
  return r * patchesV_ + c == item && ea == a && eb == b;
}

int WeldGrid::sampleCount(Point p) const {
  return lineSamples(p.row, patchesU_, su_, closedU_).n * lineSamples(p.column, patchesV_, sv_, closedV_).n;
}

std::vector<uint64_t> WeldGrid::itemsContaining(Point p) const {
  const LineSamples rs = lineSamples(p.row, patchesU_, su_, closedU_);
  const LineSamples cs = lineSamples(p.column, patchesV_, sv_, closedV_);
  std::vector<uint64_t> items;
  for (int i = 0; i < rs.n; ++i) {
    for (int j = 0; j < cs.n; ++j) items.push_back(rs.patch[i] * patchesV_ + cs.patch[j]);
  }
  std::sort(items.begin(), items.end());
  items.erase(std::unique(items.begin(), items.end()), items.end());
  return items;
}

// Item (r, c) emits the rows [firstOwnedRow(r), lastOwnedRow(r)], and likewise the columns: a line
// shared with the previous patch is this patch's (the later one), a line shared with the next
// patch is the next one's, except that the last patch keeps its last line and, when closed, the
// first patch gives its first line to the last patch.
int WeldGrid::firstOwnedRow(uint64_t r) const { return closedU_ && r == 0 ? 1 : 0; }
int WeldGrid::lastOwnedRow(uint64_t r) const { return r + 1 == patchesU_ ? su_ - 1 : su_ - 2; }
int WeldGrid::firstOwnedColumn(uint64_t c) const { return closedV_ && c == 0 ? 1 : 0; }
int WeldGrid::lastOwnedColumn(uint64_t c) const { return sv_ == 1 ? 0 : c + 1 == patchesV_ ? sv_ - 1 : sv_ - 2; }

uint64_t WeldGrid::rowsBefore(uint64_t r) const {
  return r * static_cast<uint64_t>(su_ - 1) - (closedU_ && r > 0 ? 1 : 0);
}

uint64_t WeldGrid::columnsBefore(uint64_t c) const {
  return sv_ == 1 ? 0 : c * static_cast<uint64_t>(sv_ - 1) - (closedV_ && c > 0 ? 1 : 0);
}

uint64_t WeldGrid::firstIndexOf(uint64_t item) const {
  if (item >= items()) return pointCount();
  const uint64_t r = item / patchesV_, c = item % patchesV_;
  const uint64_t rowsOwned = static_cast<uint64_t>(lastOwnedRow(r) - firstOwnedRow(r) + 1);
  return rowsBefore(r) * columns() + rowsOwned * columnsBefore(c);
}

uint64_t WeldGrid::globalIndex(Point p) const {
  const auto [r, a] = emitter(lineSamples(p.row, patchesU_, su_, closedU_));
  const auto [c, b] = emitter(lineSamples(p.column, patchesV_, sv_, closedV_));
  const uint64_t colsOwned = static_cast<uint64_t>(lastOwnedColumn(c) - firstOwnedColumn(c) + 1);
  return firstIndexOf(r * patchesV_ + c) + static_cast<uint64_t>(a - firstOwnedRow(r)) * colsOwned +
         static_cast<uint64_t>(b - firstOwnedColumn(c));
}

// ---- WeldedNumbering ---------------------------------------------------------------------------

namespace {

// Calls f(a, b) for every boundary sample of an item (each once).
template <class F>
void forEachBoundarySample(int su, int sv, F&& f) {
  for (int a = 0; a < su; ++a) {
    if (a == 0 || a == su - 1 || sv <= 2) {
      for (int b = 0; b < sv; ++b) f(a, b);
    } else {
      f(a, 0);
      f(a, sv - 1);
    }
  }
}

}  // namespace

WeldedNumbering::WeldedNumbering(const WeldGrid& grid, uint64_t first, uint64_t end)
    : grid_(grid), first_(first), end_(end) {
  if (first > end || end > grid.items()) {
    throw std::invalid_argument("WeldedNumbering: items " + std::to_string(first) + ".." + std::to_string(end) +
                                " outside 0.." + std::to_string(grid.items()));
  }
  ownedCount_ = grid.firstIndexOf(end) - grid.firstIndexOf(first);
  if (end == grid.items()) return;  // nothing is owned by a later item
  // A later item owning a point of this file's items: only boundary samples can be shared.
  for (uint64_t item = first; item < end; ++item) {
    forEachBoundarySample(grid.samplesU(), grid.samplesV(), [&](int a, int b) {
      const WeldGrid::Point p = grid.pointOf(item, a, b);
      if (grid.ownerOf(p) >= end) foreign_.emplace(grid.globalIndex(p), 0);
    });
  }
  foreignOrder_.reserve(foreign_.size());
  for (const auto& [g, local] : foreign_) foreignOrder_.push_back(g);
  std::sort(foreignOrder_.begin(), foreignOrder_.end());
  for (size_t k = 0; k < foreignOrder_.size(); ++k) foreign_[foreignOrder_[k]] = ownedCount_ + k;
}

bool WeldedNumbering::touches(WeldGrid::Point p) const {
  for (uint64_t item : grid_.itemsContaining(p)) {
    if (contains(item)) return true;
  }
  return false;
}

uint64_t WeldedNumbering::localIndex(WeldGrid::Point p) const {
  const uint64_t g = grid_.globalIndex(p), base = grid_.firstIndexOf(first_);
  if (g >= base && g - base < ownedCount_) return g - base;
  const auto it = foreign_.find(g);
  if (it == foreign_.end()) {
    throw std::logic_error("WeldedNumbering: point " + std::to_string(p.row) + "," + std::to_string(p.column) +
                           " is not in items " + std::to_string(first_) + ".." + std::to_string(end_));
  }
  return it->second;
}

uint64_t WeldedNumbering::triangleCount() const {
  if (grid_.curve()) return 0;
  return (end_ - first_) * 2 * static_cast<uint64_t>(grid_.samplesU() - 1) * static_cast<uint64_t>(grid_.samplesV() - 1);
}

void WeldedNumbering::rowIndices(uint64_t item, int a, uint64_t* out) const {
  const WeldGrid::Owned o = grid_.owned(item);
  const int sv = grid_.samplesV();
  const bool ownedRow = a >= o.row0 && a <= o.row1;
  const uint64_t base = grid_.firstIndexOf(item) - grid_.firstIndexOf(first_) +
                        (ownedRow ? static_cast<uint64_t>(a - o.row0) * static_cast<uint64_t>(o.col1 - o.col0 + 1) : 0);
  for (int b = 0; b < sv; ++b) {
    out[b] = ownedRow && b >= o.col0 && b <= o.col1 ? base + static_cast<uint64_t>(b - o.col0)
                                                     : localIndex(grid_.pointOf(item, a, b));
  }
}

void WeldedNumbering::forEachTriangleRow(bool reversed, const std::function<void(const uint64_t*, size_t)>& emit) const {
  if (grid_.curve()) return;
  const int su = grid_.samplesU(), sv = grid_.samplesV();
  std::vector<uint64_t> lower(static_cast<size_t>(sv)), upper(static_cast<size_t>(sv)), tri(6 * static_cast<size_t>(sv - 1));
  for (uint64_t item = first_; item < end_; ++item) {
    rowIndices(item, 0, lower.data());
    for (int a = 0; a + 1 < su; ++a) {
      rowIndices(item, a + 1, upper.data());
      uint64_t* t = tri.data();
      for (size_t b = 0; b + 1 < static_cast<size_t>(sv); ++b) {
        const uint64_t p00 = lower[b], p01 = lower[b + 1], p10 = upper[b], p11 = upper[b + 1];
        // (p00, p10, p11), (p00, p11, p01): counter-clockwise in (u, v), front-facing towards du x dv.
        const uint64_t cell[6] = {p00, reversed ? p11 : p10, reversed ? p10 : p11,
                                  p00, reversed ? p01 : p11, reversed ? p11 : p01};
        for (uint64_t i : cell) *t++ = i;
      }
      emit(tri.data(), 2 * static_cast<size_t>(sv - 1));
      lower.swap(upper);
    }
  }
}

uint64_t WeldedNumbering::polylineLength() const {
  if (!grid_.curve() || end_ == first_) return 0;
  return (end_ - first_) * static_cast<uint64_t>(grid_.samplesU() - 1) + 1;
}

void WeldedNumbering::forEachPolylinePoint(const std::function<void(uint64_t)>& emit) const {
  if (!grid_.curve()) return;
  for (uint64_t item = first_; item < end_; ++item) {
    for (int a = item == first_ ? 0 : 1; a < grid_.samplesU(); ++a) emit(localIndex(grid_.pointOf(item, a, 0)));
  }
}

std::vector<std::pair<uint64_t, uint64_t>> WeldedNumbering::contextItems() const {
  std::vector<uint64_t> items;
  if (!whole()) {
    for (uint64_t item = first_; item < end_; ++item) {
      forEachBoundarySample(grid_.samplesU(), grid_.samplesV(), [&](int a, int b) {
        for (uint64_t other : grid_.itemsContaining(grid_.pointOf(item, a, b))) {
          if (!contains(other)) items.push_back(other);
        }
      });
    }
  }
  std::sort(items.begin(), items.end());
  items.erase(std::unique(items.begin(), items.end()), items.end());
  std::vector<std::pair<uint64_t, uint64_t>> ranges;
  for (uint64_t item : items) {
    if (!ranges.empty() && ranges.back().second == item) {
      ++ranges.back().second;
    } else {
      ranges.emplace_back(item, item + 1);
    }
  }
  return ranges;
}

// ---- WeldedVertexStream ------------------------------------------------------------------------

WeldedVertexStream::WeldedVertexStream(const WeldedNumbering& numbering, FieldMask fields, bool reversed, Emit emit)
    : numbering_(numbering), fields_(fields), reversed_(reversed), emit_(std::move(emit)) {
  slot_.fill(-1);
  for (int f = 0; f < kFieldCount; ++f) {
    if (fields & fieldBit(static_cast<Field>(f))) slot_[static_cast<size_t>(f)] = fieldCount_++;
  }
  scratch_.resize(static_cast<size_t>(fieldCount_) * 3);
}

void WeldedVertexStream::finishVertex(Pending& p) {
  const int n = slot_[static_cast<size_t>(Field::Normal)];
  if (n >= 0) {
    const double* s = p.normalSum;
    const double len2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
    // Samples whose normals (nearly) cancel keep the canonical sample's normal.
    if (p.seen > 1 && len2 > 1e-12) {
      const double inv = 1.0 / std::sqrt(len2);
      for (int ax = 0; ax < 3; ++ax) p.values[static_cast<size_t>(n) * 3 + ax] = s[ax] * inv;
    }
    if (reversed_) {
      for (int ax = 0; ax < 3; ++ax) p.values[static_cast<size_t>(n) * 3 + ax] = -p.values[static_cast<size_t>(n) * 3 + ax];
    }
  }
  WeldedVertex v;
  v.values = p.values.data();
  v.slot = &slot_;
  v.item = p.item;
  v.a = p.a;
  v.b = p.b;
  emit_(v);
  ++emitted_;
}

void WeldedVertexStream::consume(const GridChunk& chunk) {
  const WeldGrid& grid = numbering_.grid();
  const int su = grid.samplesU(), sv = grid.samplesV();
  const int normalSlot = slot_[static_cast<size_t>(Field::Normal)];
  const size_t n = chunk.pointCount();
  for (size_t p = 0; p < n; ++p) {
    const uint64_t item = chunk.itemOf(p);
    const size_t q = chunk.pointInItem(p);
    const int a = static_cast<int>(q / static_cast<size_t>(sv)), b = static_cast<int>(q % static_cast<size_t>(sv));
    const bool interior = a > 0 && a + 1 < su && (sv == 1 || (b > 0 && b + 1 < sv));
    const bool own = numbering_.contains(item);
    if (interior) {
      if (!own) continue;  // a context item's interior is its own
      // One sample: emitted as it is (no renormalisation, so it equals the evaluation bit for bit).
      for (int f = 0; f < kFieldCount; ++f) {
        const int s = slot_[static_cast<size_t>(f)];
        if (s < 0) continue;
        for (int ax = 0; ax < 3; ++ax) scratch_[static_cast<size_t>(s) * 3 + ax] = chunk.coord(static_cast<Field>(f), p, ax);
      }
      if (reversed_ && normalSlot >= 0) {
        for (int ax = 0; ax < 3; ++ax) scratch_[static_cast<size_t>(normalSlot) * 3 + ax] *= -1.0;
      }
      WeldedVertex v;
      v.values = scratch_.data();
      v.slot = &slot_;
      v.item = item;
      v.a = a;
      v.b = b;
      emit_(v);
      ++emitted_;
      continue;
    }
    const WeldGrid::Point point = grid.pointOf(item, a, b);
    if (!own && !numbering_.touches(point)) continue;
    const uint64_t g = grid.globalIndex(point);
    auto [it, added] = pending_.try_emplace(g);
    Pending& pend = it->second;
    if (added) {  // the canonical sample: the first in item order
      pend.values.resize(scratch_.size());
      for (int f = 0; f < kFieldCount; ++f) {
        const int s = slot_[static_cast<size_t>(f)];
        if (s < 0) continue;
        for (int ax = 0; ax < 3; ++ax) pend.values[static_cast<size_t>(s) * 3 + ax] = chunk.coord(static_cast<Field>(f), p, ax);
      }
      pend.item = item;
      pend.a = a;
      pend.b = b;
    }
    if (normalSlot >= 0) {
      for (int ax = 0; ax < 3; ++ax) pend.normalSum[ax] += chunk.coord(Field::Normal, p, ax);
    }
    ++pend.seen;
    // Emitted by its owner's emitting sample, the last of its samples; a foreign point waits for finish().
    if (own && grid.emits(item, a, b)) {
      if (pend.seen != grid.sampleCount(point)) {
        throw std::logic_error("WeldedVertexStream: point " + std::to_string(g) + " has " + std::to_string(pend.seen) +
                               " of its " + std::to_string(grid.sampleCount(point)) + " samples at its owner");
      }
      finishVertex(pend);
      pending_.erase(it);
    }
  }
}

void WeldedVertexStream::finish() {
  const WeldGrid& grid = numbering_.grid();
  for (uint64_t g : numbering_.foreignPoints()) {
    const auto it = pending_.find(g);
    const int expected = it == pending_.end() ? 0 : grid.sampleCount(grid.pointOf(it->second.item, it->second.a, it->second.b));
    if (it == pending_.end() || it->second.seen != expected) {
      throw std::logic_error("WeldedVertexStream: foreign point " + std::to_string(g) + " is missing samples (its " +
                             "context items were not streamed)");
    }
    finishVertex(it->second);
    pending_.erase(it);
  }
  if (!pending_.empty() || emitted_ != numbering_.vertexCount()) {
    throw std::logic_error("WeldedVertexStream: " + std::to_string(emitted_) + " of " +
                           std::to_string(numbering_.vertexCount()) + " vertices emitted, " +
                           std::to_string(pending_.size()) + " still waiting");
  }
}

}  // namespace shapespline::io
