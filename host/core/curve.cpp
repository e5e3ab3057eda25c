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

std::vector<ExtendedIndex> extendedIndices(int n, bool closed, bool phantom, int count, int centre, int& offset) {
  std::vector<ExtendedIndex> out;
  if (phantom) {
    offset = 0;
    const int size = closed ? n + 3 : n + 2;
    out.resize(size);
    for (int i = 0; i < size; ++i) {
      const int k = i - 1;  // entry i is P_{i-1}
      if (closed) {
        out[i] = {wrap(k, n), 0, 1.0, 0.0};
      } else if (k < 0) {
        out[i] = {0, 1, 2.0, -1.0};  // P_{-1} = 2 P_0 - P_1
      } else if (k >= n) {
        out[i] = {n - 1, n - 2, 2.0, -1.0};  // P_n = 2 P_{n-1} - P_{n-2}
      } else {
        out[i] = {k, 0, 1.0, 0.0};
      }
    }
    return out;
  }
  if (closed) {
    offset = 0;
    out.resize(n + count - 1);
    for (int i = 0; i < n + count - 1; ++i) out[i] = {wrap(i - centre, n), 0, 1.0, 0.0};
  } else {
    offset = -centre;
    out.resize(n);
    for (int i = 0; i < n; ++i) out[i] = {i, 0, 1.0, 0.0};
  }
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
  if (c.alphaEB()) {
    c.spans_ = {0, m.closed ? n - 1 : n - 2};
  } else {
    c.spans_ = m.closed ? SpanRange{0, n - 1} : SpanRange{centre, n - count + centre};
  }
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
  if (!spanKnots_.empty()) {
    const int s = span - spans_.first;
    return spanKnots_[s] + t * (spanKnots_[s + 1] - spanKnots_[s]);
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

CurvePoint Curve::evaluate(int span, double t) const {
  if (span < spans_.first || span > spans_.last) throwSpan(span, spans_);
  checkLocal("t", t);
  if (knotVector()) {
    const double a = bspline_.knots[span], b = bspline_.knots[span + 1];
    if (!(b > a))
      throw std::out_of_range("span " + std::to_string(span) + " is the empty knot interval [" + preciseText(a) + ", " +
                              preciseText(b) + "]");
    const BSplineCurvePoint p = evalBSplineCurve(bspline_, a + t * (b - a));
    return {p.point, p.d1, p.d2};
  }
  return evalSpan(span, t);
}

CurvePoint Curve::evaluateAt(double u) const {
  const auto [lo, hi] = parameterRange();
  if (!(u >= lo && u <= hi))
    throw std::out_of_range("u = " + preciseText(u) + " outside the parameter range [" + preciseText(lo) + ", " + preciseText(hi) + "]");
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
