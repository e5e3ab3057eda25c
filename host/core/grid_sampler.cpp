#include <shapespline/core/grid_sampler.h>

#include <shapespline/core/chunk_runner.h>
#include <shapespline/core/knot_table.h>
#include <shapespline/core/point_math.h>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

// The hot loops of surface sampling are also compiled for AVX2 and picked at run time. No FMA
// in either clone (the "avx2" target does not enable it), so both give identical bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SHAPESPLINE_HOT_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SHAPESPLINE_HOT_CLONES
#endif

namespace shapespline {

namespace sampler {
// dst[3b + c] = (x, y, z)[c][b]: structure-of-arrays rows into an interleaved xyz plane.
SHAPESPLINE_HOT_CLONES
void interleaveRows(const double* x, const double* y, const double* z, int n, double* dst) {
  for (int b = 0; b < n; ++b) {
    dst[3 * b + 0] = x[b];
    dst[3 * b + 1] = y[b];
    dst[3 * b + 2] = z[b];
  }
}
}  // namespace sampler

namespace {

using namespace sampler;


bool wants(FieldMask mask, Field f) { return (mask & fieldBit(f)) != 0; }

// Row k of a surface sampler's row buffers is the partial of u-order kPartialOrders[k][0] and
// v-order kPartialOrders[k][1]: point, du, dv, duu, duv, dvv.
constexpr int kPartialOrders[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};

double gridParameter(int a, int samples) { return samples > 1 ? static_cast<double>(a) / (samples - 1) : 0.0; }

// Basis (and singular blend) values of one direction at every grid parameter, laid out so that the
// inner loops run over contiguous samples: b[d][r * samples + a] = B_r^(d)(t_a).
struct DirectionTable {
  int count = 0, samples = 0;
  std::vector<double> b[3];
  std::vector<glm::dvec3> blend;  // (S, S', S'')(t_a)

  const double* row(int d, int r) const { return b[d].data() + static_cast<size_t>(r) * samples; }
};

DirectionTable tabulate(const SpanBasis& basis, int samples) {
  DirectionTable tab;
  tab.count = basis.count;
  tab.samples = samples;
  for (auto& v : tab.b) v.assign(static_cast<size_t>(basis.count) * samples, 0.0);
  tab.blend.resize(samples);
  for (int a = 0; a < samples; ++a) {
    const double t = gridParameter(a, samples);
    double v[3][kMaxBasisCount];
    evalSpanBasis(basis, t, v[0], v[1], v[2]);
    for (int d = 0; d < 3; ++d)
      for (int r = 0; r < basis.count; ++r) tab.b[d][static_cast<size_t>(r) * samples + a] = v[d][r];
    tab.blend[a] = pm::singularBlend(t);
  }
  return tab;
}

// sum_s x[s] * t[s], s = 0..3, summed in that order from 0.0: the order of every four-function
// v-contraction, fused with the quotient rule or not, so that all give the same bits.
inline __attribute__((always_inline)) double orderedSum4(const double x[4], const double t[4]) {
  double acc = 0.0;
  acc += x[0] * t[0];
  acc += x[1] * t[1];
  acc += x[2] * t[2];
  acc += x[3] * t[3];
  return acc;
}

// The v-contraction of one partial: dst[c][b] = sum_s rows[s][b] * T[s * kCoords + c] over the
// samples b < n and the kCoords coordinates c, summed in order s = 0, 1, ... starting from 0.0
// (the order fixes the bits). rows[s] is a tabulated basis row, T the u-contracted net points of the
// sample row (coordinates interleaved). The 4-function families (all Xu-Wang and α-EB bases, cubic
// B-splines) get an unrolled loop that keeps the sums in registers and loads each basis value once
// for all coordinates.
template <int kCoords>
inline __attribute__((always_inline)) void contractCoordRows4(const double* const* rows, const double* T, int n,
                                                              double* const* dst) {
  double t[kCoords][4];
  for (int c = 0; c < kCoords; ++c)
    for (int s = 0; s < 4; ++s) t[c][s] = T[s * kCoords + c];
  // The destination rows are disjoint from the basis rows (ivdep: the compiler cannot see that
  // through the pointer tables, and would not vectorise across samples).
#pragma GCC ivdep
  for (int b = 0; b < n; ++b) {
    const double x[4] = {rows[0][b], rows[1][b], rows[2][b], rows[3][b]};
    for (int c = 0; c < kCoords; ++c) dst[c][b] = orderedSum4(x, t[c]);
  }
}

SHAPESPLINE_HOT_CLONES
void contractCoordRows4x3(const double* const* rows, const double* T, int n, double* const* dst) {
  contractCoordRows4<3>(rows, T, n, dst);
}
SHAPESPLINE_HOT_CLONES
void contractCoordRows4x4(const double* const* rows, const double* T, int n, double* const* dst) {
  contractCoordRows4<4>(rows, T, n, dst);
}

template <int kCoords>
void contractCoordRows(const double* const* rows, const double* T, int m, int n, double* const* dst) {
  if (m == 4) {
    if constexpr (kCoords == 3) return contractCoordRows4x3(rows, T, n, dst);
    if constexpr (kCoords == 4) return contractCoordRows4x4(rows, T, n, dst);
  }
  for (int c = 0; c < kCoords; ++c)
    for (int b = 0; b < n; ++b) {
      double acc = 0.0;
      for (int s = 0; s < m; ++s) acc += rows[s][b] * T[s * kCoords + c];
      dst[c][b] = acc;
    }
}

// The largest row of net values a u-contraction handles: kMaxBasisCount points of 4 coordinates.
constexpr int kMaxNetRow = 4 * kMaxBasisCount;

// The u-contraction of one sample row: T[d][j] = sum_r w[d][r] * net[r][j] for the derivative
// orders d with need[d], over the `width` doubles j of each of the m net rows (consecutive control
// points, coordinates interleaved), summed in order r = 0, 1, ... from 0.0. A fixed width (four
// points of 3 or 4 coordinates: every cubic row) keeps the sums in registers.
template <int kWidth>
inline __attribute__((always_inline)) void contractNetRowsFixed(const double* const* net,
                                                                const double (*w)[kMaxBasisCount], const bool need[3],
                                                                int m, double (*T)[kMaxNetRow]) {
  for (int d = 0; d < 3; ++d) {
    if (!need[d]) continue;
    double acc[kWidth] = {};
    for (int r = 0; r < m; ++r)
      for (int j = 0; j < kWidth; ++j) acc[j] += w[d][r] * net[r][j];
    for (int j = 0; j < kWidth; ++j) T[d][j] = acc[j];
  }
}

SHAPESPLINE_HOT_CLONES
void contractNetRows12(const double* const* net, const double (*w)[kMaxBasisCount], const bool need[3], int m,
                       double (*T)[kMaxNetRow]) {
  contractNetRowsFixed<12>(net, w, need, m, T);
}
SHAPESPLINE_HOT_CLONES
void contractNetRows16(const double* const* net, const double (*w)[kMaxBasisCount], const bool need[3], int m,
                       double (*T)[kMaxNetRow]) {
  contractNetRowsFixed<16>(net, w, need, m, T);
}

void contractNetRows(const double* const* net, const double (*w)[kMaxBasisCount], const bool need[3], int m, int width,
                     double (*T)[kMaxNetRow]) {
  if (width == 12) return contractNetRows12(net, w, need, m, T);
  if (width == 16) return contractNetRows16(net, w, need, m, T);
  for (int d = 0; d < 3; ++d) {
    if (!need[d]) continue;
    for (int j = 0; j < width; ++j) T[d][j] = 0.0;
    for (int r = 0; r < m; ++r) {
      const double wr = w[d][r];
      const double* p = net[r];
#pragma GCC ivdep  // T is the caller's local array, never part of the net
      for (int j = 0; j < width; ++j) T[d][j] += wr * p[j];
    }
  }
}

// The u-contraction of sample row a: T[d][s * kCoords + c] = sum_r B_r^(d)(u_a) P[r][s][c] for the
// derivative orders d with needD[d], over mv consecutive points of each of the mu net rows from P
// (rows `stride` points apart). `Table` is a DirectionTable or a KnotTable (row(d, r): B_r^(d) at
// every sample of the direction).
template <class Table, class Vec>
void contractInU(const Table& tu, int mu, int a, const bool needD[3], const Vec* P, size_t stride, int mv,
                 double (*T)[kMaxNetRow]) {
  static_assert(sizeof(Vec) == Vec::length() * sizeof(double), "net points are read as interleaved doubles");
  double w[3][kMaxBasisCount];
  const double* netRows[kMaxBasisCount];
  for (int r = 0; r < mu; ++r) {
    for (int d = 0; d < 3; ++d) w[d][r] = needD[d] ? tu.row(d, r)[a] : 0.0;
    netRows[r] = &P[static_cast<size_t>(r) * stride][0];
  }
  contractNetRows(netRows, w, needD, mu, mv * Vec::length(), T);
}

// The v-contractions of samples [b0, b1) of a row (one run of a knot-vector row, or a whole uniform
// row): every partial k with need[k] into its rows row(k, c), c < kCoords, from the u-contracted
// T[du] and the v basis rows of order dv. `Table` as in contractInU.
template <int kCoords, class Table, class RowFn>
void contractInV(const Table& tv, int mv, int b0, int b1, const bool need[6], const double (*T)[kMaxNetRow],
                 RowFn row) {
  for (int k = 0; k < 6; ++k) {
    if (!need[k]) continue;
    const int du = kPartialOrders[k][0], dv = kPartialOrders[k][1];
    const double* basisRows[kMaxBasisCount];
    for (int s = 0; s < mv; ++s) basisRows[s] = tv.row(dv, s) + b0;
    double* dst[kCoords];
    for (int c = 0; c < kCoords; ++c) dst[c] = row(k, c) + b0;
    contractCoordRows<kCoords>(basisRows, T[du], mv, b1 - b0, dst);
  }
}


void checkGrid(const GridSpec& grid, size_t items, bool surface, size_t& first, size_t& count) {
  if (grid.samplesU < 2) throw std::invalid_argument("samplesU must be >= 2, got " + std::to_string(grid.samplesU));
  if (surface && grid.samplesV < 2)
    throw std::invalid_argument("samplesV must be >= 2, got " + std::to_string(grid.samplesV));
  if (!surface && grid.samplesV != 1) throw std::invalid_argument("curves sample with samplesV = 1");
  first = grid.firstItem;
  count = grid.itemCount == 0 ? (first <= items ? items - first : 0) : grid.itemCount;
  if (first > items || count > items - first)
    throw std::invalid_argument("item range [" + std::to_string(first) + ", " + std::to_string(first + count) +
                                ") outside the model's " + std::to_string(items) + " items");
}

}  // namespace

std::vector<int> curveGridItems(const Curve& curve) {
  std::vector<int> items;
  const SpanRange r = curve.spans();
  for (int j = r.first; j <= r.last; ++j) {
    if (curve.usesKnotVector()) {
      const auto& k = curve.model().knots;
      if (!(k[j] < k[j + 1])) continue;
    }
    items.push_back(j);
  }
  return items;
}

namespace {

// The patches of range `r` of a surface of shape `m`; knot vectors skip their empty intervals.
SurfaceGridItems gridItemsIn(const PatchRange& r, const SurfaceShape& m) {
  SurfaceGridItems items;
  const bool knotVector = parameterizationOf(m) == Parameterization::KnotVector;
  for (int i = r.u.first; i <= r.u.last; ++i) {
    if (!knotVector || m.knotsU[i] < m.knotsU[i + 1]) items.u.push_back(i);
  }
  for (int j = r.v.first; j <= r.v.last; ++j) {
    if (!knotVector || m.knotsV[j] < m.knotsV[j + 1]) items.v.push_back(j);
  }
  return items;
}

}  // namespace

SurfaceGridItems surfaceGridItems(const SurfaceShape& m) { return gridItemsIn(patchRangeOf(m), m); }

// The surface's own range: a band of patch rows (Surface::patchRows) has fewer than its shape's.
SurfaceGridItems surfaceGridItems(const Surface& surface) { return gridItemsIn(surface.patches(), surface.model()); }

namespace {

// The α-EB data of a span's two vertices (docs/math.md §4.2); `alphaEB` false for plain families.
struct SpanEnds {
  bool alphaEB = false;
  glm::dvec3 v0{0.0}, v1{0.0};
  double a0 = 0.0, a1 = 0.0;
};

// Rows [aBegin, aEnd) of one uniform curve span at points point, point + 1, ...: the table sums
// and, for α-EB, the blend. A function of its own (not inside the sampler's lambda) so that GCC
// keeps the table pointers and sums in registers: inlined into the lambda it spilled them to the
// stack in the r loop (17 stack accesses per iteration), and the CPU α-EB curve rate fell ~10%.
template <class Out>
void sampleSpanRows(const DirectionTable& tab, const glm::dvec3* P, const SpanEnds& ends, double invH, int aBegin,
                    int aEnd, size_t point, Out& out) {
  const size_t S = static_cast<size_t>(tab.samples);
  const double* b0 = tab.b[0].data();
  const double* b1 = tab.b[1].data();
  const double* b2 = tab.b[2].data();
  for (int a = aBegin; a < aEnd; ++a, ++point) {
    glm::dvec3 c0(0.0), c1(0.0), c2(0.0);
    for (int r = 0; r < tab.count; ++r) {
      const size_t k = static_cast<size_t>(r) * S + static_cast<size_t>(a);
      pm::accumulate3(c0, c1, c2, b0[k], b1[k], b2[k], P[r]);
    }
    if (ends.alphaEB) pm::alphaEBBlendCurve(tab.blend[a], ends.v0, ends.v1, ends.a0, ends.a1, c0, c1, c2);
    out.put(Field::Point, point, c0);
    out.put(Field::D1, point, c1 * invH);
    out.put(Field::D2, point, c2 * (invH * invH));
  }
}

// Rows [aBegin, aEnd) of one knot interval of a knot-vector curve: each sample's tabulated basis
// against the control points of its span (the same sums, in the same order, as evalBSplineCurve;
// with `weights`, a rational curve: homogeneous sums and the quotient rule).
template <class Out>
void sampleKnotSpanRows(const KnotTable& tab, const glm::dvec3* points, const double* weights, int aBegin, int aEnd,
                        size_t point, Out& out) {
  for (int a = aBegin; a < aEnd; ++a, ++point) {
    const size_t first = static_cast<size_t>(tab.span[static_cast<size_t>(a)] - tab.order + 1);
    glm::dvec3 c0(0.0), c1(0.0), c2(0.0);
    double w0 = 0.0, w1 = 0.0, w2 = 0.0;
    for (int r = 0; r < tab.order; ++r) {
      const double b0 = tab.row(0, r)[a], b1 = tab.row(1, r)[a], b2 = tab.row(2, r)[a];
      if (!weights) {
        pm::accumulate3(c0, c1, c2, b0, b1, b2, points[first + r]);
        continue;
      }
      const double w = weights[first + r];
      pm::accumulate3(c0, c1, c2, b0, b1, b2, w * points[first + r]);
      w0 += b0 * w, w1 += b1 * w, w2 += b2 * w;
    }
    if (weights) pm::rationalCurve(c0, c1, c2, w0, w1, w2);
    out.put(Field::Point, point, c0);
    out.put(Field::D1, point, c1);
    out.put(Field::D2, point, c2);
  }
}

// The homogeneous partials of a rational row (coordinates 0-2: A, coordinate 3: W) become the
// surface's, in place, sample by sample (point_math.h rationalSurface). Rows of partials that are
// not needed are never written, so they stay zero and the quotient rule keeps them zero: the
// per-sample loop has no branch. kPartials is 3 without second partials, so that the rule's unused
// outputs are dead code.
template <int kPartials>
inline __attribute__((always_inline)) void quotientRule(double* const (*A)[3], const double* const* W, int samples) {
  // The rows are disjoint slices of one buffer: no sample's stores reach another's loads, which
  // the compiler cannot see through the pointer table (ivdep lets it vectorise across samples).
#pragma GCC ivdep
  for (int b = 0; b < samples; ++b) {
    glm::dvec3 q[6] = {};
    double w[6] = {};
    for (int k = 0; k < kPartials; ++k) q[k] = glm::dvec3(A[k][0][b], A[k][1][b], A[k][2][b]), w[k] = W[k][b];
    pm::rationalSurface(q[0], q[1], q[2], q[3], q[4], q[5], w[0], w[1], w[2], w[3], w[4], w[5]);
    for (int k = 0; k < kPartials; ++k)
      for (int c = 0; c < 3; ++c) A[k][c][b] = q[k][c];
  }
}

// The two instances as plain functions, so that they get the AVX2 clone too (CPU NURBS, point +
// du + dv on a 64 x 64 net: 88.9 -> 99.8 Mpts/s at 32 x 32 per patch, docs/performance.md).
SHAPESPLINE_HOT_CLONES
void quotientRuleFirst(double* const (*A)[3], const double* const* W, int samples) { quotientRule<3>(A, W, samples); }
SHAPESPLINE_HOT_CLONES
void quotientRuleSecond(double* const (*A)[3], const double* const* W, int samples) { quotientRule<6>(A, W, samples); }

// Samples [b0, b1) of a rational row. `rows` must start zeroed: see quotientRule.
template <class RowFn>
void rationalRows(const bool need[6], int b0, int b1, RowFn row) {
  double* A[6][3];
  const double* W[6];
  for (int k = 0; k < 6; ++k) {
    for (int c = 0; c < 3; ++c) A[k][c] = row(k, c) + b0;
    W[k] = row(k, 3) + b0;
  }
  if (need[3] || need[4] || need[5]) {
    quotientRuleSecond(A, W, b1 - b0);
  } else {
    quotientRuleFirst(A, W, b1 - b0);
  }
}

// A rational surface's point, du and dv over one run of a row, four-function bases in v: the
// homogeneous sums of contractCoordRows4 (orderedSum4) and the quotient rule of quotientRule<3>, per sample in
// one pass, so that the homogeneous rows never go through memory. rows0/rows1: the v basis rows of
// order 0 and 1; T0/T1: the net contracted in u to order 0 and 1 (coordinates interleaved, W last);
// dst[k][c]: partial k (point, du, dv), coordinate c. The same sums and the same
// pm::rationalSurface call, so the same bits as the two passes.
SHAPESPLINE_HOT_CLONES
void rationalFirstPartials4(const double* const* rows0, const double* const* rows1, const double* T0, const double* T1,
                            int n, double* const (*dst)[3]) {
  double t0[4][4], t1[4][4];  // [coordinate][basis function]
  for (int c = 0; c < 4; ++c)
    for (int s = 0; s < 4; ++s) t0[c][s] = T0[s * 4 + c], t1[c][s] = T1[s * 4 + c];
#pragma GCC ivdep  // dst rows are disjoint from the basis rows
  for (int b = 0; b < n; ++b) {
    const double x[4] = {rows0[0][b], rows0[1][b], rows0[2][b], rows0[3][b]};
    const double y[4] = {rows1[0][b], rows1[1][b], rows1[2][b], rows1[3][b]};
    double h[3][4];  // homogeneous point, du, dv
    for (int c = 0; c < 4; ++c) {
      h[0][c] = orderedSum4(x, t0[c]);
      h[1][c] = orderedSum4(x, t1[c]);
      h[2][c] = orderedSum4(y, t0[c]);
    }
    glm::dvec3 q[6] = {glm::dvec3(h[0][0], h[0][1], h[0][2]), glm::dvec3(h[1][0], h[1][1], h[1][2]),
                       glm::dvec3(h[2][0], h[2][1], h[2][2]), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
    pm::rationalSurface(q[0], q[1], q[2], q[3], q[4], q[5], h[0][3], h[1][3], h[2][3], 0.0, 0.0, 0.0);
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) dst[k][c][b] = q[k][c];
  }
}


// Row a of knot interval pair (i, j) of a knot-vector surface: the partials need[k] (kPartialOrders)
// at every v sample into the structure-of-arrays rows row(k, c), c < 3. As in the uniform path, the
// net is contracted in u with row a's tabulated basis, then each needed row is one contraction over
// the v basis rows; once per run of v samples that share a span (the last sample may lie on the
// next). A dvec4 net is the homogeneous net (w P, w) of a rational surface: its rows have a fourth
// coordinate, W, and the quotient rule turns each run into the surface's partials.
template <class Vec, class RowFn>
void knotRowPartials(const KnotTable& tu, const KnotTable& tv, const Vec* net, int cols, int a, const bool need[6],
                     RowFn row) {
  constexpr int kCoords = Vec::length();
  constexpr bool rational = kCoords == 4;  // the homogeneous net (w P, w)
  const int mu = tu.order, mv = tv.order;
  const Vec* P = net + static_cast<size_t>(tu.span[static_cast<size_t>(a)] - mu + 1) * cols;
  const bool needD[3] = {true, need[1] || need[4], need[3]};
  for (int b0 = 0; b0 < tv.samples;) {
    const int b1 = tv.runEnd(b0);
    const int firstV = tv.span[static_cast<size_t>(b0)] - mv + 1;
    double T[3][kMaxNetRow];
    contractInU(tu, mu, a, needD, P + firstV, static_cast<size_t>(cols), mv, T);
    if (rational && mv == 4 && need[1] && need[2] && !need[3] && !need[4] && !need[5]) {
      const double* rows0[4] = {tv.row(0, 0) + b0, tv.row(0, 1) + b0, tv.row(0, 2) + b0, tv.row(0, 3) + b0};
      const double* rows1[4] = {tv.row(1, 0) + b0, tv.row(1, 1) + b0, tv.row(1, 2) + b0, tv.row(1, 3) + b0};
      double* const dst[3][3] = {{row(0, 0) + b0, row(0, 1) + b0, row(0, 2) + b0},
                                 {row(1, 0) + b0, row(1, 1) + b0, row(1, 2) + b0},
                                 {row(2, 0) + b0, row(2, 1) + b0, row(2, 2) + b0}};
      rationalFirstPartials4(rows0, rows1, T[0], T[1], b1 - b0, dst);
    } else {
      contractInV<kCoords>(tv, mv, b0, b1, need, T, row);
      if (rational) rationalRows(need, b0, b1, row);
    }
    b0 = b1;
  }
}

}  // namespace

void sampleCurveGrid(const Curve& curve, const GridSpec& grid, FieldMask fields, const ChunkConsumer& consumer,
                     const SamplerOptions& options) {
  if (fields & ~kCurveFields) throw std::invalid_argument("curves provide the fields point, d1 and d2 only");
  const std::vector<int> items = curveGridItems(curve);
  size_t first = 0, count = 0;
  checkGrid(grid, items.size(), false, first, count);
  const int S = grid.samplesU;
  const DirectionTable tab = tabulate(curve.basis(), S);
  const bool alphaEB = curve.model().family.construction == Construction::AlphaEB;
  const auto& knots = curve.spanKnots();
  const int firstSpan = curve.spans().first;
  const int n = static_cast<int>(curve.model().points.size());

  std::optional<KnotTables> knotTables;
  if (curve.usesKnotVector()) {
    const BSplineCurveData& d = curve.knotData();
    knotTables.emplace(d.order, d.knots, static_cast<int>(d.points.size()), S);
  }

  auto computeItem = [&](auto& out, KnotTable& scratch, size_t item, int aBegin, int aEnd, size_t point) {
    const int span = items[item];
    if (curve.usesKnotVector()) {
      const KnotTable& tab = knotTables->of(span, scratch);
      if (!tab.scaled) {
        const BSplineCurveData& d = curve.knotData();
        sampleKnotSpanRows(tab, d.points.data(), d.weights.empty() ? nullptr : d.weights.data(), aBegin, aEnd, point,
                           out);
        return;
      }
      for (int a = aBegin; a < aEnd; ++a, ++point) {
        const CurvePoint cp = curve.evaluate(span, gridParameter(a, S));
        out.put(Field::Point, point, cp.point), out.put(Field::D1, point, cp.d1), out.put(Field::D2, point, cp.d2);
      }
      return;
    }
    const glm::dvec3* P = curve.spanPoints().data() + span + curve.spanPointOffset();
    const double invH = knots.empty() ? 1.0 : 1.0 / (knots[span - firstSpan + 1] - knots[span - firstSpan]);
    SpanEnds ends;
    if (alphaEB) {
      const int j1 = (span + 1) % n;
      ends = {true, curve.alphaV()[span], curve.alphaV()[j1], curve.alphas()[span], curve.alphas()[j1]};
    }
    sampleSpanRows(tab, P, ends, invH, aBegin, aEnd, point, out);
  };
  auto compute = [&](auto&& out, size_t begin, size_t end, size_t firstPoint) {
    KnotTable scratch;  // a knot interval's table when the job's tables are over their budget
    forEachItemRows(begin, end, static_cast<size_t>(S), 1, firstPoint, [&](size_t item, int a0, int a1, size_t point) {
      computeItem(out, scratch, item, a0, a1, point);
    });
  };
  runChunked(ChunkPlan(first, count, static_cast<size_t>(S), 1, options.maxChunkPoints), fields, options, consumer,
             compute);
}

void sampleSurfaceGrid(const Surface& surface, const GridSpec& grid, FieldMask fields,
                       const ChunkConsumer& consumer, const SamplerOptions& options) {
  if (fields & ~kSurfaceFields)
    throw std::invalid_argument("surfaces provide the fields point, du, dv, duu, duv, dvv and normal only");
  const auto items = surfaceGridItems(surface);
  size_t first = 0, count = 0;
  checkGrid(grid, items.size(), true, first, count);
  const int Su = grid.samplesU, Sv = grid.samplesV;
  const DirectionTable tu = tabulate(surface.basisU(), Su), tv = tabulate(surface.basisV(), Sv);
  const SurfaceShape& model = surface.model();
  const bool alphaEB = model.family.construction == Construction::AlphaEB;
  const bool normal = wants(fields, Field::Normal);
  // Which partials of the base surface the requested fields need (α-EB second partials need the
  // first ones too, docs/math.md §5.3).
  const bool needUU = wants(fields, Field::Duu), needVV = wants(fields, Field::Dvv), needUV = wants(fields, Field::Duv);
  // A rational surface (weights) is sampled from its homogeneous net (w P, w): four coordinates,
  // then the quotient rule per sample, whose second partials use the first ones too.
  const bool rational = surface.usesKnotVector() && !surface.knotData().weights.empty();
  const bool needU = wants(fields, Field::Du) || normal || ((needUU || needUV) && (alphaEB || rational));
  const bool needV = wants(fields, Field::Dv) || normal || ((needVV || needUV) && (alphaEB || rational));
  const int mu = tu.count, mv = tv.count;
  static constexpr int kOutputField[6] = {int(Field::Point), int(Field::Du),  int(Field::Dv),
                                          int(Field::Duu),   int(Field::Duv), int(Field::Dvv)};
  const bool need[6] = {true, needU, needV, needUU, needUV, needVV};
  std::optional<KnotTables> knotsU, knotsV;
  std::vector<glm::dvec4> homogeneous;
  if (surface.usesKnotVector()) {
    const BSplineSurfaceData& d = surface.knotData();
    knotsU.emplace(d.orderU, d.knotsU, d.rows, Su);
    knotsV.emplace(d.orderV, d.knotsV, d.cols, Sv);
    if (rational) homogeneous = homogeneousPoints(d.points, d.weights);
  }

  auto compute = [&](auto&& out, size_t rowBegin, size_t rowEnd, size_t firstPoint) {
    // Row buffers (structure of arrays over v samples): C, Cu, Cv, Cuu, Cuv, Cvv per coordinate.
    std::vector<double> rows(static_cast<size_t>(6 * 4) * Sv);  // coordinate 3: W of a rational surface
    auto row = [&](int k, int c) { return rows.data() + static_cast<size_t>(k * 4 + c) * Sv; };
    const double* fieldRows[kFieldCount][3] = {};  // the rows of each computed output field
    for (int k = 0; k < 6; ++k)
      if (need[k])
        for (int c = 0; c < 3; ++c) fieldRows[kOutputField[k]][c] = row(k, c);
    KnotTable scratchU, scratchV;  // knot interval tables when the job's are over their budget
    forEachItemRows(rowBegin, rowEnd, static_cast<size_t>(Su), static_cast<size_t>(Sv), firstPoint,
                    [&](size_t item, int aBegin, int aEnd, size_t point) {
      const auto [i, j] = items[item];
      const KnotTable* knotU = nullptr;
      const KnotTable* knotV = nullptr;
      if (surface.usesKnotVector()) {
        knotU = &knotsU->of(i, scratchU);
        knotV = &knotsV->of(j, scratchV);
      }
      if (knotU && (knotU->scaled || knotV->scaled)) {
        // Knot intervals near 1e-310: per point, through the scaled partials of evalBSplineSurface.
        for (int a = aBegin; a < aEnd; ++a)
          for (int b = 0; b < Sv; ++b, ++point) {
            const SurfacePoint sp = surface.evaluate(i, j, gridParameter(a, Su), gridParameter(b, Sv));
            out.put(Field::Point, point, sp.point), out.put(Field::Du, point, sp.du), out.put(Field::Dv, point, sp.dv);
            out.put(Field::Duu, point, sp.duu), out.put(Field::Duv, point, sp.duv);
            out.put(Field::Dvv, point, sp.dvv), out.put(Field::Normal, point, sp.normal);
          }
        return;
      }
      const int stride = knotU ? surface.knotData().cols : surface.netCols();
      const glm::dvec3* P = knotU ? surface.knotData().points.data()
                                  : surface.patchNet().data() + static_cast<size_t>(i + surface.netOffsetU()) * stride +
                                        (j + surface.netOffsetV());
      double alpha[4] = {0, 0, 0, 0};
      glm::dvec3 V[4] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
      if (alphaEB) {  // corners (i,j), (i,j+1), (i+1,j), (i+1,j+1), wrapped in closed directions
        const int i1 = (i + 1) % model.rows, j1 = (j + 1) % model.cols;
        const int ci[4] = {i, i, i1, i1}, cj[4] = {j, j1, j, j1};
        for (int k = 0; k < 4; ++k) {
          alpha[k] = surface.alphas()[static_cast<size_t>(ci[k]) * model.cols + cj[k]];
          V[k] = surface.alphaVertex(ci[k], cj[k]);
        }
      }
      for (int a = aBegin; a < aEnd; ++a) {
        if (knotU) {
          if (rational) {
            knotRowPartials(*knotU, *knotV, homogeneous.data(), stride, a, need, row);
          } else {
            knotRowPartials(*knotU, *knotV, P, stride, a, need, row);
          }
        } else {
          const bool needD[3] = {true, needU || needUV, needUU};
          double T[3][kMaxNetRow];
          contractInU(tu, mu, a, needD, P, static_cast<size_t>(stride), mv, T);
          contractInV<3>(tv, mv, 0, Sv, need, T, row);
        }
        if (!alphaEB && !normal) {
          // Plain partials: the rows go out as they are (into interleaved planes, or records).
          out.putRows(fieldRows, Sv, point);
          point += static_cast<size_t>(Sv);
          continue;
        }
        const pm::BlendFactors fu = pm::blendFactors(tu.blend[a]);
        const double uA = gridParameter(a, Su);
        for (int b = 0; b < Sv; ++b, ++point) {
          glm::dvec3 q[6];
          for (int k = 0; k < 6; ++k) q[k] = need[k] ? glm::dvec3(row(k, 0)[b], row(k, 1)[b], row(k, 2)[b]) : glm::dvec3(0.0);
          if (alphaEB) {
            // docs/math.md §5.3, only the orders the requested fields need (need[] already includes
            // the first partials that α-EB second partials use); the skipped ones feed no output.
            const pm::BlendFactors fv = pm::blendFactors(tv.blend[b]);
            pm::AlphaEBWeights w = pm::alphaEBWeightsZero();
            pm::cornerBlend(fu.f00, fu.f01, fv.f00, fv.f01, alpha, V, w.a00, w.L00);
            if (need[1]) pm::cornerBlend(fu.f10, fu.f11, fv.f00, fv.f01, alpha, V, w.a10, w.L10);
            if (need[2]) pm::cornerBlend(fu.f00, fu.f01, fv.f10, fv.f11, alpha, V, w.a01, w.L01);
            if (need[3]) pm::cornerBlend(fu.f20, fu.f21, fv.f00, fv.f01, alpha, V, w.a20, w.L20);
            if (need[4]) pm::cornerBlend(fu.f10, fu.f11, fv.f10, fv.f11, alpha, V, w.a11, w.L11);
            if (need[5]) pm::cornerBlend(fu.f00, fu.f01, fv.f20, fv.f21, alpha, V, w.a02, w.L02);
            if (need[3] || need[4] || need[5]) pm::alphaEBBlendSecond(w, q[0], q[1], q[2], q[3], q[4], q[5]);
            pm::alphaEBBlendFirst(w, q[0], q[1], q[2]);
          }
          for (int k = 0; k < 6; ++k) out.put(static_cast<Field>(kOutputField[k]), point, q[k]);
          if (normal) {
            const bool corner = (a == 0 || a == Su - 1) && (b == 0 || b == Sv - 1);
            glm::dvec3 n;
            // Corners of α-EB patches and degenerate crosses follow the full §5.3 convention.
            if ((alphaEB && corner) || !unitNormal(q[1], q[2], n))
              out.put(Field::Normal, point, surface.evaluate(i, j, uA, gridParameter(b, Sv)).normal);
            else
              out.put(Field::Normal, point, n);
          }
        }
      }
    });
  };
  runChunked(ChunkPlan(first, count, static_cast<size_t>(Su), static_cast<size_t>(Sv), options.maxChunkPoints), fields,
             options, consumer, compute);
}

}  // namespace shapespline
