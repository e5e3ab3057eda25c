#pragma once
// Curve evaluation on the CPU in fp64 (docs/math.md §1, §2, §4, §7–§10).
//
// Two tiers, as in tinynurbs: raw kernels over plain arrays (no allocation, fixed maximum order)
// built from the per-point formulas of core/point_math.h, which the GLSL kernels include too, and
// the typed `Curve`, built once from a validated CurveModel, that owns the precomputed data (span
// basis, span point list, α-EB nodes and V points) and maps spans / global parameters to kernel
// calls.
//
// Span point list ("span points"): every uniform construction is stored as one contiguous array
// `spanPoints()` such that span j reads the m = basis.count points spanPoints()[j + spanPointOffset()
// + r], r = 0..m-1, i.e. P_{j-c+r} of docs/math.md §1 with closed indices already wrapped (R2) and, for
// α-EB, the phantom points of §4.1 already in place. The GPU uploads this array and never wraps.
#include <shapespline/core/bspline.h>
#include <shapespline/core/model.h>
#include <shapespline/core/span_basis.h>

#include <glm/vec3.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace shapespline {

// A point of a curve and its first two derivatives with respect to the GLOBAL parameter u
// (docs/math.md §1 and R16: span knots divide the t-derivatives by h^r; knot-vector B-splines use the
// knot parameter).
struct CurvePoint {
  glm::dvec3 point{0.0}, d1{0.0}, d2{0.0};
};

// The point and first derivative alone (the list kernel, core/list_eval.h): CurvePoint's bits.
struct CurveFirst {
  glm::dvec3 point{0.0}, d1{0.0};
};

// Inclusive span index range [first, last] (docs/math.md §1 / §4.1).
struct SpanRange {
  int first = 0, last = -1;
};

// ---- Raw kernels (their formulas: core/point_math.h, shared with GLSL) ------------------------

// One span of a local family: C(t) = sum_r B_r(t) pts[r], r < basis.count (docs/math.md §1), and its
// derivatives times invH^1 and invH^2 (invH = 1/h_s for span knots, else 1).
void evalLocalSpan(const SpanBasis& basis, const glm::dvec3* pts, double t, double invH, CurvePoint& out);

// One α-EB span (docs/math.md §4.2): pts = P_{j-1..j+2} of the extended polygon (4 points), v0/v1 =
// V_j/V_{j+1}, a0/a1 = α_j/α_{j+1}. Q = C + a (L - C) with a, L blended by the singular blend S (§3).
void evalAlphaEBSpan(const SpanBasis& basis, const glm::dvec3* pts, const glm::dvec3& v0, const glm::dvec3& v1,
                     double a0, double a1, double t, CurvePoint& out);

// V_j = P_j + ((1-α_j)/α_j)(P_j - node_j) (docs/math.md §4.2, §5.2). Throws ModelError(field, α, ...)
// when V_j is beyond the fp64 range (α so small that |P_j - node_j| / α overflows): every point of
// the two spans at P_j depends on V_j, so such a model cannot be evaluated (it is refused, exit 2).
// `field` gives the field name ("alpha[3]"), called only then.
glm::dvec3 alphaEBVertex(const glm::dvec3& p, const glm::dvec3& node, double alpha,
                         const std::function<std::string()>& field);

// ---- Typed curve --------------------------------------------------------------------------------

class Curve {
 public:
  // Validates (core/validate.h, throws ModelError) and precomputes everything evaluation needs.
  static Curve create(CurveModel model);

  const CurveModel& model() const { return model_; }
  int dimension() const { return model_.dimension; }
  // True for `bspline` with a knot vector (docs/math.md §10.1); evaluation then goes through
  // core/bspline.h and the parameter is the knot parameter.
  // Decided once here from the family table (core/family.h); every layer dispatches on it.
  Parameterization parameterization() const { return parameterization_; }
  bool usesKnotVector() const { return knotVector(); }
  // The knot-vector B-spline itself (order, knots, points; usesKnotVector() only).
  const BSplineCurveData& knotData() const { return bspline_; }

  // Valid spans. Local families: docs/math.md §1 (open j = c..N-m+c, closed 0..N-1); α-EB: §4.1 (open
  // 0..N-2, closed 0..N-1). Knot-vector B-splines: the knot interval indices k-1..n of §10.1
  // (an empty interval is rejected by evaluate()).
  SpanRange spans() const { return spans_; }
  // [u_min, u_max] of the global parameter: j + t, span knots κ, or [t_{k-1}, t_N].
  std::pair<double, double> parameterRange() const;
  // Global parameter of (span, t).
  double parameterOf(int span, double t) const;

  // Span `span`, local t in [0,1]: point and derivatives w.r.t. the global u, one-sided at t = 0/1
  // (the span's own polynomial). Throws std::out_of_range for a span or t outside the valid range.
  CurvePoint evaluate(int span, double t) const;
  // Global u in parameterRange(). At an interior joint the span to the right is used, except at
  // u_max. Throws std::out_of_range outside the range.
  CurvePoint evaluateAt(double u) const;
  // The list kernel (core/list_eval.h): evaluate() / evaluateAt() without d2 (knot-vector
  // B-splines: not computed; other families compute their span's d2 and drop it), the point alone
  // when `derivatives` is false; the same bits and range checks. `cache` carries the knot interval
  // from one query of a list to the next.
  CurveFirst evaluateFirst(int span, double t, bool derivatives, KnotBasisCache& cache) const;
  CurveFirst evaluateFirstAt(double u, bool derivatives, KnotBasisCache& cache) const;
  // The span of global u and the local t in it, as evaluateAt picks them (u is clamped into the
  // range, no check): uniform and span-knot spans, or the non-empty knot interval of
  // core/bspline.h findKnotSpan. The one lookup that CPU and GPU parameter lists share.
  int spanAt(double u, double& t) const;

  // Span basis of the family (not meaningful for knot-vector B-splines).
  const SpanBasis& basis() const { return basis_; }
  // See the header comment: span j reads spanPoints()[j + spanPointOffset() + r], r < basis().count.
  const std::vector<glm::dvec3>& spanPoints() const { return spanPoints_; }
  int spanPointOffset() const { return spanPointOffset_; }
  // Span knots κ_0..κ_S (empty when the spans are uniform).
  const std::vector<double>& spanKnots() const { return spanKnots_; }

  // α-EB only (empty otherwise). extendedPoints()[i] = P_{i-1}: open N+2 points with the phantom
  // points P_{-1}, P_N of §4.1, closed N+3 points wrapped mod N; span j reads entries j..j+3.
  // alphaNodes()[j] = node_j = C_j(0), alphaV()[j] = V_j, alphas()[j] = α_j, all of size N;
  // span j uses index j and (j+1) mod N.
  const std::vector<glm::dvec3>& extendedPoints() const { return alphaEB() ? spanPoints_ : emptyPoints_; }
  const std::vector<glm::dvec3>& alphaNodes() const { return nodes_; }
  const std::vector<glm::dvec3>& alphaV() const { return v_; }
  const std::vector<double>& alphas() const { return model_.alpha; }

  // A band of spans first..last (valid spans of a uniform or span-knot curve of shape `shape`, its
  // own points not read, with `pointCount` points) built from the points pointOf(i) and α alphaOf(i)
  // (α-EB) alone: spans 0..last-first of the band evaluate to the same bits as spans first..last of
  // the whole curve, and its α-EB vertices are checked as create() checks them (ModelError naming
  // the whole curve's alpha[i]). A curve streamed from its file is sampled a band at a time.
  using PointOf = std::function<const glm::dvec3*(int index)>;
  using AlphaOf = std::function<const double*(int index)>;
  static Curve bandOf(const CurveModel& shape, int pointCount, int first, int last, const PointOf& pointOf,
                      const AlphaOf& alphaOf);
  // The point indices bandOf(shape, pointCount, first, last, ...) reads, ascending (a closed curve
  // wraps: its first and last spans read points from the other end).
  static std::vector<int> bandPoints(const CurveModel& shape, int pointCount, int first, int last);

 private:
  Curve() = default;
  CurvePoint evalSpan(int span, double t) const;  // no range checks
  // The range checks of evaluate() and evaluateAt() (std::out_of_range).
  void checkSpanQuery(int span, double t) const;
  void checkGlobalQuery(double u) const;

  CurveModel model_;
  SpanBasis basis_;
  SpanRange spans_;
  bool knotVector() const { return parameterization_ == Parameterization::KnotVector; }
  bool alphaEB() const { return parameterization_ == Parameterization::AlphaEB; }

  Parameterization parameterization_ = Parameterization::LocalSpans;
  std::vector<glm::dvec3> spanPoints_;
  int spanPointOffset_ = 0;
  std::vector<glm::dvec3> nodes_, v_;
  std::vector<double> spanKnots_;
  BSplineCurveData bspline_;  // knot-vector B-splines only
  std::vector<glm::dvec3> emptyPoints_;
};

// ---- Shared helpers (also used by core/surface.cpp) ---------------------------------------------

// One entry of an extended/wrapped index sequence: ext = w0 * P[i0] + w1 * P[i1].
struct ExtendedIndex {
  int i0 = 0, i1 = 0;
  double w0 = 1.0, w1 = 0.0;
};
// The 1-D span point sequence of one direction with n points (see the header comment).
// phantom = true: α-EB rule of §4.1 / §5.1 (c = 1; open: P_{-1} = 2P_0 - P_1, P_n = 2P_{n-1} - P_{n-2};
// closed: mod n), entry i is P_{i-1}. phantom = false: plain rule of §1 (open: P itself, offset -c;
// closed: entry i is P_{(i-c) mod n}, n + m - 1 entries, offset 0). `offset` receives the offset.
std::vector<ExtendedIndex> extendedIndices(int n, bool closed, bool phantom, int count, int centre, int& offset);
// Entry i of that sequence, its length and its offset, one at a time (a curve too long to list).
ExtendedIndex extendedIndex(int i, int n, bool closed, bool phantom, int count, int centre);
int extendedSize(int n, bool closed, bool phantom, int count);
int extendedOffset(bool closed, bool phantom, int centre);

// The valid spans of a uniform or span-knot curve of shape `shape` with `pointCount` points
// (Curve::spans() of the curve it makes; not for knot vectors).
SpanRange uniformCurveSpans(const CurveModel& shape, int pointCount);
// The global parameter of (span, t) of such a curve: j + t, or by its span knots κ (Curve::parameterOf).
double uniformSpanParameter(const std::vector<double>& spanKnots, SpanRange spans, int span, double t);

}  // namespace shapespline
