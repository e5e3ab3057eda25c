#include <shapespline/core/curve.h>

#include <shapespline/core/point_math.h>
#include <shapespline/core/validate.h>
#include <shapespline/core/value_text.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace shapespline {

namespace {

[[noreturn]] void throwSpan(int span, SpanRange r) {
  throw std::out_of_range("span " + std::to_string(span) + " outside the valid span range [" +
                          std::to_string(r.first) + ", " + std::to_string(r.last) + "]");
}

void checkLocal(const char* name, double t) {
  // Written so that NaN fails too.
  if (!(t >= 0.0 && t <= 1.0))
    throw std::out_of_range(std::string(name) + " = " + preciseText(t) + " outside the local parameter range [0, 1]");
}

int wrap(int i, int n) { return ((i % n) + n) % n; }

}  // namespace

// ---- Raw kernels --------------------------------------------------------------------------------

void evalLocalSpan(const SpanBasis& basis, const glm::dvec3* pts, double t, double invH, CurvePoint& out) {
  double b[kMaxBasisCount], d1[kMaxBasisCount], d2[kMaxBasisCount];
  evalSpanBasis(basis, t, b, d1, d2);
  glm::dvec3 p(0.0), q1(0.0), q2(0.0);
  for (int r = 0; r < basis.count; ++r) pm::accumulate3(p, q1, q2, b[r], d1[r], d2[r], pts[r]);
  out.point = p;
  out.d1 = q1 * invH;
  out.d2 = q2 * (invH * invH);
}

void evalAlphaEBSpan(const SpanBasis& basis, const glm::dvec3* pts, const glm::dvec3& v0, const glm::dvec3& v1,
                     double a0, double a1, double t, CurvePoint& out) {
  CurvePoint c;
  evalLocalSpan(basis, pts, t, 1.0, c);
  pm::alphaEBBlendCurve(pm::singularBlend(t), v0, v1, a0, a1, c.point, c.d1, c.d2);
  out = c;
}

glm::dvec3 alphaEBVertex(const glm::dvec3& p, const glm::dvec3& node, double alpha,
                         const std::function<std::string()>& field) {
  const glm::dvec3 v = pm::alphaEBVertex(p, node, alpha);
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
    const glm::dvec3 d = p - node;
    const double dist = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    throw ModelError(field(), shortestText(alpha),
                     "alpha is so small that V = P + ((1-alpha)/alpha)(P - node) exceeds the fp64 range (|P - node| = " +
                         shortestText(dist) +
                         "; docs/math.md section 4.2): alpha must be at least about |P - node| / 1.8e308");
  }
  return v;
}

// ---- Helpers ------------------------------------------------------------------------------------

ExtendedIndex extendedIndex(int i, int n, bool closed, bool phantom, int count, int centre) {
  (void)count;
  if (phantom) {
    const int k = i - 1;  // entry i is P_{i-1}
    if (closed) return {wrap(k, n), 0, 1.0, 0.0};
    if (k < 0) return {0, 1, 2.0, -1.0};            // P_{-1} = 2 P_0 - P_1
    if (k >= n) return {n - 1, n - 2, 2.0, -1.0};   // P_n = 2 P_{n-1} - P_{n-2}
    return {k, 0, 1.0, 0.0};
  }
  if (closed) return {wrap(i - centre, n), 0, 1.0, 0.0};
  return {i, 0, 1.0, 0.0};
}

int extendedSize(int n, bool closed, bool phantom, int count) {
  if (phantom) return closed ? n + 3 : n + 2;
  return closed ? n + count - 1 : n;
}

int extendedOffset(bool closed, bool phantom, int centre) { return phantom || closed ? 0 : -centre; }

std::vector<ExtendedIndex> extendedIndices(int n, bool closed, bool phantom, int count, int centre, int& offset) {
  offset = extendedOffset(closed, phantom, centre);
  std::vector<ExtendedIndex> out(static_cast<size_t>(extendedSize(n, closed, phantom, count)));
  for (size_t i = 0; i < out.size(); ++i) out[i] = extendedIndex(static_cast<int>(i), n, closed, phantom, count, centre);
  return out;
}

// ---- Curve --------------------------------------------------------------------------------------

Curve Curve::create(CurveModel model) {
  validateCurve(model);
  Curve c;
  c.model_ = std::move(model);
  const CurveModel& m = c.model_;
  const int n = static_cast<int>(m.points.size());
  const Construction kind = m.family.construction;

  c.parameterization_ = parameterizationOf(kind, !m.knots.empty());
  if (c.knotVector()) {
    c.bspline_.order = m.family.order;
    c.bspline_.knots = m.knots;
    c.bspline_.points = m.points;
    c.bspline_.weights = m.weights;
    c.spans_ = {m.family.order - 1, n - 1};
    return c;
  }

  c.basis_ = makeSpanBasis(m.family);
  const int count = c.basis_.count, centre = c.basis_.centre;
  c.spans_ = uniformCurveSpans(m, n);
  const std::vector<ExtendedIndex> ext =
      extendedIndices(n, m.closed, c.alphaEB(), count, centre, c.spanPointOffset_);
  c.spanPoints_.resize(ext.size());
  for (size_t i = 0; i < ext.size(); ++i)
    c.spanPoints_[i] = ext[i].w1 == 0.0 ? m.points[ext[i].i0]
                                        : ext[i].w0 * m.points[ext[i].i0] + ext[i].w1 * m.points[ext[i].i1];
  if (kind == Construction::ExtendedBSpline || kind == Construction::GB) c.spanKnots_ = m.knots;

  if (c.alphaEB()) {
    // node_j = C_j(0) and V_j, once per model (§14).
    c.nodes_.resize(n);
    c.v_.resize(n);
    // At t = 0 only b_0..b_2 are nonzero (b_3(0) = 0, §2.3), so node_j reads P_{j-1..j+1}: with four
    // points the last node of an open curve would read one entry past the extended polygon.
    SpanBasis nodeBasis = c.basis_;
    nodeBasis.count = 3;
    for (int j = 0; j < n; ++j) {
      CurvePoint node;
      evalLocalSpan(nodeBasis, &c.spanPoints_[j], 0.0, 1.0, node);
      c.nodes_[j] = node.point;
      c.v_[j] = alphaEBVertex(m.points[j], node.point, m.alpha[j], [j] { return "alpha[" + std::to_string(j) + "]"; });
    }
  }
  return c;
}

SpanRange uniformCurveSpans(const CurveModel& m, int n) {
  if (m.family.construction == Construction::AlphaEB) return {0, m.closed ? n - 1 : n - 2};
  const SpanBasis basis = makeSpanBasis(m.family);
  return m.closed ? SpanRange{0, n - 1} : SpanRange{basis.centre, n - basis.count + basis.centre};
}

std::vector<int> Curve::bandPoints(const CurveModel& m, int n, int first, int last) {
  const SpanBasis basis = makeSpanBasis(m.family);
  const bool phantom = m.family.construction == Construction::AlphaEB;
  const int offset = extendedOffset(m.closed, phantom, basis.centre);
  std::vector<int> points;
  for (int e = first + offset; e < last + offset + basis.count; ++e) {
    const ExtendedIndex x = extendedIndex(e, n, m.closed, phantom, basis.count, basis.centre);
    points.push_back(x.i0);
    if (x.w1 != 0.0) points.push_back(x.i1);
  }
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  return points;
}

Curve Curve::bandOf(const CurveModel& whole, int n, int first, int last, const PointOf& pointOf,
                    const AlphaOf& alphaOf) {
  const SpanRange spans = uniformCurveSpans(whole, n);
  const Parameterization kind = parameterizationOf(whole.family.construction, !whole.knots.empty());
  if (kind == Parameterization::KnotVector)
    throw std::invalid_argument("Curve band: a knot-vector curve is not split into bands");
  if (first < spans.first || last > spans.last || first > last)
    throw std::invalid_argument("Curve band: spans " + std::to_string(first) + ".." + std::to_string(last) +
                                " are not spans of the curve");
  Curve b;
  b.parameterization_ = kind;
  b.basis_ = makeSpanBasis(whole.family);
  const int count = last - first + 1;
  b.spans_ = {0, count - 1};
  const bool phantom = b.alphaEB();
  // Span j reads entries j + offset + r, r < basis count: the band's entries are those of its spans.
  const int offset = extendedOffset(whole.closed, phantom, b.basis_.centre);
  b.spanPoints_.resize(static_cast<size_t>(count + b.basis_.count - 1));
  for (size_t i = 0; i < b.spanPoints_.size(); ++i) {
    const ExtendedIndex x =
        extendedIndex(first + offset + static_cast<int>(i), n, whole.closed, phantom, b.basis_.count, b.basis_.centre);
    b.spanPoints_[i] = x.w1 == 0.0 ? *pointOf(x.i0) : x.w0 * *pointOf(x.i0) + x.w1 * *pointOf(x.i1);
  }
  CurveModel& m = b.model_;
  m.family = whole.family;
  m.dimension = whole.dimension;
  m.closed = false;
  if (!whole.knots.empty())  // span knots κ_s of spans first..last
    m.knots.assign(whole.knots.begin() + (first - spans.first), whole.knots.begin() + (last - spans.first + 2));
  b.spanKnots_ = m.knots;
  if (!phantom) {
    m.points = b.spanPoints_;  // plain copies of the points (what the net's scale is planned from)
    return b;
  }
  // α-EB: vertices first..last+1 (the last wrapped in a closed curve), whose nodes read entries
  // k..k+2 of the band as node_j reads j..j+2 of the whole curve (create()).
  SpanBasis nodeBasis = b.basis_;
  nodeBasis.count = 3;
  for (int k = 0; k <= count; ++k) {
    const int j = (first + k) % n;
    m.points.push_back(*pointOf(j));
    m.alpha.push_back(*alphaOf(j));
    CurvePoint node;
    evalLocalSpan(nodeBasis, &b.spanPoints_[static_cast<size_t>(k)], 0.0, 1.0, node);
    b.nodes_.push_back(node.point);
    b.v_.push_back(alphaEBVertex(m.points.back(), node.point, m.alpha.back(),
                                 [j] { return "alpha[" + std::to_string(j) + "]"; }));
  }
  return b;
}

std::pair<double, double> Curve::parameterRange() const {
  if (knotVector()) {
    const int k = bspline_.order, n = static_cast<int>(bspline_.points.size());
    return {bspline_.knots[k - 1], bspline_.knots[n]};
  }
  if (!spanKnots_.empty()) return {spanKnots_.front(), spanKnots_.back()};
  return {static_cast<double>(spans_.first), static_cast<double>(spans_.last + 1)};
}

double Curve::parameterOf(int span, double t) const {
  if (span < spans_.first || span > spans_.last) throwSpan(span, spans_);
  if (knotVector()) {
    const double a = bspline_.knots[span], b = bspline_.knots[span + 1];
    return a + t * (b - a);
  }
  return uniformSpanParameter(spanKnots_, spans_, span, t);
}

double uniformSpanParameter(const std::vector<double>& spanKnots, SpanRange spans, int span, double t) {
  if (!spanKnots.empty()) {
    const int s = span - spans.first;
    return spanKnots[s] + t * (spanKnots[s + 1] - spanKnots[s]);
  }
  return span + t;
}

CurvePoint Curve::evalSpan(int span, double t) const {
  CurvePoint out;
  if (alphaEB()) {
    const int n = static_cast<int>(model_.points.size());
    const int j1 = span + 1 == n ? 0 : span + 1;  // only reached for closed curves
    evalAlphaEBSpan(basis_, &spanPoints_[span], v_[span], v_[j1], model_.alpha[span], model_.alpha[j1], t, out);
    return out;
  }
  double invH = 1.0, h = 1.0;
  if (!spanKnots_.empty()) {
    const int s = span - spans_.first;
    h = spanKnots_[s + 1] - spanKnots_[s];
    invH = 1.0 / h;
  }
  if (!std::isfinite(invH)) {
    // h below 1/DBL_MAX (a subnormal knot interval): 1/h overflows, q/h need not (and 0/h is 0,
    // where 0 * inf would be NaN). A derivative beyond fp64 still overflows here, and is refused
    // where it is written.
    evalLocalSpan(basis_, &spanPoints_[span + spanPointOffset_], t, 1.0, out);
    out.d1 /= h;
    out.d2 = out.d2 / h / h;
    return out;
  }
  evalLocalSpan(basis_, &spanPoints_[span + spanPointOffset_], t, invH, out);
  return out;
}

void Curve::checkSpanQuery(int span, double t) const {
  if (span < spans_.first || span > spans_.last) throwSpan(span, spans_);
  checkLocal("t", t);
  if (knotVector()) {
    const double a = bspline_.knots[span], b = bspline_.knots[span + 1];
    if (!(b > a))
      throw std::out_of_range("span " + std::to_string(span) + " is the empty knot interval [" + preciseText(a) + ", " +
                              preciseText(b) + "]");
  }
}

void Curve::checkGlobalQuery(double u) const {
  const auto [lo, hi] = parameterRange();
  if (!(u >= lo && u <= hi))
    throw std::out_of_range("u = " + preciseText(u) + " outside the parameter range [" + preciseText(lo) + ", " + preciseText(hi) + "]");
}

CurvePoint Curve::evaluate(int span, double t) const {
  checkSpanQuery(span, t);
  if (knotVector()) {
    const double a = bspline_.knots[span], b = bspline_.knots[span + 1];
    const BSplineCurvePoint p = evalBSplineCurve(bspline_, a + t * (b - a));
    return {p.point, p.d1, p.d2};
  }
  return evalSpan(span, t);
}

CurveFirst Curve::evaluateFirst(int span, double t, bool derivatives, KnotBasisCache& cache) const {
  checkSpanQuery(span, t);
  if (knotVector()) {
    const double a = bspline_.knots[span], b = bspline_.knots[span + 1];
    const BSplineCurveFirst p = evalBSplineCurveFirst(bspline_, a + t * (b - a), derivatives, cache);
    return {p.point, p.d1};
  }
  const CurvePoint p = evalSpan(span, t);
  return {p.point, derivatives ? p.d1 : glm::dvec3(0.0)};
}

CurveFirst Curve::evaluateFirstAt(double u, bool derivatives, KnotBasisCache& cache) const {
  checkGlobalQuery(u);
  if (knotVector()) {
    const BSplineCurveFirst p = evalBSplineCurveFirst(bspline_, u, derivatives, cache);
    return {p.point, p.d1};
  }
  double t = 0.0;
  const int span = spanAt(u, t);
  const CurvePoint p = evalSpan(span, t);
  return {p.point, derivatives ? p.d1 : glm::dvec3(0.0)};
}

CurvePoint Curve::evaluateAt(double u) const {
  checkGlobalQuery(u);
  if (knotVector()) {
    // At the knot parameter itself, not a + t (b - a): evalBSplineCurve finds the span of spanAt.
    const BSplineCurvePoint p = evalBSplineCurve(bspline_, u);
    return {p.point, p.d1, p.d2};
  }
  double t = 0.0;
  const int span = spanAt(u, t);
  return evalSpan(span, t);
}

int Curve::spanAt(double u, double& t) const {
  if (knotVector()) {
    const int n = static_cast<int>(bspline_.points.size());
    const int span = findKnotSpan(bspline_.order, bspline_.knots, n, u);
    const double a = bspline_.knots[span], b = bspline_.knots[span + 1];
    t = std::clamp((u - a) / (b - a), 0.0, 1.0);
    return span;
  }
  if (!spanKnots_.empty()) {
    const auto it = std::upper_bound(spanKnots_.begin(), spanKnots_.end(), u);
    int s = static_cast<int>(it - spanKnots_.begin()) - 1;
    s = std::clamp(s, 0, static_cast<int>(spanKnots_.size()) - 2);
    t = (u - spanKnots_[s]) / (spanKnots_[s + 1] - spanKnots_[s]);
    t = std::clamp(t, 0.0, 1.0);
    return spans_.first + s;
  }
  int j = static_cast<int>(std::floor(u));
  j = std::clamp(j, spans_.first, spans_.last);
  t = std::clamp(u - j, 0.0, 1.0);
  return j;
}

}  // namespace shapespline
