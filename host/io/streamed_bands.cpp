#include <shapespline/io/streamed_bands.h>

#include <shapespline/core/span_basis.h>
#include <shapespline/core/validate.h>
#include <shapespline/core/value_scan.h>
#include <shapespline/io/array_stream.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <climits>
#include <deque>
#include <map>
#include <optional>
#include <stdexcept>
#include <vector>

namespace shapespline::io {

namespace {

// The bands covering patch rows `rows`: firstRows, then twice as many each time, up to the rows
// whose net fits maxBytes.
std::vector<SpanRange> bandsOver(SpanRange rows, int cols, BandSizes sizes) {
  const size_t rowBytes = (static_cast<size_t>(cols) + kMaxBasisCount) * sizeof(glm::dvec3);
  const int most = static_cast<int>(std::clamp<size_t>(sizes.maxBytes / rowBytes, 1, INT_MAX / 2));
  std::vector<SpanRange> bands;
  for (int first = rows.first, size = std::clamp(sizes.firstRows, 1, most); first <= rows.last;) {
    const int last = first + std::min(size, rows.last - first + 1) - 1;
    bands.push_back({first, last});
    first = last + 1;
    size = std::min(size * 2, most);
  }
  return bands;
}

// One row's points and α, kept apart from the blocks (a closed net's rows read out of order).
struct KeptRow {
  std::vector<glm::dvec3> points;
  std::vector<double> alpha;
};

// Rows of the net as read, in order, a block at a time, with their α when α is a file.
struct RowBlock {
  int first = 0, count = 0;
  std::vector<glm::dvec3> points;
  std::vector<double> alpha;
};

}  // namespace

bool bandsCanStream(const SurfaceModel& m, const ModelArrays& arrays) {
  return deferredArray(arrays, "points") && !deferredArray(arrays, "weights") && m.weights.empty() &&
         parameterizationOf(m) != Parameterization::KnotVector;
}

StreamedNet streamSurfaceBands(const SurfaceModel& m, const ModelArrays& arrays, SurfaceFingerprint& fingerprint,
                               SpanRange rows, const BandSink& sink, BandSizes sizes, size_t windowPoints,
                               SurfaceWarningScan* warnings) {
  if (!bandsCanStream(m, arrays)) throw std::logic_error("streamSurfaceBands: not a net of uniform spans in a file");
  const DeferredArray& points = *deferredArray(arrays, "points");
  const bool alphaEB = m.family.construction == Construction::AlphaEB;
  const DeferredArray* alphaFile = alphaEB ? deferredArray(arrays, "alpha") : nullptr;
  const size_t cols = static_cast<size_t>(m.cols);
  const int netRows = m.rows;
  StreamedNet out;

  // α that is not a file: one number (a row of it serves every row) or written out in the model.
  std::vector<double> uniformRow;
  if (alphaEB && !alphaFile) {
    if (arrays.uniformAlpha) uniformRow.assign(cols, *arrays.uniformAlpha);
    const std::vector<double>& row0 = uniformRow.empty() ? m.alpha : uniformRow;
    checkSurfaceAlphas(row0.data(), uniformRow.empty() ? row0.size() : cols, 0, m.cols);
  }

  const std::vector<SpanRange> bands = bandsOver(rows, m.cols, sizes);
  // The rows each band reads, found when first asked for (each costs the net's layout: finding
  // them all up front would delay the first band).
  std::vector<std::optional<std::vector<int>>> needs(bands.size());
  auto need = [&](size_t i) -> const std::vector<int>& {
    if (!needs[i]) needs[i] = Surface::bandPointRows(m, bands[i].first, bands[i].last);
    return *needs[i];
  };

  // A net closed in u wraps: its first band reads its last rows, its last band its first rows
  // (a band between them reads no wrapped row the first or the last does not: bands further in
  // reach less far past either end). Those are kept apart: the last ones read first (a stream of
  // their own), the first ones as read.
  std::map<int, KeptRow> kept;
  if (m.closedU && !bands.empty()) {
    for (size_t i : {size_t{0}, bands.size() - 1})
      for (int k : need(i))
        if (k < kMaxBasisCount || k >= netRows - kMaxBasisCount) kept[k];
    ArrayStream pointTail(points, arrays.maxValueBytes);
    std::optional<ArrayStream> alphaTail;
    if (alphaFile) alphaTail.emplace(*alphaFile, arrays.maxValueBytes);
    int at = 0;
    for (auto& [k, row] : kept) {
      if (k < kMaxBasisCount && k < netRows - kMaxBasisCount) continue;  // a first row, kept as read
      pointTail.skip(3 * cols * static_cast<std::uint64_t>(k - at));
      row.points.resize(cols);
      pointTail.read(&row.points.data()->x, 3 * cols, 3 * cols * static_cast<std::uint64_t>(k));
      if (alphaTail) {
        alphaTail->skip(cols * static_cast<std::uint64_t>(k - at));
        row.alpha.resize(cols);
        alphaTail->read(row.alpha.data(), cols, cols * static_cast<std::uint64_t>(k));
        checkSurfaceAlphas(row.alpha.data(), cols, cols * static_cast<size_t>(k), m.cols);
      }
      at = k + 1;
    }
  }

  ArrayStream pointFile(points, arrays.maxValueBytes);
  std::optional<ArrayStream> alphaStream;
  if (alphaFile) alphaStream.emplace(*alphaFile, arrays.maxValueBytes);
  const int blockRows = static_cast<int>(std::max<size_t>(1, windowPoints / cols));
  std::deque<RowBlock> blocks;
  int read = 0;  // rows read in order
  auto readBlock = [&] {
    RowBlock b;
    b.first = read;
    b.count = std::min(blockRows, netRows - read);
    const size_t n = static_cast<size_t>(b.count) * cols, first = static_cast<size_t>(read) * cols;
    b.points.resize(n);
    pointFile.read(&b.points.data()->x, 3 * n, 3 * std::uint64_t(first));
    out.largestCoordinate = std::max(out.largestCoordinate, largestMagnitude(&b.points.data()->x, 3 * n));
    fingerprint.points(b.points.data(), n);
    if (warnings) warnings->points(b.points.data(), n);
    if (alphaStream) {
      b.alpha.resize(n);
      alphaStream->read(b.alpha.data(), n, first);
      checkSurfaceAlphas(b.alpha.data(), n, first, m.cols);
      out.alpha.add(b.alpha.data(), n);
      if (warnings) warnings->alphas(b.alpha.data(), n);
    }
    for (auto& [k, row] : kept) {
      if (k < b.first || k >= b.first + b.count || !row.points.empty()) continue;
      const size_t at = static_cast<size_t>(k - b.first) * cols;
      row.points.assign(b.points.begin() + std::ptrdiff_t(at), b.points.begin() + std::ptrdiff_t(at + cols));
      if (alphaStream) row.alpha.assign(b.alpha.begin() + std::ptrdiff_t(at), b.alpha.begin() + std::ptrdiff_t(at + cols));
    }
    read += b.count;
    blocks.push_back(std::move(b));
  };
  auto blockOf = [&](int k) -> const RowBlock& {
    for (const RowBlock& b : blocks)
      if (k >= b.first && k < b.first + b.count) return b;
    throw std::logic_error("streamSurfaceBands: row " + std::to_string(k) + " is no longer held");
  };
  const Surface::PointRowOf pointRow = [&](int k) -> const glm::dvec3* {
    if (auto it = kept.find(k); it != kept.end() && !it->second.points.empty()) return it->second.points.data();
    const RowBlock& b = blockOf(k);
    return &b.points[static_cast<size_t>(k - b.first) * cols];
  };
  const Surface::AlphaRowOf alphaRow = [&](int k) -> const double* {
    if (!uniformRow.empty()) return uniformRow.data();
    if (!alphaFile) return &m.alpha[static_cast<size_t>(k) * cols];
    if (auto it = kept.find(k); it != kept.end() && !it->second.alpha.empty()) return it->second.alpha.data();
    const RowBlock& b = blockOf(k);
    return &b.alpha[static_cast<size_t>(k - b.first) * cols];
  };
  // The lowest row that bands i on read from the blocks (INT_MAX: none). Bands read ascending
  // rows but for the kept ones, so the first band that reads any from the blocks has it.
  auto lowestInBlocks = [&](size_t i) {
    for (; i < bands.size(); ++i)
      for (int k : need(i))
        if (!kept.count(k)) return k;
    return INT_MAX;
  };

  // Blocks below every row still to be read from them go as soon as the next one is in (a shard's
  // first band may lie far into the net).
  auto dropBelow = [&](int lowest) {
    while (!blocks.empty() && blocks.front().first + blocks.front().count <= lowest) blocks.pop_front();
  };

  for (size_t i = 0; i < bands.size(); ++i) {
    int highest = -1;  // the last row to read before band i (a kept row counts until it is read)
    for (int k : need(i))
      if (auto it = kept.find(k); it == kept.end() || it->second.points.empty()) highest = std::max(highest, k);
    const int lowest = lowestInBlocks(i);
    while (read <= highest) {
      readBlock();
      dropBelow(lowest);
    }
    sink(Surface::bandOf(m, bands[i].first, bands[i].last, pointRow, alphaRow), bands[i].first, bands[i].last);
    dropBelow(lowestInBlocks(i + 1));
  }
  while (read < netRows) {  // the rest of the net, through the rules and the fingerprint only
    readBlock();
    blocks.clear();
  }

  // α after the points in the fingerprint (and the tally, when α is not a file).
  if (alphaFile) {
    ArrayStream again(*alphaFile, arrays.maxValueBytes);
    std::vector<double> values(std::min(windowPoints, static_cast<size_t>(netRows) * cols));
    for (size_t first = 0, total = static_cast<size_t>(netRows) * cols; first < total; first += values.size()) {
      const size_t n = std::min(values.size(), total - first);
      again.read(values.data(), n, first);
      fingerprint.alphas(values.data(), n);
    }
  } else if (!uniformRow.empty()) {
    for (int k = 0; k < netRows; ++k) {
      out.alpha.add(uniformRow.data(), cols);
      fingerprint.alphas(uniformRow.data(), cols);
    }
    if (warnings) warnings->alphas(uniformRow.data(), cols);  // the smallest is the first
  } else if (alphaEB) {
    out.alpha.add(m.alpha.data(), m.alpha.size());
    fingerprint.alphas(m.alpha.data(), m.alpha.size());
    if (warnings) warnings->alphas(m.alpha.data(), m.alpha.size());
  }

  // Every vertex a band held was checked by its band; the rest need the bound (or the caller's
  // built surface, when it cannot clear them).
  const PatchRange all = patchRangeOf(m);
  const bool everyVertexInABand = rows.first == all.u.first && rows.last == all.u.last;
  if (alphaEB && !everyVertexInABand)
    out.verticesShown = alphaEBVerticesSurelyFinite(m, out.largestCoordinate, out.alpha.summary().min);
  return out;
}

}  // namespace shapespline::io
