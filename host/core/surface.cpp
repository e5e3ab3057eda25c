#include <shapespline/core/surface.h>

#include <shapespline/core/huge_pages.h>
#include <shapespline/core/point_math.h>
#include <shapespline/core/validate.h>
#include <shapespline/core/value_scan.h>
#include <shapespline/core/value_text.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace shapespline {

static_assert(kNormalShift == pm::kNormalShift && kNormalDegeneracy == pm::kNormalDegeneracy,
              "the public §5.3 constants are the shared ones");

namespace {

std::string rangeText(const SpanRange& r) {
  return "[" + std::to_string(r.first) + ", " + std::to_string(r.last) + "]";
}

void checkLocal(const char* name, double t) {
  if (!(t >= 0.0 && t <= 1.0))
    throw std::out_of_range(std::string(name) + " = " + preciseText(t) + " outside the local parameter range [0, 1]");
}

// A patch-net index sequence for one direction, plus the knot interval range for B-splines.
SpanRange knotIntervals(int order, int n) { return {order - 1, n - 1}; }

}  // namespace

// ---- Raw kernels --------------------------------------------------------------------------------

void evalTensorPatch(const SpanBasis& bu, const SpanBasis& bv, const glm::dvec3* net, int stride, double u,
                     double v, PatchDerivs& out) {
  double b0[kMaxBasisCount], b1[kMaxBasisCount], b2[kMaxBasisCount];
  double c0[kMaxBasisCount], c1[kMaxBasisCount], c2[kMaxBasisCount];
  evalSpanBasis(bu, u, b0, b1, b2);
  evalSpanBasis(bv, v, c0, c1, c2);
  PatchDerivs d;
  for (int r = 0; r < bu.count; ++r) {
    // Row r contracted with the v basis first: three v-partials of one row curve.
    glm::dvec3 row0(0.0), row1(0.0), row2(0.0);
    const glm::dvec3* p = net + static_cast<ptrdiff_t>(r) * stride;
    for (int s = 0; s < bv.count; ++s) pm::accumulate3(row0, row1, row2, c0[s], c1[s], c2[s], p[s]);
    pm::accumulateTensorRow(d.p, d.u, d.v, d.uu, d.uv, d.vv, b0[r], b1[r], b2[r], row0, row1, row2);
  }
  out = d;
}

SurfaceFirst evalTensorPatchFirst(const SpanBasis& bu, const SpanBasis& bv, const glm::dvec3* net, int stride, double u,
                                  double v, bool derivatives) {
  double b0[kMaxBasisCount], b1[kMaxBasisCount], c0[kMaxBasisCount], c1[kMaxBasisCount];
  evalSpanBasis(bu, u, b0, derivatives ? b1 : nullptr, nullptr);
  evalSpanBasis(bv, v, c0, derivatives ? c1 : nullptr, nullptr);
  SurfaceFirst d;
  for (int r = 0; r < bu.count; ++r) {
    // evalTensorPatch's sums, in its order, less the second partials.
    glm::dvec3 row0(0.0), row1(0.0);
    const glm::dvec3* p = net + static_cast<ptrdiff_t>(r) * stride;
    if (derivatives) {
      for (int s = 0; s < bv.count; ++s) row0 += c0[s] * p[s], row1 += c1[s] * p[s];
      pm::accumulateTensorRowFirst(d.point, d.du, d.dv, b0[r], b1[r], row0, row1);
    } else {
      for (int s = 0; s < bv.count; ++s) row0 += c0[s] * p[s];
      d.point += b0[r] * row0;
    }
  }
  return d;
}

void evalAlphaEBPatch(const SpanBasis& basis, const glm::dvec3* net, int stride, const glm::dvec3 V[4],
                      const double alpha[4], double u, double v, PatchDerivs& out, PatchDerivs* base) {
  PatchDerivs c;
  evalTensorPatch(basis, basis, net, stride, u, v, c);
  const pm::AlphaEBWeights w = pm::alphaEBWeights(pm::singularBlend(u), pm::singularBlend(v), alpha, V);
  PatchDerivs q = c;
  pm::alphaEBBlendPatch(w, q.p, q.u, q.v, q.uu, q.uv, q.vv);
  out = q;
  if (base) *base = c;
}

glm::dvec3 alphaEBCornerNormal(const glm::dvec3& p, const glm::dvec3& node, const glm::dvec3& vU, double alphaU,
                               const glm::dvec3& vV, double alphaV, double sU, double sV) {
  glm::dvec3 axisU, axisV;
  pm::alphaEBCornerAxes(p, node, vU, alphaU, vV, alphaV, sU, sV, axisU, axisV);
  return glm::cross(axisU, axisV);
}

bool degenerateCross(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& cross) {
  return pm::degenerateCross(a, b, cross);
}

glm::dvec3 unitScaled(const glm::dvec3& a) {
  const double m = std::max(std::abs(a.x), std::max(std::abs(a.y), std::abs(a.z)));
  if (!(m > 0.0) || !std::isfinite(m)) return a;
  const int e = std::ilogb(m);
  return {std::ldexp(a.x, -e), std::ldexp(a.y, -e), std::ldexp(a.z, -e)};
}

namespace {
double maxAbs(const glm::dvec3& a) { return std::max(std::abs(a.x), std::max(std::abs(a.y), std::abs(a.z))); }
}  // namespace

bool unitNormal(const glm::dvec3& a, const glm::dvec3& b, glm::dvec3& n) {
  // Fast path: with every component magnitude in [2^-240, 2^240] the cross product, the lengths and
  // their products neither overflow nor underflow, so the exact power-of-two scaling below would
  // not change a bit (and ilogb/ldexp cost more than the rest of a grid sample).
  constexpr double kLo = 0x1p-240, kHi = 0x1p240;
  const double ma = maxAbs(a), mb = maxAbs(b);
  if (ma > kLo && ma < kHi && mb > kLo && mb < kHi) {
    const glm::dvec3 x = glm::cross(a, b);
    if (degenerateCross(a, b, x)) return false;
    n = x / glm::length(x);
    return true;
  }
  const glm::dvec3 sa = unitScaled(a), sb = unitScaled(b);
  const glm::dvec3 x = glm::cross(sa, sb);
  if (degenerateCross(sa, sb, x)) return false;
  n = x / glm::length(x);
  return true;
}

// ---- Surface ------------------------------------------------------------------------------------

namespace {

// Net index of P_0 along one direction: extendedIndices puts point k at entry k + this, a plain copy.
int firstPointEntry(bool phantom, bool closed, int centre) { return phantom ? 1 : closed ? centre : 0; }

// Net entry (a, b) from the points (`at(i, j)` = P_ij) and the extended indices x = eu[a], y = ev[b]:
// a plain copy gives the point's own bits. The one formula of an entry, whether the net is built whole
// (netInPlace) or a band of rows at a time (Surface::bandOf).
template <class At>
glm::dvec3 netEntry(const ExtendedIndex& x, const ExtendedIndex& y, At&& at) {
  auto rowPoint = [&](int i) { return y.w1 == 0.0 ? at(i, y.i0) : y.w0 * at(i, y.i0) + y.w1 * at(i, y.i1); };
  return x.w1 == 0.0 ? rowPoint(x.i0) : x.w0 * rowPoint(x.i0) + x.w1 * rowPoint(x.i1);
}

// The patch net built inside the points' own block (grown to the net's size), so that a big net
// never exists twice: entries outside the block of plain copies (phantoms, wrapped rows and
// columns) are computed first, while every point is in place, then the points move to their net
// positions (last row first: a row never moves to a lower index), then those entries are written.
// Entry (a, b) combines rows first, then columns (the order of §5.1's text); the u and v rules are
// linear and act on different indices, so they commute.
std::vector<glm::dvec3> netInPlace(std::vector<glm::dvec3> points, int rows, int cols,
                                   const std::vector<ExtendedIndex>& eu, const std::vector<ExtendedIndex>& ev,
                                   int row0, int col0) {
  const size_t netRows = eu.size(), netCols = ev.size(), pointCols = static_cast<size_t>(cols);
  auto copies = [](const std::vector<ExtendedIndex>& e, int first, int n) {
    for (int k = 0; k < n; ++k) {
      const ExtendedIndex& x = e[static_cast<size_t>(first + k)];
      if (x.i0 != k || x.w1 != 0.0) return false;
    }
    return true;
  };
  if (!copies(eu, row0, rows) || !copies(ev, col0, cols))
    throw std::logic_error("netInPlace: the extended indices do not copy the points where expected");
  auto entry = [&](size_t a, size_t b) {
    return netEntry(eu[a], ev[b], [&](int i, int j) { return points[static_cast<size_t>(i) * pointCols + j]; });
  };
  auto isCopy = [&](size_t a, size_t b) {
    return a >= static_cast<size_t>(row0) && a < static_cast<size_t>(row0 + rows) && b >= static_cast<size_t>(col0) &&
           b < static_cast<size_t>(col0 + cols);
  };
  std::vector<glm::dvec3> border;
  for (size_t a = 0; a < netRows; ++a)
    for (size_t b = 0; b < netCols; ++b)
      if (!isCopy(a, b)) border.push_back(entry(a, b));
  // Huge pages (core/huge_pages.h); a reader that reserved room for the net (netCapacity) saves
  // the copy that growing the block would make.
  reserveHuge(points, netRows * netCols);
  points.resize(netRows * netCols);
  for (size_t i = static_cast<size_t>(rows); i-- > 0;) {
    const size_t to = (i + static_cast<size_t>(row0)) * netCols + static_cast<size_t>(col0), from = i * pointCols;
    if (to != from) std::memmove(&points[to], &points[from], pointCols * sizeof(glm::dvec3));
  }
  size_t next = 0;
  for (size_t a = 0; a < netRows; ++a)
    for (size_t b = 0; b < netCols; ++b)
      if (!isCopy(a, b)) points[a * netCols + b] = border[next++];
  return points;
}

// True when no α-EB vertex V = P + ((1-α)/α)(P - node) can leave fp64 (§4.2): with M the largest
// |coordinate| of the net, f the largest (1-α)/α and node = Σ w_r w_s (net entries) at (0,0),
// |V| <= M + f (M + Σ|w_r| Σ|w_s| M). (1-α)/α falls as α grows in (0,1] (validated), so f is that
// of the smallest α. A factor 4 below the largest double leaves room for the rounding of each sum;
// an infinite f or M gives false.
bool verticesSurelyFinite(double netMagnitude, double smallestAlpha, const double weightU[3], const double weightV[3]) {
  const double m = netMagnitude;
  const double f = (1.0 - smallestAlpha) / smallestAlpha;
  const double node = (std::abs(weightU[0]) + std::abs(weightU[1]) + std::abs(weightU[2])) *
                      (std::abs(weightV[0]) + std::abs(weightV[1]) + std::abs(weightV[2])) * m;
  const double bound = m + f * (m + node);
  return bound < std::numeric_limits<double>::max() / 4;
}

// The v direction's span basis: a bspline surface's own v order, else the u basis.
SpanBasis basisVOf(const SurfaceShape& m, const SpanBasis& basisU) {
  return familyOf(m.family.construction).twoOrders && m.orderV > 0 ? uniformBSplineSpanBasis(m.orderV) : basisU;
}

// The span bases at 0 (b_0..b_2 of u and v): the weights of α-EB node_ij.
void nodeWeightsOf(const SpanBasis& u, const SpanBasis& v, double weightU[3], double weightV[3]) {
  double d1[kMaxBasisCount], d2[kMaxBasisCount], u0[kMaxBasisCount], v0[kMaxBasisCount];
  evalSpanBasis(u, 0.0, u0, d1, d2);
  evalSpanBasis(v, 0.0, v0, d1, d2);
  std::copy(u0, u0 + 3, weightU);
  std::copy(v0, v0 + 3, weightV);
}

}  // namespace

Parameterization parameterizationOf(const SurfaceShape& m) {
  return parameterizationOf(m.family.construction, !m.knotsU.empty() || !m.knotsV.empty());
}

PatchRange patchRangeOf(const SurfaceShape& m) {
  if (parameterizationOf(m) == Parameterization::KnotVector) {
    const int orderV = m.orderV > 0 ? m.orderV : m.family.order;
    return {knotIntervals(m.family.order, m.rows), knotIntervals(orderV, m.cols)};
  }
  const bool alphaEB = m.family.construction == Construction::AlphaEB;
  const SpanBasis u = makeSpanBasis(m.family), v = basisVOf(m, u);
  auto range = [&](int n, bool closed, const SpanBasis& b) {
    if (alphaEB) return SpanRange{0, closed ? n - 1 : n - 2};
    return closed ? SpanRange{0, n - 1} : SpanRange{b.centre, n - b.count + b.centre};
  };
  return {range(m.rows, m.closedU, u), range(m.cols, m.closedV, v)};
}

bool alphaEBVerticesSurelyFinite(const SurfaceShape& m, double pointMagnitude, double smallestAlpha) {
  const SpanBasis u = makeSpanBasis(m.family), v = basisVOf(m, u);
  // The net's entries are the points and phantoms w0 P + w1 P' (§5.1): at most Σ|w| times the
  // points' magnitude per direction.
  auto spread = [](int n, bool closed, const SpanBasis& b) {
    int offset = 0;
    double most = 1.0;
    for (const ExtendedIndex& e : extendedIndices(n, closed, true, b.count, b.centre, offset))
      most = std::max(most, std::abs(e.w0) + std::abs(e.w1));
    return most;
  };
  double weightU[3], weightV[3];
  nodeWeightsOf(u, v, weightU, weightV);
  const double net = pointMagnitude * spread(m.rows, m.closedU, u) * spread(m.cols, m.closedV, v);
  return verticesSurelyFinite(net, smallestAlpha, weightU, weightV);
}

size_t netCapacity(int rows, int cols) {
  // Every family's net has at most kMaxBasisCount - 1 more entries per direction than points
  // (extendedIndices: closed uniform families wrap count - 1, α-EB adds 2 or 3).
  return static_cast<size_t>(rows + kMaxBasisCount) * static_cast<size_t>(cols + kMaxBasisCount);
}

Surface Surface::create(SurfaceModel model) {
  validateSurface(model);
  Surface s;
  std::vector<glm::dvec3> points = std::move(model.points);
  std::vector<double> weights = std::move(model.weights);
  s.model_ = std::move(static_cast<SurfaceShape&>(model));
  const SurfaceShape& m = s.model_;

  s.parameterization_ = parameterizationOf(m);
  if (s.knotVector()) {
    s.bspline_.orderU = m.family.order;
    s.bspline_.orderV = m.orderV > 0 ? m.orderV : m.family.order;
    s.bspline_.knotsU = m.knotsU;
    s.bspline_.knotsV = m.knotsV;
    s.bspline_.rows = m.rows;
    s.bspline_.cols = m.cols;
    s.bspline_.points = std::move(points);
    s.bspline_.weights = std::move(weights);
    s.patches_ = patchRangeOf(m);
    return s;
  }

  std::vector<ExtendedIndex> eu, ev;
  s.layOut(m, eu, ev);
  s.net_ = netInPlace(std::move(points), m.rows, m.cols, eu, ev, s.pointRow_, s.pointCol_);
  s.requireFiniteVertices(0, m.rows);
  return s;
}

void Surface::layOut(const SurfaceShape& m, std::vector<ExtendedIndex>& eu, std::vector<ExtendedIndex>& ev) {
  parameterization_ = parameterizationOf(m);
  basisU_ = makeSpanBasis(m.family);
  basisV_ = basisVOf(m, basisU_);
  patches_ = patchRangeOf(m);
  eu = extendedIndices(m.rows, m.closedU, alphaEB(), basisU_.count, basisU_.centre, offU_);
  ev = extendedIndices(m.cols, m.closedV, alphaEB(), basisV_.count, basisV_.centre, offV_);
  netRows_ = static_cast<int>(eu.size());
  netCols_ = static_cast<int>(ev.size());
  pointRow_ = firstPointEntry(alphaEB(), m.closedU, basisU_.centre);
  pointCol_ = firstPointEntry(alphaEB(), m.closedV, basisV_.centre);
  // At (0,0) only b_0..b_2 are nonzero in each direction (b_3(0) = 0, §2.3), so node_ij reads the
  // 3 x 3 block around P_ij: a 4 x 4 block would read past the extended net for the last row of an
  // open direction (and into the next row for the last column).
  if (alphaEB()) nodeWeightsOf(basisU_, basisV_, nodeWeightU_, nodeWeightV_);
}

void Surface::requireFiniteVertices(int firstRow, int wholeRows) const {
  if (!alphaEB()) return;
  const SurfaceShape& m = model_;
  // Every V within fp64 (a tiny α makes V overflow, §4.2): ModelError naming the first vertex
  // that breaks the rule. Computing every V was a fifth of building a 4096² net, so a bound over
  // the whole net comes first, and only a net it cannot clear is checked vertex by vertex.
  if (verticesSurelyFinite(largestMagnitude(reinterpret_cast<const double*>(net_.data()), 3 * net_.size()),
                           valueRange(m.alpha.data(), m.alpha.size()).min, nodeWeightU_, nodeWeightV_))
    return;
  for (int i = 0; i < m.rows; ++i) {
    for (int j = 0; j < m.cols; ++j) {
      (void)alphaEBVertex(controlPoint(i, j), alphaNode(i, j), m.alpha[static_cast<size_t>(i) * m.cols + j], [&, i, j] {
        return "alpha[" + std::to_string((firstRow + i) % wholeRows) + "][" + std::to_string(j) + "]";
      });
    }
  }
}

Surface Surface::bandShell(const SurfaceShape& whole, int first, int last) const {
  if (knotVector() || first < patches_.u.first || last > patches_.u.last || first > last) {
    throw std::invalid_argument("Surface band: rows " + std::to_string(first) + ".." + std::to_string(last) +
                                " are not patch rows of a uniform-span surface");
  }
  const int count = last - first + 1;
  Surface b;
  b.parameterization_ = parameterization_;
  b.basisU_ = basisU_;
  b.basisV_ = basisV_;
  b.patches_ = {{0, count - 1}, patches_.v};
  // Patch i reads net rows i + offU_ .. i + offU_ + m - 1 (m = basisU_.count).
  b.netRows_ = count + basisU_.count - 1;
  b.netCols_ = netCols_;
  b.offU_ = 0;
  b.offV_ = offV_;
  SurfaceShape& m = b.model_;
  m.family = whole.family;
  m.orderV = whole.orderV;
  m.closedU = false;
  m.closedV = whole.closedV;
  m.cols = whole.cols;
  b.pointCol_ = pointCol_;
  if (!alphaEB()) {
    // Only the net is evaluated; its rows stand for the point rows (what a GPU mirror uploads).
    m.rows = b.netRows_;
    b.pointRow_ = 0;
    return b;
  }
  // α-EB: vertex rows first..last+1 (the last one wrapped in a closed u direction), whose α the
  // caller adds; the net rows are those the nodes and V read (alphaNode: rows i..i+2), and P_kj is
  // net entry (k + 1, j + pointCol_) as in the whole surface's net.
  std::copy(nodeWeightU_, nodeWeightU_ + 3, b.nodeWeightU_);
  std::copy(nodeWeightV_, nodeWeightV_ + 3, b.nodeWeightV_);
  m.rows = count + 1;
  b.pointRow_ = pointRow_;
  return b;
}

Surface Surface::patchRows(int first, int last) const {
  Surface b = bandShell(model_, first, last);
  const size_t netFirst = static_cast<size_t>(first + offU_), netRows = static_cast<size_t>(b.netRows_);
  b.net_.assign(net_.begin() + static_cast<std::ptrdiff_t>(netFirst * netCols_),
                net_.begin() + static_cast<std::ptrdiff_t>((netFirst + netRows) * netCols_));
  if (!alphaEB()) return b;
  const size_t cols = static_cast<size_t>(model_.cols);
  for (int k = 0; k < b.model_.rows; ++k) {
    const size_t row = static_cast<size_t>((first + k) % model_.rows) * cols;
    b.model_.alpha.insert(b.model_.alpha.end(), model_.alpha.begin() + static_cast<std::ptrdiff_t>(row),
                          model_.alpha.begin() + static_cast<std::ptrdiff_t>(row + cols));
  }
  return b;
}

std::vector<int> Surface::bandPointRows(const SurfaceShape& shape, int first, int last) {
  Surface layout;
  std::vector<ExtendedIndex> eu, ev;
  layout.layOut(shape, eu, ev);
  (void)layout.bandShell(shape, first, last);  // refuses rows outside the patches, and knot vectors
  std::vector<int> rows;
  for (int a = first + layout.offU_; a < first + layout.offU_ + layout.basisU_.count + last - first; ++a) {
    rows.push_back(eu[static_cast<size_t>(a)].i0);
    if (eu[static_cast<size_t>(a)].w1 != 0.0) rows.push_back(eu[static_cast<size_t>(a)].i1);
  }
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  return rows;
}

Surface Surface::bandOf(const SurfaceShape& shape, int first, int last, const PointRowOf& pointRow,
                        const AlphaRowOf& alphaRow) {
  Surface layout;
  std::vector<ExtendedIndex> eu, ev;
  layout.layOut(shape, eu, ev);
  Surface b = layout.bandShell(shape, first, last);
  const size_t netFirst = static_cast<size_t>(first + layout.offU_), netCols = static_cast<size_t>(b.netCols_);
  b.net_.resize(static_cast<size_t>(b.netRows_) * netCols);
  for (size_t a = 0; a < static_cast<size_t>(b.netRows_); ++a) {
    const ExtendedIndex& x = eu[netFirst + a];
    const glm::dvec3* rows[2] = {pointRow(x.i0), x.w1 != 0.0 ? pointRow(x.i1) : nullptr};
    auto at = [&](int i, int j) { return rows[i == x.i0 ? 0 : 1][j]; };
    for (size_t c = 0; c < netCols; ++c) b.net_[a * netCols + c] = netEntry(x, ev[c], at);
  }
  if (!layout.alphaEB()) return b;
  const size_t cols = static_cast<size_t>(shape.cols);
  b.model_.alpha.reserve(static_cast<size_t>(b.model_.rows) * cols);
  for (int k = 0; k < b.model_.rows; ++k) {
    const double* a = alphaRow((first + k) % shape.rows);
    b.model_.alpha.insert(b.model_.alpha.end(), a, a + cols);
  }
  b.requireFiniteVertices(first, shape.rows);
  return b;
}

std::vector<glm::dvec3> Surface::controlPoints() const {
  std::vector<glm::dvec3> points;
  reserveHuge(points, static_cast<size_t>(model_.rows) * model_.cols);
  forEachControlPoint([&](const glm::dvec3& p) { points.push_back(p); });
  return points;
}

SurfaceModel Surface::toModel() const {
  SurfaceModel m;
  static_cast<SurfaceShape&>(m) = model_;
  m.points = controlPoints();
  m.weights = weights();
  return m;
}

glm::dvec3 Surface::alphaNode(int i, int j) const {
  // C_ij(0,0) as evalTensorPatch sums it (rows contracted along v first), so the bits are the same.
  const glm::dvec3* net = &net_[static_cast<size_t>(i) * netCols_ + j];
  glm::dvec3 p(0.0);
  for (int r = 0; r < 3; ++r) {
    glm::dvec3 row(0.0);
    for (int s = 0; s < 3; ++s) row += nodeWeightV_[s] * net[static_cast<size_t>(r) * netCols_ + s];
    p += nodeWeightU_[r] * row;
  }
  return p;
}

glm::dvec3 Surface::alphaVertex(int i, int j) const {
  // create() checked the rule (V within fp64) for every vertex; the same arithmetic here.
  return pm::alphaEBVertex(controlPoint(i, j), alphaNode(i, j), model_.alpha[static_cast<size_t>(i) * model_.cols + j]);
}

std::vector<glm::dvec3> Surface::alphaV() const {
  std::vector<glm::dvec3> v;
  if (!alphaEB()) return v;
  v.reserve(static_cast<size_t>(model_.rows) * model_.cols);
  for (int i = 0; i < model_.rows; ++i)
    for (int j = 0; j < model_.cols; ++j) v.push_back(alphaVertex(i, j));
  return v;
}

std::vector<glm::dvec3> Surface::alphaNodes() const {
  std::vector<glm::dvec3> nodes;
  if (!alphaEB()) return nodes;
  nodes.reserve(static_cast<size_t>(model_.rows) * model_.cols);
  for (int i = 0; i < model_.rows; ++i)
    for (int j = 0; j < model_.cols; ++j) nodes.push_back(alphaNode(i, j));
  return nodes;
}

std::pair<double, double> Surface::parameterRangeU() const {
  if (knotVector()) return {bspline_.knotsU[bspline_.orderU - 1], bspline_.knotsU[bspline_.rows]};
  return {static_cast<double>(patches_.u.first), static_cast<double>(patches_.u.last + 1)};
}

std::pair<double, double> Surface::parameterRangeV() const {
  if (knotVector()) return {bspline_.knotsV[bspline_.orderV - 1], bspline_.knotsV[bspline_.cols]};
  return {static_cast<double>(patches_.v.first), static_cast<double>(patches_.v.last + 1)};
}

std::pair<double, double> Surface::parameterOf(int i, int j, double u, double v) const {
  if (i < patches_.u.first || i > patches_.u.last || j < patches_.v.first || j > patches_.v.last)
    throw std::out_of_range("patch (" + std::to_string(i) + ", " + std::to_string(j) +
                            ") outside the valid patch range " + rangeText(patches_.u) + " x " +
                            rangeText(patches_.v));
  if (knotVector()) {
    const double u0 = bspline_.knotsU[i], u1 = bspline_.knotsU[i + 1];
    const double v0 = bspline_.knotsV[j], v1 = bspline_.knotsV[j + 1];
    return {u0 + u * (u1 - u0), v0 + v * (v1 - v0)};
  }
  return {i + u, j + v};
}

void Surface::evalPatch(int i, int j, double u, double v, PatchDerivs& out, PatchDerivs& base) const {
  if (knotVector()) {
    const double u0 = bspline_.knotsU[i], u1 = bspline_.knotsU[i + 1];
    const double v0 = bspline_.knotsV[j], v1 = bspline_.knotsV[j + 1];
    const BSplineSurfacePoint p = evalBSplineSurface(bspline_, u0 + u * (u1 - u0), v0 + v * (v1 - v0));
    out = {p.point, p.du, p.dv, p.duu, p.duv, p.dvv};
    base = out;
    // The normal's partials: scaled by powers of two, so still finite (with the same normal) where
    // knot intervals near 1e-310 make du, dv overflow.
    base.u = p.duDir, base.v = p.dvDir;
    return;
  }
  const glm::dvec3* net = &net_[static_cast<size_t>(i + offU_) * netCols_ + (j + offV_)];
  if (!alphaEB()) {
    evalTensorPatch(basisU_, basisV_, net, netCols_, u, v, out);
    base = out;
    return;
  }
  const int i1 = i + 1 == model_.rows ? 0 : i + 1;  // only reached in closed directions
  const int j1 = j + 1 == model_.cols ? 0 : j + 1;
  const size_t k00 = static_cast<size_t>(i) * model_.cols + j, k01 = static_cast<size_t>(i) * model_.cols + j1;
  const size_t k10 = static_cast<size_t>(i1) * model_.cols + j, k11 = static_cast<size_t>(i1) * model_.cols + j1;
  const glm::dvec3 V[4] = {alphaVertex(i, j), alphaVertex(i, j1), alphaVertex(i1, j), alphaVertex(i1, j1)};
  const double alpha[4] = {model_.alpha[k00], model_.alpha[k01], model_.alpha[k10], model_.alpha[k11]};
  evalAlphaEBPatch(basisU_, net, netCols_, V, alpha, u, v, out, &base);
}

bool Surface::cornerLimit(int i, int j, int cu, int cv, glm::dvec3& n) const {
  const int rows = model_.rows, cols = model_.cols;
  const int p = (i + cu) % rows, q = (j + cv) % cols;          // the vertex
  const int pn = (i + 1 - cu) % rows, qn = (j + 1 - cv) % cols;  // its neighbours inside the patch
  const size_t kv = static_cast<size_t>(p) * cols + q;
  if (model_.alpha[kv] != 1.0) return false;
  const size_t ku = static_cast<size_t>(pn) * cols + q, kw = static_cast<size_t>(p) * cols + qn;
  const glm::dvec3& P = controlPoint(p, q);
  const glm::dvec3 c = alphaEBCornerNormal(P, alphaNode(p, q), alphaVertex(pn, q), model_.alpha[ku], alphaVertex(p, qn),
                                           model_.alpha[kw],
                                           cu == 0 ? 1.0 : -1.0, cv == 0 ? 1.0 : -1.0);
  // Scaled before the length so that |c|^2 neither overflows nor underflows for extreme nets.
  const glm::dvec3 s = unitScaled(c);
  const double len = glm::length(s);
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  n = s / len;
  return true;
}

SurfacePoint Surface::evalWithNormal(int i, int j, double u, double v) const {
  PatchDerivs q, c;
  evalPatch(i, j, u, v, q, c);
  SurfacePoint out;
  out.point = q.p;
  out.du = q.u;
  out.dv = q.v;
  out.duu = q.uu;
  out.duv = q.uv;
  out.dvv = q.vv;

  // 1. α = 1 vertex at an exact patch corner: diagonal limit.
  if (alphaEB() && (u == 0.0 || u == 1.0) && (v == 0.0 || v == 1.0)) {
    glm::dvec3 n;
    if (cornerLimit(i, j, u == 0.0 ? 0 : 1, v == 0.0 ? 0 : 1, n)) {
      out.normal = n;
      out.normalRule = NormalRule::CornerLimit;
      return out;
    }
  }
  // 2. Regular point (knot vectors: the partials scaled to stay finite, see evalPatch).
  if (unitNormal(knotVector() ? c.u : q.u, knotVector() ? c.v : q.v, out.normal)) {
    out.normalRule = NormalRule::Regular;
    return out;
  }
  // 3. Moved towards the patch centre by δ in each parameter.
  PatchDerivs qs, cs;
  evalPatch(i, j, pm::towardCentre(u), pm::towardCentre(v), qs, cs);
  if (unitNormal(knotVector() ? cs.u : qs.u, knotVector() ? cs.v : qs.v, out.normal)) {
    out.normalRule = NormalRule::Shifted;
    return out;
  }
  // 4. Base surface at the original point.
  if (unitNormal(c.u, c.v, out.normal)) {
    out.normalRule = NormalRule::Base;
    return out;
  }
  out.normal = pm::fixedAxisNormal();
  out.normalRule = NormalRule::FixedAxis;
  return out;
}

void Surface::checkPatchQuery(int i, int j, double u, double v) const {
  if (i < patches_.u.first || i > patches_.u.last || j < patches_.v.first || j > patches_.v.last)
    throw std::out_of_range("patch (" + std::to_string(i) + ", " + std::to_string(j) +
                            ") outside the valid patch range " + rangeText(patches_.u) + " x " +
                            rangeText(patches_.v));
  checkLocal("u", u);
  checkLocal("v", v);
  if (knotVector()) {
    if (!(bspline_.knotsU[i + 1] > bspline_.knotsU[i]) || !(bspline_.knotsV[j + 1] > bspline_.knotsV[j]))
      throw std::out_of_range("patch (" + std::to_string(i) + ", " + std::to_string(j) +
                              ") is an empty knot interval");
  }
}

SurfacePoint Surface::evaluate(int i, int j, double u, double v) const {
  checkPatchQuery(i, j, u, v);
  return evalWithNormal(i, j, u, v);
}

void Surface::checkGlobalQuery(double U, double V) const {
  const auto [ulo, uhi] = parameterRangeU();
  const auto [vlo, vhi] = parameterRangeV();
  if (!(U >= ulo && U <= uhi) || !(V >= vlo && V <= vhi))
    throw std::out_of_range("(U, V) = (" + preciseText(U) + ", " + preciseText(V) + ") outside the parameter range [" + preciseText(ulo) +
                            ", " + preciseText(uhi) + "] x [" + preciseText(vlo) + ", " + preciseText(vhi) + "]");
}

SurfacePoint Surface::evaluateAt(double U, double V) const {
  checkGlobalQuery(U, V);
  int i = 0, j = 0;
  double u = 0.0, v = 0.0;
  patchAt(U, V, i, j, u, v);
  return evalWithNormal(i, j, u, v);
}

SurfaceFirst Surface::evalFirst(int i, int j, double u, double v, bool derivatives, SurfaceListCache& cache) const {
  if (knotVector()) {
    // The knot parameter as evalPatch forms it, so that the span and bits are evalPatch's.
    const double u0 = bspline_.knotsU[i], u1 = bspline_.knotsU[i + 1];
    const double v0 = bspline_.knotsV[j], v1 = bspline_.knotsV[j + 1];
    const BSplineSurfaceFirst p = evalBSplineSurfaceFirst(bspline_, u0 + u * (u1 - u0), v0 + v * (v1 - v0),
                                                          derivatives, cache.u, cache.v);
    return {p.point, p.du, p.dv};
  }
  const glm::dvec3* net = &net_[static_cast<size_t>(i + offU_) * netCols_ + (j + offV_)];
  if (!alphaEB()) return evalTensorPatchFirst(basisU_, basisV_, net, netCols_, u, v, derivatives);
  // α-EB: the blend's weights read the base partials, so both are computed (§5.3).
  PatchDerivs q, c;
  evalPatch(i, j, u, v, q, c);
  return derivatives ? SurfaceFirst{q.p, q.u, q.v} : SurfaceFirst{q.p, glm::dvec3(0.0), glm::dvec3(0.0)};
}

SurfaceFirst Surface::evaluateFirst(int i, int j, double u, double v, bool derivatives, SurfaceListCache& cache) const {
  checkPatchQuery(i, j, u, v);
  return evalFirst(i, j, u, v, derivatives, cache);
}

SurfaceFirst Surface::evaluateFirstAt(double U, double V, bool derivatives, SurfaceListCache& cache) const {
  checkGlobalQuery(U, V);
  int i = 0, j = 0;
  double u = 0.0, v = 0.0;
  patchAtFrom(U, V, cache.u.span, cache.v.span, i, j, u, v);
  return evalFirst(i, j, u, v, derivatives, cache);
}

glm::dvec3 Surface::limitNormal(int i, int j, int cornerU, int cornerV) const {
  if (!alphaEB()) throw std::logic_error("limitNormal: only α-EB surfaces have α = 1 vertices");
  if (i < patches_.u.first || i > patches_.u.last || j < patches_.v.first || j > patches_.v.last)
    throw std::out_of_range("patch (" + std::to_string(i) + ", " + std::to_string(j) +
                            ") outside the valid patch range " + rangeText(patches_.u) + " x " +
                            rangeText(patches_.v));
  if ((cornerU != 0 && cornerU != 1) || (cornerV != 0 && cornerV != 1))
    throw std::out_of_range("limitNormal: corner indices must be 0 or 1");
  const int p = (i + cornerU) % model_.rows, q = (j + cornerV) % model_.cols;
  if (model_.alpha[static_cast<size_t>(p) * model_.cols + q] != 1.0)
    throw std::logic_error("limitNormal: vertex (" + std::to_string(p) + ", " + std::to_string(q) +
                           ") has alpha != 1");
  return evalWithNormal(i, j, cornerU, cornerV).normal;
}

void Surface::patchAt(double U, double V, int& i, int& j, double& u, double& v) const {
  patchAtFrom(U, V, -1, -1, i, j, u, v);
}

void Surface::patchAtFrom(double U, double V, int hintU, int hintV, int& i, int& j, double& u, double& v) const {
  if (knotVector()) {
    i = findKnotSpanFrom(hintU, bspline_.orderU, bspline_.knotsU, bspline_.rows, U);
    j = findKnotSpanFrom(hintV, bspline_.orderV, bspline_.knotsV, bspline_.cols, V);
    u = std::clamp((U - bspline_.knotsU[i]) / (bspline_.knotsU[i + 1] - bspline_.knotsU[i]), 0.0, 1.0);
    v = std::clamp((V - bspline_.knotsV[j]) / (bspline_.knotsV[j + 1] - bspline_.knotsV[j]), 0.0, 1.0);
    return;
  }
  auto unitPatch = [](double x, const SpanRange& r, double& local) {
    const int k = std::clamp(static_cast<int>(std::floor(x)), r.first, r.last);
    local = std::clamp(x - k, 0.0, 1.0);
    return k;
  };
  i = unitPatch(U, patches_.u, u);
  j = unitPatch(V, patches_.v, v);
}

}  // namespace shapespline
