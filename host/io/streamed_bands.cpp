#include <shapespline/io/streamed_bands.h>

#include <shapespline/core/span_basis.h>
#include <shapespline/core/validate.h>
#include <shapespline/core/value_scan.h>
#include <shapespline/io/array_stream.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <climits>
#include <deque>
#include <functional>
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

// A net read as `rows` rows of `cols` points (a surface's point rows; a curve's points, one a row),
// each point `coords` values in its file, and its α (α-EB) from a file, one number or the model.
struct RowNet {
  const DeferredArray* points = nullptr;
  const DeferredArray* alphaFile = nullptr;
  std::optional<double> uniformAlpha;
  const std::vector<double>* modelAlpha = nullptr;  // written out in the model (α-EB), else null
  int rows = 0;
  size_t cols = 1, coords = 3;
  bool closed = false;
  std::function<void(const double* alpha, size_t count, size_t first)> alphaRule;  // flat index `first`
};

// A net of `rows` rows of `cols` points, closed or not, its points file and its α (α-EB): a file,
// one number, or written out in the model (`modelAlpha`).
RowNet rowNetOf(const ModelArrays& arrays, int rows, size_t cols, bool closed, bool alphaEB,
                const std::vector<double>& modelAlpha) {
  RowNet net;
  net.points = deferredArray(arrays, "points");
  net.rows = rows;
  net.cols = cols;
  net.closed = closed;
  if (!alphaEB) return net;
  net.alphaFile = deferredArray(arrays, "alpha");
  if (net.alphaFile) return net;
  if (arrays.uniformAlpha) net.uniformAlpha = arrays.uniformAlpha;
  else net.modelAlpha = &modelAlpha;
  return net;
}

// The rows band i reads, ascending; and band i built from them (a row's points, a row's α).
using RowsOfBand = std::function<std::vector<int>(size_t band)>;
using BuildBand = std::function<void(size_t band, const Surface::PointRowOf&, const Surface::AlphaRowOf&)>;

// Streams `net` through the value rules, `fingerprint`, the α tally and `warnings` in file order,
// building each of `bandCount` bands (rows ascending but for a closed net's wrapped rows) as soon
// as its rows are in, the rows held only while a band still needs them.
StreamedNet streamRows(const RowNet& net, const ModelArrays& arrays, NetFingerprint& fingerprint, size_t bandCount,
                       const RowsOfBand& rowsOf, const BuildBand& build, size_t windowPoints, ValueScan* warnings) {
  const DeferredArray& points = *net.points;
  const DeferredArray* alphaFile = net.alphaFile;
  const bool alphaEB = alphaFile || net.uniformAlpha || net.modelAlpha;
  const size_t cols = net.cols, coords = net.coords;
  const int netRows = net.rows;
  StreamedNet out;

  // α that is not a file: one number (a row of it serves every row) or written out in the model.
  std::vector<double> uniformRow;
  if (alphaEB && !alphaFile) {
    if (net.uniformAlpha) uniformRow.assign(cols, *net.uniformAlpha);
    const std::vector<double>& row0 = uniformRow.empty() ? *net.modelAlpha : uniformRow;
    net.alphaRule(row0.data(), uniformRow.empty() ? row0.size() : cols, 0);
  }

  // The rows each band reads, found when first asked for (each costs the net's layout: finding
  // them all up front would delay the first band).
  std::vector<std::optional<std::vector<int>>> needs(bandCount);
  auto need = [&](size_t i) -> const std::vector<int>& {
    if (!needs[i]) needs[i] = rowsOf(i);
    return *needs[i];
  };

  // A row's points from their file: `coords` values a point, z = 0 for a curve's (n, 2) array.
  std::vector<double> flat;
  auto readPoints = [&](ArrayStream& file, glm::dvec3* to, size_t n, size_t first) {
    if (coords == 3) return file.read(&to->x, 3 * n, 3 * std::uint64_t(first));
    flat.resize(coords * n);
    file.read(flat.data(), coords * n, coords * std::uint64_t(first));
    for (size_t k = 0; k < n; ++k) {
      to[k] = glm::dvec3(0.0);
      for (size_t d = 0; d < coords; ++d) to[k][static_cast<int>(d)] = flat[k * coords + d];
    }
  };

  // A closed net (a surface closed in u, a closed curve) wraps: its first band reads its last rows,
  // its last band its first rows (a band between them reads no wrapped row the first or the last
  // does not: bands further in reach less far past either end). Those are kept apart: the last
  // ones read first (a stream of their own), the first ones as read.
  std::map<int, KeptRow> kept;
  if (net.closed && bandCount > 0) {
    for (size_t i : {size_t{0}, bandCount - 1})
      for (int k : need(i))
        if (k < kMaxBasisCount || k >= netRows - kMaxBasisCount) kept[k];
    ArrayStream pointTail(points, arrays.maxValueBytes);
    std::optional<ArrayStream> alphaTail;
    if (alphaFile) alphaTail.emplace(*alphaFile, arrays.maxValueBytes);
    int at = 0;
    for (auto& [k, row] : kept) {
      if (k < kMaxBasisCount && k < netRows - kMaxBasisCount) continue;  // a first row, kept as read
      pointTail.skip(coords * cols * static_cast<std::uint64_t>(k - at));
      row.points.resize(cols);
      readPoints(pointTail, row.points.data(), cols, cols * static_cast<size_t>(k));
      if (alphaTail) {
        alphaTail->skip(cols * static_cast<std::uint64_t>(k - at));
        row.alpha.resize(cols);
        alphaTail->read(row.alpha.data(), cols, cols * static_cast<std::uint64_t>(k));
        net.alphaRule(row.alpha.data(), cols, cols * static_cast<size_t>(k));
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
    readPoints(pointFile, b.points.data(), n, first);
    out.largestCoordinate = std::max(out.largestCoordinate, largestMagnitude(&b.points.data()->x, 3 * n));
    fingerprint.points(b.points.data(), n);
    if (warnings) warnings->points(b.points.data(), n);
    if (alphaStream) {
      b.alpha.resize(n);
      alphaStream->read(b.alpha.data(), n, first);
      net.alphaRule(b.alpha.data(), n, first);
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
    throw std::logic_error("streamed bands: row " + std::to_string(k) + " is no longer held");
  };
  const Surface::PointRowOf pointRow = [&](int k) -> const glm::dvec3* {
    if (auto it = kept.find(k); it != kept.end() && !it->second.points.empty()) return it->second.points.data();
    const RowBlock& b = blockOf(k);
    return &b.points[static_cast<size_t>(k - b.first) * cols];
  };
  const Surface::AlphaRowOf alphaRow = [&](int k) -> const double* {
    if (!uniformRow.empty()) return uniformRow.data();
    if (!alphaFile) return &(*net.modelAlpha)[static_cast<size_t>(k) * cols];
    if (auto it = kept.find(k); it != kept.end() && !it->second.alpha.empty()) return it->second.alpha.data();
    const RowBlock& b = blockOf(k);
    return &b.alpha[static_cast<size_t>(k - b.first) * cols];
  };
  // The lowest row that bands i on read from the blocks (INT_MAX: none). Bands read ascending
  // rows but for the kept ones, so the first band that reads any from the blocks has it.
  auto lowestInBlocks = [&](size_t i) {
    for (; i < bandCount; ++i)
      for (int k : need(i))
        if (!kept.count(k)) return k;
    return INT_MAX;
  };

  // Blocks below every row still to be read from them go as soon as the next one is in (a shard's
  // first band may lie far into the net).
  auto dropBelow = [&](int lowest) {
    while (!blocks.empty() && blocks.front().first + blocks.front().count <= lowest) blocks.pop_front();
  };

  for (size_t i = 0; i < bandCount; ++i) {
    int highest = -1;  // the last row to read before band i (a kept row counts until it is read)
    for (int k : need(i))
      if (auto it = kept.find(k); it == kept.end() || it->second.points.empty()) highest = std::max(highest, k);
    const int lowest = lowestInBlocks(i);
    while (read <= highest) {
      readBlock();
      dropBelow(lowest);
    }
    build(i, pointRow, alphaRow);
    needs[i].reset();  // done with (a curve's list is as long as its band: not kept for them all)
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
    // A window of the one number at a time (a curve's rows are one point each).
    const size_t total = static_cast<size_t>(netRows) * cols;
    const std::vector<double> run(std::min(std::max(windowPoints, cols), total), *net.uniformAlpha);
    for (size_t first = 0; first < total; first += run.size()) {
      const size_t n = std::min(run.size(), total - first);
      out.alpha.add(run.data(), n);
      fingerprint.alphas(run.data(), n);
    }
    if (warnings) warnings->alphas(uniformRow.data(), cols);  // the smallest is the first
  } else if (alphaEB) {
    out.alpha.add(net.modelAlpha->data(), net.modelAlpha->size());
    fingerprint.alphas(net.modelAlpha->data(), net.modelAlpha->size());
    if (warnings) warnings->alphas(net.modelAlpha->data(), net.modelAlpha->size());
  }
  return out;
}

}  // namespace

bool bandsCanStream(const SurfaceModel& m, const ModelArrays& arrays) {
  return deferredArray(arrays, "points") && !deferredArray(arrays, "weights") && m.weights.empty() &&
         parameterizationOf(m) != Parameterization::KnotVector;
}

StreamedNet streamSurfaceBands(const SurfaceModel& m, const ModelArrays& arrays, NetFingerprint& fingerprint,
                               SpanRange rows, const BandSink& sink, BandSizes sizes, size_t windowPoints,
                               SurfaceWarningScan* warnings) {
  if (!bandsCanStream(m, arrays)) throw std::logic_error("streamSurfaceBands: not a net of uniform spans in a file");
  const bool alphaEB = m.family.construction == Construction::AlphaEB;
  RowNet net = rowNetOf(arrays, m.rows, static_cast<size_t>(m.cols), m.closedU, alphaEB, m.alpha);
  net.alphaRule = [&m](const double* a, size_t n, size_t first) { checkSurfaceAlphas(a, n, first, m.cols); };

  const std::vector<SpanRange> bands = bandsOver(rows, m.cols, sizes);
  StreamedNet out = streamRows(
      net, arrays, fingerprint, bands.size(),
      [&](size_t i) { return Surface::bandPointRows(m, bands[i].first, bands[i].last); },
      [&](size_t i, const Surface::PointRowOf& pointRow, const Surface::AlphaRowOf& alphaRow) {
        sink(Surface::bandOf(m, bands[i].first, bands[i].last, pointRow, alphaRow), bands[i].first, bands[i].last);
      },
      windowPoints, warnings);

  // Every vertex a band held was checked by its band; the rest need the bound (or the caller's
  // built surface, when it cannot clear them).
  const PatchRange all = patchRangeOf(m);
  const bool everyVertexInABand = rows.first == all.u.first && rows.last == all.u.last;
  if (alphaEB && !everyVertexInABand)
    out.verticesShown = alphaEBVerticesSurelyFinite(m, out.largestCoordinate, out.alpha.summary().min);
  return out;
}

bool curveSpansCanStream(const CurveModel& m, const ModelArrays& arrays) {
  return deferredArray(arrays, "points") && !deferredArray(arrays, "weights") && m.weights.empty() &&
         parameterizationOf(m.family.construction, !m.knots.empty()) != Parameterization::KnotVector;
}

StreamedNet streamCurveSpans(const CurveModel& m, const ModelArrays& arrays, NetFingerprint& fingerprint,
                             SpanRange spans, const CurveBandSink& sink, BandSizes sizes, size_t windowPoints,
                             CurveWarningScan* warnings) {
  if (!curveSpansCanStream(m, arrays)) throw std::logic_error("streamCurveSpans: not a curve of uniform spans in a file");
  const bool alphaEB = m.family.construction == Construction::AlphaEB;
  const DeferredArray& points = *deferredArray(arrays, "points");
  const int n = static_cast<int>(points.header.shape[0]);
  RowNet net = rowNetOf(arrays, n, 1, m.closed, alphaEB, m.alpha);
  net.coords = static_cast<size_t>(points.header.shape[1]);
  net.alphaRule = [](const double* a, size_t count, size_t first) { checkCurveAlphas(a, count, first); };

  // Bands over every span, so that each α-EB vertex is checked by a band; only those that meet
  // `spans` go to the sink.
  const std::vector<SpanRange> bands = bandsOver(uniformCurveSpans(m, n), 1, sizes);
  StreamedNet out = streamRows(
      net, arrays, fingerprint, bands.size(), [&](size_t i) { return Curve::bandPoints(m, n, bands[i].first, bands[i].last); },
      [&](size_t i, const Surface::PointRowOf& pointOf, const Surface::AlphaRowOf& alphaOf) {
        const Curve band = Curve::bandOf(m, n, bands[i].first, bands[i].last, pointOf, alphaOf);
        if (bands[i].last >= spans.first && bands[i].first <= spans.last) sink(band, bands[i].first, bands[i].last);
      },
      windowPoints, warnings);
  out.rational = false;
  return out;
}

}  // namespace shapespline::io
