#include <shapespline/part/closest_points.h>

#include <shapespline/core/parallel_for.h>
#include <shapespline/core/point_math.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace shapespline::part {

namespace {

constexpr int kMaxNewtonSteps = 60;
constexpr int kMaxHalvings = 40;
constexpr double kStepTolerance = ClosestPoints::kStepTolerance;
constexpr double kTrustedStep = ClosestPoints::kTrustedStep;
// Boundary feet of other faces within this fraction of the diagonal of the best one are the same
// place (an edge that two faces share meets within their trim tolerance), for the sign.
constexpr double kSameFootFraction = 1e-6;
constexpr double kOnSurfaceFraction = ClosestPoints::kOnSurfaceFraction;
// A cell that may hold a nearer point than Newton found on it (Newton did not settle, or the query
// is near a centre of the cell's curvature: the curvature towards the query's side times the
// distance at least kFocalFraction) gets a second look while its bound is nearer than the best
// point: Newton in each quarter, kSecondLookDepth levels deep.
constexpr double kFocalFraction = 1.0;
constexpr int kSecondLookDepth = 2;

// A point of a surface piece and its partials with respect to the piece's local parameters.
struct LocalPoint {
  glm::dvec3 p{0.0}, u{0.0}, v{0.0}, uu{0.0}, uv{0.0}, vv{0.0};
};

LocalPoint evaluateLocal(const Surface& s, int i, int j, double u, double v) {
  if (s.usesKnotVector()) {
    const BSplineSurfaceData& d = s.knotData();
    const double hu = d.knotsU[i + 1] - d.knotsU[i], hv = d.knotsV[j + 1] - d.knotsV[j];
    const BSplineSurfacePoint e = evalBSplineSurface(d, d.knotsU[i] + u * hu, d.knotsV[j] + v * hv);
    return {e.point, e.du * hu, e.dv * hv, e.duu * (hu * hu), e.duv * (hu * hv), e.dvv * (hv * hv)};
  }
  PatchDerivs out;
  const glm::dvec3* net = &s.patchNet()[static_cast<size_t>(i + s.netOffsetU()) * s.netCols() + (j + s.netOffsetV())];
  evalTensorPatch(s.basisU(), s.basisV(), net, s.netCols(), u, v, out);
  return {out.p, out.u, out.v, out.uu, out.uv, out.vv};
}

// A point of a tree patch at local (u, v) and its local partials: the centred power form by Horner's
// rule, each row in v first (value, first and half the second derivative), then the rows in u.
LocalPoint evaluatePatch(const ProjectionTree& tree, const ProjectionPatch& patch, double u, double v) {
  const glm::dvec4* c = &tree.coefficients()[patch.first];
  const double su = u - 0.5, sv = v - 0.5;
  const size_t rowLength = static_cast<size_t>(patch.m + 1);
  glm::dvec4 p(0.0), pu(0.0), puu(0.0), pv(0.0), puv(0.0), pvv(0.0);  // puu, pvv: halved
  for (int d = patch.n; d >= 0; --d) {
    const glm::dvec4* row = c + static_cast<size_t>(d) * rowLength;
    glm::dvec4 r(0.0), r1(0.0), r2(0.0);  // r2: halved
    for (int e = patch.m; e >= 0; --e) {
      r2 = r2 * sv + r1;
      r1 = r1 * sv + r;
      r = r * sv + row[e];
    }
    puu = puu * su + pu;
    pu = pu * su + p;
    p = p * su + r;
    puv = puv * su + pv;
    pv = pv * su + r1;
    pvv = pvv * su + r2;
  }
  puu *= 2.0, pvv *= 2.0;
  LocalPoint e{glm::dvec3(p), glm::dvec3(pu), glm::dvec3(pv), glm::dvec3(puu), glm::dvec3(puv), glm::dvec3(pvv)};
  if (patch.rational) pm::rationalSurface(e.p, e.u, e.v, e.uu, e.uv, e.vv, p.w, pu.w, pv.w, puu.w, puv.w, pvv.w);
  return e;
}

// A point of the surface at global (U, V) (clamped into the domain) and its partials with respect to
// U and V: evaluateAt without the normal.
LocalPoint evaluateGlobal(const Surface& s, double U, double V) {
  const auto [u0, u1] = s.parameterRangeU();
  const auto [v0, v1] = s.parameterRangeV();
  U = std::clamp(U, u0, u1), V = std::clamp(V, v0, v1);
  if (s.usesKnotVector()) {
    const BSplineSurfacePoint e = evalBSplineSurface(s.knotData(), U, V);
    return {e.point, e.du, e.dv, e.duu, e.duv, e.dvv};
  }
  int i = 0, j = 0;
  double u = 0.0, v = 0.0;
  s.patchAt(U, V, i, j, u, v);
  return evaluateLocal(s, i, j, u, v);  // uniform patches: local and global partials agree
}

// The parameter x in [lo, hi] nearest q on a curve piece, by Newton from x: eval(x) gives the
// point, first and second derivatives. Returns the squared distance there.
template <typename Eval>
double newtonOnSegment(const glm::dvec3& q, double lo, double hi, double& x, glm::dvec3& foot, const Eval& eval) {
  glm::dvec3 p, d1, d2;
  eval(x, p, d1, d2);
  glm::dvec3 r = p - q;
  double f = glm::dot(r, r);
  for (int step = 0; step < kMaxNewtonSteps; ++step) {
    const double g = glm::dot(d1, r);
    if ((x <= lo && g > 0.0) || (x >= hi && g < 0.0) || g == 0.0) break;
    const double curvature = glm::dot(d1, d1) + glm::dot(d2, r);
    const double h = curvature > 0.0 ? curvature : glm::dot(d1, d1);
    double dx = h > 0.0 ? -g / h : (g > 0.0 ? lo - x : hi - x);
    if (std::abs(dx) < kStepTolerance) break;
    const bool trusted = curvature > 0.0 && std::abs(dx) < kTrustedStep;
    double xn = 0.0, fn = 0.0;
    glm::dvec3 pn, d1n, d2n;
    int halvings = 0;
    for (;; dx *= 0.5) {
      xn = std::clamp(x + dx, lo, hi);
      eval(xn, pn, d1n, d2n);
      fn = glm::dot(pn - q, pn - q);
      if (fn <= f || trusted || ++halvings > kMaxHalvings) break;
    }
    if (fn > f && !trusted) break;
    const double moved = std::abs(xn - x);
    x = xn, p = pn, d1 = d1n, d2 = d2n, r = pn - q, f = fn;
    if (moved < kStepTolerance) break;
  }
  foot = p;
  return f;
}

// Newton on |S - q|^2 over patch (i, j)'s local rectangle lo..hi from x: the step of Newton's matrix
// where it is positive definite, else Gauss-Newton's; a parameter on its bound with the gradient
// pushing outwards held there; the step clamped into the rectangle and halved until the distance
// falls. Returns the squared distance at the final x, e the point there; `settled` when Newton's
// matrix is positive definite there (a strict local minimum, or the nearest point of a border the
// distance falls towards).
double newtonOnPatch(const ProjectionTree& tree, const ProjectionPatch& patch, const double lo[2], const double hi[2],
                     const glm::dvec3& q, double x[2], LocalPoint& e, bool& settled) {
  e = evaluatePatch(tree, patch, x[0], x[1]);
  glm::dvec3 r = e.p - q;
  double f = glm::dot(r, r);
  for (int step = 0; step < kMaxNewtonSteps; ++step) {
    const double g[2] = {glm::dot(e.u, r), glm::dot(e.v, r)};
    // Gauss-Newton's matrix, and Newton's (with the residual's curvature) where it is positive.
    const double a00 = glm::dot(e.u, e.u), a01 = glm::dot(e.u, e.v), a11 = glm::dot(e.v, e.v);
    double h00 = a00 + glm::dot(e.uu, r), h01 = a01 + glm::dot(e.uv, r), h11 = a11 + glm::dot(e.vv, r);
    const bool curvesUp = h00 > 0.0 && h00 * h11 - h01 * h01 > 0.0;
    if (!curvesUp) h00 = a00, h01 = a01, h11 = a11;
    // A parameter on its bound with the gradient pushing outwards stays there; so does one on its
    // bound that the step would push out.
    bool held[2] = {(x[0] <= lo[0] && g[0] > 0.0) || (x[0] >= hi[0] && g[0] < 0.0),
                    (x[1] <= lo[1] && g[1] > 0.0) || (x[1] >= hi[1] && g[1] < 0.0)};
    double dx[2] = {0.0, 0.0};
    for (int pass = 0; pass < 2; ++pass) {
      const double det = h00 * h11 - h01 * h01;
      dx[0] = dx[1] = 0.0;
      if (!held[0] && !held[1] && det > 0.0) {
        dx[0] = -(h11 * g[0] - h01 * g[1]) / det;
        dx[1] = -(h00 * g[1] - h01 * g[0]) / det;
      } else if (!held[0] && h00 > 0.0 && (held[1] || det <= 0.0)) {
        dx[0] = -g[0] / h00;
      } else if (!held[1] && h11 > 0.0) {
        dx[1] = -g[1] / h11;
      } else if (!held[0] || !held[1]) {
        // Singular (a pole): a gradient step across the piece.
        const double norm = std::hypot(held[0] ? 0.0 : g[0], held[1] ? 0.0 : g[1]);
        if (norm > 0.0)
          for (int k = 0; k < 2; ++k) dx[k] = held[k] ? 0.0 : -g[k] / norm * (hi[k] - lo[k]);
      }
      bool again = false;
      for (int k = 0; k < 2; ++k)
        if (!held[k] && ((x[k] <= lo[k] && dx[k] < 0.0) || (x[k] >= hi[k] && dx[k] > 0.0))) held[k] = again = true;
      if (!again) break;
    }
    // Up to the rectangle's border, no further (still a descent direction), landing on it exactly.
    double reach = 1.0, border = 0.0;
    int stops = -1;
    for (int k = 0; k < 2; ++k) {
      const double bound = x[k] + dx[k] < lo[k] ? lo[k] : (x[k] + dx[k] > hi[k] ? hi[k] : x[k] + dx[k]);
      if (bound != x[k] + dx[k] && (bound - x[k]) / dx[k] < reach) reach = (bound - x[k]) / dx[k], stops = k, border = bound;
    }
    dx[0] *= reach, dx[1] *= reach;
    // A step shorter than the tolerance would move nothing that matters: stop without evaluating it.
    const double stepLength = std::max(std::abs(dx[0]), std::abs(dx[1]));
    if (stepLength < kStepTolerance) break;
    const bool trusted = curvesUp && !held[0] && !held[1] && stops < 0 && stepLength < kTrustedStep;
    double xn[2], fn = 0.0;
    LocalPoint en;
    int halvings = 0;
    for (;; dx[0] *= 0.5, dx[1] *= 0.5) {
      for (int k = 0; k < 2; ++k) xn[k] = std::clamp(x[k] + dx[k], lo[k], hi[k]);
      if (halvings == 0 && stops >= 0) xn[stops] = border;
      en = evaluatePatch(tree, patch, xn[0], xn[1]);
      fn = glm::dot(en.p - q, en.p - q);
      if (fn <= f || trusted || ++halvings > kMaxHalvings) break;
    }
    if (fn > f && !trusted) break;
    const double moved = std::max(std::abs(xn[0] - x[0]), std::abs(xn[1] - x[1]));
    x[0] = xn[0], x[1] = xn[1], e = en, r = en.p - q, f = fn;
    if (moved < kStepTolerance) break;
  }
  const double h00 = glm::dot(e.u, e.u) + glm::dot(e.uu, r), h01 = glm::dot(e.u, e.v) + glm::dot(e.uv, r),
               h11 = glm::dot(e.v, e.v) + glm::dot(e.vv, r);
  settled = h00 > 0.0 && h00 * h11 - h01 * h01 > 0.0;
  return f;
}

}  // namespace

ClosestPoints::ClosestPoints(const ProjectionTree& tree, double tolerance) : tree_(tree), tolerance_(tolerance) {
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance))
    throw std::invalid_argument("ClosestPoints: the tolerance must be finite and >= 0");
  for (const ProjectionFace& face : tree.faces()) {
    const TrimLoops& trim = face.surface->model().trim;
    inside_.emplace_back();
    if (!trim.empty()) inside_.back().emplace(trim);
  }
}

bool ClosestPoints::solveCell(const glm::dvec3& q, const ProjectionCell& cell, const glm::dvec2* from, bool everySide,
                              double bestD2, Candidate& out) const {
  const Surface& s = *tree_.faces()[cell.face].surface;
  const double lo[2] = {cell.u0, cell.v0}, hi[2] = {cell.u1, cell.v1};
  double x[2] = {0.5, 0.5};
  if (from) {
    x[0] = (from->x - cell.u0) / (cell.u1 - cell.u0);
    x[1] = (from->y - cell.v0) / (cell.v1 - cell.v0);
  } else {
    // Where q falls on the cell's parallelogram (least squares), kept inside it.
    const glm::dvec3 d = q - cell.middle;
    const double a = glm::dot(cell.alongU, cell.alongU), b = glm::dot(cell.alongU, cell.alongV),
                 c = glm::dot(cell.alongV, cell.alongV), det = a * c - b * b;
    if (det > 0.0) {
      const double pu = glm::dot(d, cell.alongU), pv = glm::dot(d, cell.alongV);
      x[0] = std::clamp(0.5 + (c * pu - b * pv) / det, 0.0, 1.0);
      x[1] = std::clamp(0.5 + (a * pv - b * pu) / det, 0.0, 1.0);
    }
  }
  x[0] = cell.u0 + x[0] * (cell.u1 - cell.u0);
  x[1] = cell.v0 + x[1] * (cell.v1 - cell.v0);
  const double start[2] = {x[0], x[1]};
  LocalPoint e;
  bool settled = false;
  const ProjectionPatch& patch = tree_.patches()[cell.patch];
  double f = newtonOnPatch(tree_, patch, lo, hi, q, x, e, settled);
  // On the domain's border the nearest point may be a minimum along the border that is not one of
  // the surface: a border side of the cell is searched on its own where Newton ended on it, or
  // every border side (a doubtful cell's second look, where a second minimum may be).
  const auto [uMin, uMax] = s.parameterRangeU();
  const auto [vMin, vMax] = s.parameterRangeV();
  const SurfaceShape& shape = s.model();
  const double tiny2 = (kOnSurfaceFraction * tree_.diagonal()) * (kOnSurfaceFraction * tree_.diagonal());
  for (int side = 0; side < 4 && f > tiny2; ++side) {
    const bool alongV = side < 2;  // a side of fixed u, running along v
    const double fixed = side == 0 ? cell.u0 : side == 1 ? cell.u1 : side == 2 ? cell.v0 : cell.v1;
    const auto [U, V] = alongV ? s.parameterOf(cell.i, cell.j, fixed, cell.v0) : s.parameterOf(cell.i, cell.j, cell.u0, fixed);
    const bool border = alongV ? !shape.closedU && (U == uMin || U == uMax) : !shape.closedV && (V == vMin || V == vMax);
    if (!border || (!everySide && (alongV ? x[0] : x[1]) != fixed)) continue;
    const auto eval = [&](double t, glm::dvec3& p, glm::dvec3& d1, glm::dvec3& d2) {
      const LocalPoint l = alongV ? evaluatePatch(tree_, patch, fixed, t) : evaluatePatch(tree_, patch, t, fixed);
      p = l.p, d1 = alongV ? l.v : l.u, d2 = alongV ? l.vv : l.uu;
    };
    double t = alongV ? start[1] : start[0];
    glm::dvec3 foot;
    const double fb = newtonOnSegment(q, alongV ? cell.v0 : cell.u0, alongV ? cell.v1 : cell.u1, t, foot, eval);
    if (fb < f) {
      f = fb;
      x[0] = alongV ? fixed : t, x[1] = alongV ? t : fixed;
      e.p = foot;
      e.u = e.v = glm::dvec3(0.0);  // not evaluated at the side's point
    }
  }
  const auto [U, V] = s.parameterOf(cell.i, cell.j, x[0], x[1]);
  const std::optional<TrimClassifier>& inside = inside_[cell.face];
  if (!inside || inside->inside({U, V})) {
    out = {f, e.p, U, V, cell.face, false, cell.i, cell.j, x[0], x[1], e.u, e.v};
    return settled;
  }
  // Outside the loops: the nearest point of the cell inside them is on a loop piece that meets it.
  solveRuns(q, cell.index, bestD2, out);
  return settled;
}

void ClosestPoints::solveRuns(const glm::dvec3& q, int cell, double bestD2, Candidate& out) const {
  // Nearest box first, stopping at the first box farther than the nearest point found.
  const std::span<const int> runs = tree_.runsOf(cell);
  thread_local std::vector<std::pair<double, int>> order;
  order.clear();
  for (const int r : runs) {
    const double d2 = tree_.runs()[r].box.distance2(q);
    if (d2 <= bestD2) order.emplace_back(d2, r);
  }
  // A heap: most cells list dozens of pieces, and the first few usually settle it.
  std::make_heap(order.begin(), order.end(), std::greater<>{});
  while (!order.empty()) {
    std::pop_heap(order.begin(), order.end(), std::greater<>{});
    const auto [d2, r] = order.back();
    order.pop_back();
    if (d2 > out.d2) break;
    Candidate c;
    solveRun(q, tree_.runs()[r], c);
    if (c.d2 < out.d2) out = c;
  }
}

void ClosestPoints::solveRun(const glm::dvec3& q, const ProjectionRun& run, Candidate& out) const {
  const Surface& s = *tree_.faces()[run.face].surface;
  const std::vector<glm::dvec2>& loop = s.model().trim.loops[run.loop];
  const auto [uMin, uMax] = s.parameterRangeU();
  const auto [vMin, vMax] = s.parameterRangeV();
  const glm::dvec2 a = loop[run.segment], ab = loop[(run.segment + 1) % loop.size()] - a;
  const auto eval = [&](double t, glm::dvec3& p, glm::dvec3& d1, glm::dvec3& d2) {
    const glm::dvec2 uv = a + t * ab;
    const LocalPoint e = evaluateGlobal(s, uv.x, uv.y);
    p = e.p;
    d1 = e.u * ab.x + e.v * ab.y;
    d2 = e.uu * (ab.x * ab.x) + 2.0 * e.uv * (ab.x * ab.y) + e.vv * (ab.y * ab.y);
  };
  double t = 0.5 * (run.t0 + run.t1);
  glm::dvec3 foot;
  const double f = newtonOnSegment(q, run.t0, run.t1, t, foot, eval);
  const glm::dvec2 uv = a + t * ab;
  out = {};
  out.d2 = f;
  out.point = foot;
  out.u = std::clamp(uv.x, uMin, uMax);
  out.v = std::clamp(uv.y, vMin, vMax);
  out.face = run.face;
  out.boundary = true;
}

void ClosestPoints::solveSpan(const glm::dvec3& q, const ProjectionSpan& span, Candidate& out) const {
  const Curve& curve = *tree_.curve();
  const double h = curve.parameterOf(span.span, 1.0) - curve.parameterOf(span.span, 0.0);
  const auto eval = [&](double t, glm::dvec3& p, glm::dvec3& d1, glm::dvec3& d2) {
    const CurvePoint e = curve.evaluate(span.span, t);
    p = e.point, d1 = e.d1 * h, d2 = e.d2 * (h * h);
  };
  double t = 0.5 * (span.t0 + span.t1);
  glm::dvec3 foot;
  const double f = newtonOnSegment(q, span.t0, span.t1, t, foot, eval);
  out = {};
  out.d2 = f;
  out.point = foot;
  out.u = curve.parameterOf(span.span, t);
}

FootPoint ClosestPoints::of(const glm::dvec3& q, bool signedDistance) const {
  if (tree_.nodes().empty()) return {};
  constexpr double kNone = std::numeric_limits<double>::infinity();
  Candidate best;
  auto better = [&](const Candidate& c) {
    if (c.d2 != best.d2) return c.d2 < best.d2;
    if (c.d2 == kNone) return false;
    const int a = tree_.faces().empty() ? 0 : tree_.faces()[c.face].id;
    const int b = tree_.faces().empty() ? 0 : tree_.faces()[best.face].id;
    return std::tie(a, c.u, c.v) < std::tie(b, best.u, best.v);
  };
  // No farther than the best point so far plus `slack` (a negative slack: nearer by at least -slack).
  auto within = [&](double d2, double slack) {
    if (best.d2 == kNone) return true;
    const double reach = std::sqrt(best.d2) + slack;
    return reach >= 0.0 && d2 <= reach * reach;
  };
  // A piece is solved only where it could be nearer than the best by more than the tolerance (with
  // none, ties too are solved, for the tie rule).
  const double solved = -tolerance_;
  // Within a cell, the distance from q has one minimum when q is nearer to all of it than its
  // radius of curvature; otherwise (q near a centre of curvature) it may have two.
  auto nearCentreOfCurvature = [&](const ProjectionCell& cell, double d2) {
    const bool above = glm::dot(q - cell.middle, glm::cross(cell.alongU, cell.alongV)) >= 0.0;
    return (above ? cell.bendsUp : cell.bendsDown) * std::sqrt(d2) >= kFocalFraction;
  };

  // The cells nearest bound first (the larger of the distances to its box and its oriented box),
  // each solved; doubtful ones kept for a second look. A queue entry is a node (index >= 0) or a
  // leaf (-1 - index).
  using Entry = std::pair<double, int>;
  // The queue (a heap) and the lists below are each thread's own, kept between queries: no
  // allocation per point.
  thread_local std::vector<Entry> queue;
  queue.clear();
  const auto push = [&](Entry e) {
    queue.push_back(e);
    std::push_heap(queue.begin(), queue.end(), std::greater<>{});
  };
  push({tree_.nodes().front().box.distance2(q), 0});
  // Squared bound and cell of the doubtful cells.
  thread_local std::vector<std::pair<double, int>> doubtful;
  doubtful.clear();
  while (!queue.empty()) {
    std::pop_heap(queue.begin(), queue.end(), std::greater<>{});
    const auto [d2, index] = queue.back();
    queue.pop_back();
    if (!within(d2, solved)) break;
    if (index < 0) {
      const ProjectionTree::Leaf& leaf = tree_.leaves()[-1 - index];
      Candidate c;
      if (leaf.kind == ProjectionTree::LeafKind::Span) {
        solveSpan(q, tree_.spans()[leaf.index], c);
      } else {
        const ProjectionCell& cell = tree_.cells()[leaf.index];
        if (!solveCell(q, cell, nullptr, false, best.d2, c) || nearCentreOfCurvature(cell, c.d2)) doubtful.push_back({d2, cell.index});
      }
      if (better(c)) best = c;
      continue;
    }
    const ProjectionTree::Node& node = tree_.nodes()[index];
    if (node.count == 0) {
      for (const int child : {index + 1, node.right}) {
        const double c2 = tree_.nodes()[child].box.distance2(q);
        if (within(c2, solved)) push({c2, child});
      }
      continue;
    }
    for (int k = node.first; k < node.first + node.count; ++k) {
      const ProjectionTree::Leaf& leaf = tree_.leaves()[k];
      const double bound = leafBound(q, leaf);
      if (within(bound, solved)) push({bound, -1 - k});
    }
  }
  // A doubtful cell's second look: Newton confined to each of its quarters, from its middle, every
  // border side searched, and the quarters' quarters where a quarter is doubtful too.
  const auto secondLook = [&](const auto& self, const ProjectionCell& cell, int depth) -> void {
    const double um = 0.5 * (cell.u0 + cell.u1), vm = 0.5 * (cell.v0 + cell.v1);
    const double us[3] = {cell.u0, um, cell.u1}, vs[3] = {cell.v0, vm, cell.v1};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        ProjectionCell quarter = cell;
        quarter.u0 = us[a], quarter.u1 = us[a + 1], quarter.v0 = vs[b], quarter.v1 = vs[b + 1];
        const glm::dvec2 middle(0.5 * (quarter.u0 + quarter.u1), 0.5 * (quarter.v0 + quarter.v1));
        Candidate c;
        const bool settled = solveCell(q, quarter, &middle, true, best.d2, c);
        if (better(c)) best = c;
        if (depth < kSecondLookDepth && (!settled || nearCentreOfCurvature(quarter, c.d2))) self(self, quarter, depth + 1);
      }
  };
  // A point on the surface (within kOnSurfaceFraction of the diagonal) cannot be bettered by more
  // than that: its doubtful cells need no second look.
  const double onSurface = kOnSurfaceFraction * tree_.diagonal();
  if (best.d2 > onSurface * onSurface)
    for (const auto& [box2, cell] : doubtful)
      if (within(box2, solved)) secondLook(secondLook, tree_.cells()[cell], 1);
  return finish(q, best, signedDistance);
}

FootPoint ClosestPoints::finish(const glm::dvec3& q, const Candidate& best, bool signedDistance) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  FootPoint foot;
  if (best.d2 == kNone) return foot;  // every piece outside its loops
  foot.point = best.point;
  foot.u = best.u;
  foot.v = best.v;
  foot.distance = std::sqrt(best.d2);
  foot.signedDistance = foot.distance;
  foot.boundary = best.boundary;
  if (tree_.curve()) return foot;

  auto outwardNormal = [&](const Candidate& c) {
    const ProjectionFace& face = tree_.faces()[c.face];
    glm::dvec3 n;
    // The local partials point as the global ones do (positive scales): where they are regular,
    // their unit cross product is the surface's normal (docs/math.md §5.3's regular step).
    if (c.boundary) {
      n = face.surface->evaluateAt(c.u, c.v).normal;
    } else if (!unitNormal(c.du, c.dv, n)) {
      n = face.surface->evaluate(c.i, c.j, c.lu, c.lv).normal;
    }
    return face.reversed ? -n : n;
  };
  foot.face = tree_.faces()[best.face].id;
  foot.normal = outwardNormal(best);
  if (!signedDistance) return foot;
  glm::dvec3 direction = foot.normal;
  if (best.boundary) {
    // On an edge: the sum of the outward normals of the faces that meet there, each at its own
    // nearest boundary point (within kSameFootFraction of the diagonal of this one).
    const double sameFoot = kSameFootFraction * tree_.diagonal();
    const double reach = foot.distance + sameFoot;
    std::vector<int> faces = {best.face};
    for (const int cell : cellsWithin(q, reach * reach)) {
      const int face = tree_.cells()[cell].face;
      if (std::find(faces.begin(), faces.end(), face) != faces.end()) continue;
      Candidate c;
      solveRuns(q, cell, reach * reach, c);
      if (c.d2 == kNone || std::sqrt(c.d2) > reach || glm::length(c.point - best.point) > sameFoot) continue;
      faces.push_back(face);
      direction += outwardNormal(c);
    }
  }
  if (glm::dot(q - foot.point, direction) < 0.0) foot.signedDistance = -foot.distance;
  return foot;
}

double ClosestPoints::leafBound(const glm::dvec3& q, const ProjectionTree::Leaf& leaf) const {
  const double box = leaf.box.distance2(q);
  return leaf.kind == ProjectionTree::LeafKind::Cell ? std::max(box, tree_.cells()[leaf.index].distance2(q)) : box;
}

std::vector<int> ClosestPoints::cellsWithin(const glm::dvec3& q, double reach2) const {
  std::vector<int> cells;
  thread_local std::vector<int> stack;
  stack.assign(1, 0);
  while (!stack.empty()) {
    const int index = stack.back();
    stack.pop_back();
    const ProjectionTree::Node& node = tree_.nodes()[index];
    if (node.box.distance2(q) > reach2) continue;
    if (node.count == 0) {
      stack.push_back(index + 1);
      stack.push_back(node.right);
      continue;
    }
    for (int k = node.first; k < node.first + node.count; ++k) {
      const ProjectionTree::Leaf& leaf = tree_.leaves()[k];
      if (leaf.kind != ProjectionTree::LeafKind::Cell) continue;
      if (leafBound(q, leaf) <= reach2) cells.push_back(leaf.index);
    }
  }
  return cells;
}

void ClosestPoints::of(std::span<const glm::dvec3> points, std::span<FootPoint> out, bool signedDistance,
                       int threads) const {
  constexpr size_t kBlock = 256;
  const size_t blocks = (points.size() + kBlock - 1) / kBlock;
  parallelFor(blocks, threads, [&](size_t b) {
    const size_t end = std::min(points.size(), (b + 1) * kBlock);
    for (size_t k = b * kBlock; k < end; ++k) out[k] = of(points[k], signedDistance);
  });
}

}  // namespace shapespline::part
