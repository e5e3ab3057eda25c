#include <shapespline/part/projection_tree.h>

#include <shapespline/core/field_error.h>
#include <shapespline/core/trim_classifier.h>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <functional>
#include <numeric>

namespace shapespline::part {

void Box::add(const glm::dvec3& p) {
  lo = glm::min(lo, p);
  hi = glm::max(hi, p);
}

void Box::add(const Box& b) {
  lo = glm::min(lo, b.lo);
  hi = glm::max(hi, b.hi);
}

double Box::distance2(const glm::dvec3& q) const {
  const glm::dvec3 d = glm::max(glm::max(lo - q, q - hi), glm::dvec3(0.0));
  return glm::dot(d, d);
}

namespace {

// A piece is cut until its control net lies within this fraction of its box's diagonal of the
// bilinear (or linear) interpolation of its corners: nearly flat, so that the distance from a
// point has one minimum on it (part/closest_points.cpp starts Newton at its middle).
constexpr double kFlatness = 0.05;
// At most this many halvings per direction (2^6 x 2^6 cells per patch).
constexpr int kMaxDepth = 6;
// A trim-loop segment is halved until each piece meets at most this many cells (at most
// kMaxRunDepth times).
constexpr size_t kRunCells = 4;
constexpr int kMaxRunDepth = 12;
// The most cells (and patches) a tree holds (about 250 bytes a cell with its box and leaf, and a
// patch's power form: 512 bytes for a bicubic): a net of millions of patches is refused rather than
// exhausting memory.
constexpr size_t kMaxCells = size_t{1} << 23;
// Leaves per hierarchy leaf node.
constexpr int kLeafSize = 4;

constexpr int kMaxBezier = kMaxPolyDegree + 1;

// Bernstein coefficients of a span basis: B_r(t) = sum_k beta[r][k] b_k^n(t), n = basis.degree.
// From t^d = sum_{k >= d} C(k, d) / C(n, d) b_k^n(t).
void bernsteinOf(const SpanBasis& basis, double beta[kMaxBasisCount][kMaxBezier]) {
  const int n = basis.degree;
  double binom[kMaxBezier][kMaxBezier] = {};
  for (int a = 0; a <= n; ++a) {
    binom[a][0] = 1.0;
    for (int b = 1; b <= a; ++b) binom[a][b] = binom[a - 1][b - 1] + (b < a ? binom[a - 1][b] : 0.0);
  }
  for (int r = 0; r < basis.count; ++r)
    for (int k = 0; k <= n; ++k) {
      double sum = 0.0;
      for (int d = 0; d <= k; ++d) sum += basis.coef[r][d] * binom[k][d] / binom[n][d];
      beta[r][k] = sum;
    }
}

// A Bézier net of (n + 1) x (m + 1) homogeneous points (w P, w), row-major.
struct BezierNet {
  int n = 0, m = 0;
  std::vector<glm::dvec4> q;
  glm::dvec4& at(int k, int l) { return q[static_cast<size_t>(k) * (m + 1) + l]; }
  const glm::dvec4& at(int k, int l) const { return q[static_cast<size_t>(k) * (m + 1) + l]; }
  glm::dvec3 point(int k, int l) const { return glm::dvec3(at(k, l)) / at(k, l).w; }
};

Box boxOf(const BezierNet& net) {
  Box box;
  for (int k = 0; k <= net.n; ++k)
    for (int l = 0; l <= net.m; ++l) box.add(net.point(k, l));
  return box;
}

// Largest distance of the net's points from the straight line between the ends of their row
// (alongU: the points of each column l, k = 0..n) or column.
double bend(const BezierNet& net, bool alongU) {
  const int outer = alongU ? net.m : net.n, inner = alongU ? net.n : net.m;
  double worst = 0.0;
  for (int o = 0; o <= outer; ++o) {
    auto p = [&](int i) { return alongU ? net.point(i, o) : net.point(o, i); };
    const glm::dvec3 a = p(0), b = p(inner);
    for (int i = 1; i < inner; ++i) {
      const double s = static_cast<double>(i) / inner;
      worst = std::max(worst, glm::length(p(i) - (a + s * (b - a))));
    }
  }
  return worst;
}

// The two halves of the net at the middle of u (alongU) or v, by de Casteljau.
std::pair<BezierNet, BezierNet> halve(const BezierNet& net, bool alongU) {
  BezierNet lower = net, upper = net;
  const int outer = alongU ? net.m : net.n, inner = alongU ? net.n : net.m;
  glm::dvec4 work[kMaxBezier];
  for (int o = 0; o <= outer; ++o) {
    auto ref = [&](BezierNet& b, int i) -> glm::dvec4& { return alongU ? b.at(i, o) : b.at(o, i); };
    for (int i = 0; i <= inner; ++i) work[i] = alongU ? net.at(i, o) : net.at(o, i);
    ref(lower, 0) = work[0];
    ref(upper, inner) = work[inner];
    for (int level = 1; level <= inner; ++level) {
      for (int i = 0; i + level <= inner; ++i) work[i] = 0.5 * (work[i] + work[i + 1]);
      ref(lower, level) = work[0];
      ref(upper, inner - level) = work[inner - level];
    }
  }
  return {std::move(lower), std::move(upper)};
}

// The cell's parallelogram from its corners (exact surface points: the net's corners) and its
// oriented box: axes along the parallelogram's u side, across it in its plane, and its normal;
// extents from the control points (the convex hull again).
void orient(const BezierNet& net, ProjectionCell& c) {
  const glm::dvec3 p00 = net.point(0, 0), p10 = net.point(net.n, 0), p01 = net.point(0, net.m),
                   p11 = net.point(net.n, net.m);
  c.middle = 0.25 * (p00 + p01 + p10 + p11);
  c.alongU = 0.5 * (p10 - p00 + p11 - p01);
  c.alongV = 0.5 * (p01 - p00 + p11 - p10);
  glm::dvec3 e0 = c.alongU, e1 = c.alongV;
  if (glm::length(e0) == 0.0) std::swap(e0, e1);
  const glm::dvec3 n = glm::cross(e0, e1);
  if (glm::length(n) > 1e-12 * glm::dot(e0, e0) + 1e-300) {
    c.axis[0] = glm::normalize(e0);
    c.axis[2] = glm::normalize(n);
    c.axis[1] = glm::cross(c.axis[2], c.axis[0]);
  }  // else the world axes stay
  for (int k = 0; k < 3; ++k) {
    c.lo[k] = std::numeric_limits<double>::infinity();
    c.hi[k] = -std::numeric_limits<double>::infinity();
  }
  for (int a = 0; a <= net.n; ++a)
    for (int b = 0; b <= net.m; ++b)
      for (int k = 0; k < 3; ++k) {
        const double t = glm::dot(net.point(a, b) - c.middle, c.axis[k]);
        c.lo[k] = std::min(c.lo[k], t);
        c.hi[k] = std::max(c.hi[k], t);
      }
  // Rounding in the dot products: a hair wider.
  for (int k = 0; k < 3; ++k) {
    const double pad = 1e-15 * (std::abs(c.lo[k]) + std::abs(c.hi[k]) + glm::length(c.middle));
    c.lo[k] -= pad, c.hi[k] += pad;
  }
}

// Appends the flat pieces of `net` (patch (i, j), local rectangle given) with their boxes.
void cutPatch(const BezierNet& net, int face, int i, int j, double u0, double u1, double v0, double v1, int depthU,
              int depthV, std::vector<ProjectionCell>& cells, std::vector<Box>& boxes) {
  const Box box = boxOf(net);
  const double size = glm::length(box.hi - box.lo);
  const double bendU = bend(net, true), bendV = bend(net, false);
  const double limit = kFlatness * size;
  const bool cutU = bendU > limit && depthU < kMaxDepth, cutV = bendV > limit && depthV < kMaxDepth;
  if (!cutU && !cutV) {
    ProjectionCell cell;
    cell.face = face, cell.i = i, cell.j = j, cell.u0 = u0, cell.u1 = u1, cell.v0 = v0, cell.v1 = v1;
    orient(net, cell);
    cells.push_back(cell);
    boxes.push_back(box);
    return;
  }
  const bool alongU = cutU && (!cutV || bendU >= bendV);
  auto [lower, upper] = halve(net, alongU);
  if (alongU) {
    const double um = 0.5 * (u0 + u1);
    cutPatch(lower, face, i, j, u0, um, v0, v1, depthU + 1, depthV, cells, boxes);
    cutPatch(upper, face, i, j, um, u1, v0, v1, depthU + 1, depthV, cells, boxes);
  } else {
    const double vm = 0.5 * (v0 + v1);
    cutPatch(lower, face, i, j, u0, u1, v0, vm, depthU, depthV + 1, cells, boxes);
    cutPatch(upper, face, i, j, u0, u1, vm, v1, depthU, depthV + 1, cells, boxes);
  }
}

// Coefficients of a patch's basis functions in some polynomial basis of degree n: B_r = sum_k a[r][k] b_k.
using BasisCoefficients = double[kMaxBasisCount][kMaxBezier];

// The (n + 1) x (m + 1) coefficients, row-major, of the tensor patch sum_r sum_s B_r(u) B_s(v)
// point(r, s) (homogeneous) in the bases whose coefficients are `au` (degree n, bu.count functions)
// and `av` (degree m): sum_{r,s} au[r][k] av[s][l] point(r, s), the v sums of each row shared.
std::vector<glm::dvec4> tensorCoefficients(const SpanBasis& bu, const SpanBasis& bv, const BasisCoefficients& au,
                                           const BasisCoefficients& av,
                                           const std::function<glm::dvec4(int, int)>& point) {
  const int n = bu.degree, m = bv.degree;
  std::vector<glm::dvec4> out(static_cast<size_t>(n + 1) * (m + 1), glm::dvec4(0.0));
  std::vector<glm::dvec4> partial(static_cast<size_t>(n + 1) * bv.count, glm::dvec4(0.0));
  for (int r = 0; r < bu.count; ++r)
    for (int s = 0; s < bv.count; ++s) {
      const glm::dvec4 p = point(r, s);
      for (int k = 0; k <= n; ++k) partial[static_cast<size_t>(k) * bv.count + s] += au[r][k] * p;
    }
  for (int k = 0; k <= n; ++k)
    for (int s = 0; s < bv.count; ++s)
      for (int l = 0; l <= m; ++l)
        out[static_cast<size_t>(k) * (m + 1) + l] += av[s][l] * partial[static_cast<size_t>(k) * bv.count + s];
  return out;
}

// The Bézier net of a tensor patch: sum_r sum_s B_r(u) B_s(v) point(r, s) (homogeneous).
BezierNet bezierOf(const SpanBasis& bu, const SpanBasis& bv, const std::function<glm::dvec4(int, int)>& point) {
  BasisCoefficients betaU, betaV;
  bernsteinOf(bu, betaU);
  bernsteinOf(bv, betaV);
  return {bu.degree, bv.degree, tensorCoefficients(bu, bv, betaU, betaV, point)};
}

// The patch sum_r sum_s B_r(u) B_s(v) point(r, s) (homogeneous) in the powers of (u - 1/2) and
// (v - 1/2), appended to `out` (ProjectionPatch). Each basis function's power coefficients about 0
// are moved to 1/2 (Taylor: c'_j = sum_{k >= j} C(k, j) (1/2)^(k - j) c_k), then multiplied out.
ProjectionPatch centredPowerOf(const SpanBasis& bu, const SpanBasis& bv, bool rational,
                               const std::function<glm::dvec4(int, int)>& point, std::vector<glm::dvec4>& out) {
  const auto centred = [](const SpanBasis& b, BasisCoefficients& c) {
    for (int r = 0; r < b.count; ++r)
      for (int j = 0; j <= b.degree; ++j) {
        double sum = 0.0, binom = 1.0, half = 1.0;  // C(k, j) and (1/2)^(k - j) for k = j, j + 1, ...
        for (int k = j; k <= b.degree; ++k) {
          sum += binom * half * b.coef[r][k];
          binom = binom * (k + 1) / (k + 1 - j);
          half *= 0.5;
        }
        c[r][j] = sum;
      }
  };
  BasisCoefficients cu, cv;
  centred(bu, cu);
  centred(bv, cv);
  ProjectionPatch patch;
  patch.n = bu.degree, patch.m = bv.degree, patch.first = out.size(), patch.rational = rational;
  const std::vector<glm::dvec4> c = tensorCoefficients(bu, bv, cu, cv, point);
  out.insert(out.end(), c.begin(), c.end());
  return patch;
}

// The principal curvatures at a point, signed towards +(du x dv) (a bowl that opens that way has
// both positive); false where the point is not regular.
bool principalCurvatures(const SurfacePoint& p, double& k1, double& k2) {
  const double E = glm::dot(p.du, p.du), F = glm::dot(p.du, p.dv), G = glm::dot(p.dv, p.dv);
  const double area2 = E * G - F * F;
  if (!(area2 > 1e-24 * E * G)) return false;
  const glm::dvec3 n = glm::cross(p.du, p.dv) / std::sqrt(area2);
  const double L = glm::dot(p.duu, n), M = glm::dot(p.duv, n), N = glm::dot(p.dvv, n);
  const double mean = (E * N - 2.0 * F * M + G * L) / (2.0 * area2), gauss = (L * N - M * M) / area2;
  const double spread = std::sqrt(std::max(mean * mean - gauss, 0.0));
  k1 = mean + spread, k2 = mean - spread;
  return true;
}

// How the cell bends, sampled on 3 x 3 points with a margin for what lies between them.
void measureBending(const Surface& s, ProjectionCell& c) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const SurfacePoint p = s.evaluate(c.i, c.j, c.u0 + 0.5 * a * (c.u1 - c.u0), c.v0 + 0.5 * b * (c.v1 - c.v0));
      double k1 = 0.0, k2 = 0.0;
      if (!principalCurvatures(p, k1, k2)) {
        c.bendsUp = c.bendsDown = std::numeric_limits<double>::infinity();
        continue;
      }
      c.bendsUp = std::max(c.bendsUp, 1.5 * k1);
      c.bendsDown = std::max(c.bendsDown, -1.5 * k2);
    }
}

// The box of a trim-loop piece lifted onto the surface: its ends and middle, widened on every side
// by twice the middle's distance from the chord (a short piece bends as a parabola, whose farthest
// point from the chord is its middle's).
Box sampledBox(const Surface& s, glm::dvec2 a, glm::dvec2 ab, double t0, double t1) {
  const auto [uMin, uMax] = s.parameterRangeU();
  const auto [vMin, vMax] = s.parameterRangeV();
  const auto at = [&](double t) {
    const glm::dvec2 uv = a + t * ab;
    return s.evaluateAt(std::clamp(uv.x, uMin, uMax), std::clamp(uv.y, vMin, vMax)).point;
  };
  const glm::dvec3 p0 = at(t0), p1 = at(t1), pm = at(0.5 * (t0 + t1));
  Box box;
  box.add(p0);
  box.add(p1);
  box.add(pm);
  const double bulge = 2.0 * glm::length(pm - 0.5 * (p0 + p1));
  box.lo -= glm::dvec3(bulge);
  box.hi += glm::dvec3(bulge);
  return box;
}

[[noreturn]] void refuseSize(size_t cells) {
  throw ModelError("points", std::to_string(cells) + " pieces",
                   "closest points take at most " + std::to_string(kMaxCells) +
                       " flat pieces (a few per patch): the model has too many patches to hold their bounds");
}

[[noreturn]] void refuseAlphaEB(const char* what) {
  throw ModelError("construction", "alpha_eb",
                   std::string("closest points on an α-EB ") + what +
                       " are not available: its pieces are not polynomials, so no control net bounds them");
}

// The local parameter range [a, b] of patch index `k` that [lo, hi] (global) meets, or false.
struct PatchAxis {
  bool knots = false;
  std::span<const double> t;  // knot vector
  int order = 0, count = 0;
  SpanRange range;
  int patchOf(double x) const {
    if (knots) return findKnotSpan(order, t, count, x);
    return std::clamp(static_cast<int>(std::floor(x)), range.first, range.last);
  }
  double start(int k) const { return knots ? t[k] : k; }
  double width(int k) const { return knots ? t[k + 1] - t[k] : 1.0; }
};

}  // namespace

ProjectionTree ProjectionTree::ofFaces(std::vector<ProjectionFace> faces) {
  ProjectionTree tree;
  tree.faces_ = std::move(faces);
  std::vector<Box> cellBoxes;
  // Per face, the first cell of each patch (row-major over the patch range) and one past the last.
  std::vector<std::vector<int>> patchCells(tree.faces_.size());
  size_t patches = 0;
  for (const ProjectionFace& face : tree.faces_) {
    const PatchRange range = face.surface->patches();
    patches += static_cast<size_t>(range.u.last - range.u.first + 1) * (range.v.last - range.v.first + 1);
  }
  if (patches > kMaxCells) refuseSize(patches);
  for (size_t f = 0; f < tree.faces_.size(); ++f) {
    const Surface& s = *tree.faces_[f].surface;
    if (s.parameterization() == Parameterization::AlphaEB) refuseAlphaEB("surface");
    const PatchRange range = s.patches();
    const int nu = range.u.last - range.u.first + 1, nv = range.v.last - range.v.first + 1;
    std::vector<int>& starts = patchCells[f];
    starts.reserve(static_cast<size_t>(nu) * nv + 1);
    for (int i = range.u.first; i <= range.u.last; ++i)
      for (int j = range.v.first; j <= range.v.last; ++j) {
        starts.push_back(static_cast<int>(tree.cells_.size()));
        // The patch's basis in each direction and its control point (r, s), homogeneous.
        SpanBasis bu, bv;
        std::function<glm::dvec4(int, int)> point;
        bool rational = false;
        if (s.usesKnotVector()) {
          const BSplineSurfaceData& d = s.knotData();
          if (d.knotsU[i] == d.knotsU[i + 1] || d.knotsV[j] == d.knotsV[j + 1]) continue;  // empty interval
          bu = knotIntervalBasis(d.orderU, d.knotsU, i), bv = knotIntervalBasis(d.orderV, d.knotsV, j);
          const int r0 = i - d.orderU + 1, s0 = j - d.orderV + 1;
          rational = !d.weights.empty();
          point = [&d, r0, s0](int r, int c) {
            const size_t k = static_cast<size_t>(r0 + r) * d.cols + (s0 + c);
            const double w = d.weights.empty() ? 1.0 : d.weights[k];
            return glm::dvec4(w * d.points[k], w);
          };
        } else {
          const glm::dvec3* first = &s.patchNet()[static_cast<size_t>(i + s.netOffsetU()) * s.netCols() +
                                                  (j + s.netOffsetV())];
          bu = s.basisU(), bv = s.basisV();
          point = [first, cols = s.netCols()](int r, int c) {
            return glm::dvec4(first[static_cast<size_t>(r) * cols + c], 1.0);
          };
        }
        const int patch = static_cast<int>(tree.patches_.size());
        tree.patches_.push_back(centredPowerOf(bu, bv, rational, point, tree.coefficients_));
        tree.patches_.back().face = static_cast<int>(f), tree.patches_.back().i = i, tree.patches_.back().j = j;
        const size_t before = tree.cells_.size();
        cutPatch(bezierOf(bu, bv, point), static_cast<int>(f), i, j, 0.0, 1.0, 0.0, 1.0, 0, 0, tree.cells_, cellBoxes);
        if (tree.cells_.size() > kMaxCells) refuseSize(tree.cells_.size());
        for (size_t k = before; k < tree.cells_.size(); ++k) {
          tree.cells_[k].patch = patch;
          measureBending(s, tree.cells_[k]);
        }
      }
    starts.push_back(static_cast<int>(tree.cells_.size()));
  }

  // Trim runs, their boxes from the cells they meet; cells no run meets are kept when their middle
  // is inside the loops.
  std::vector<char> keep(tree.cells_.size(), 1), met(tree.cells_.size(), 0);
  std::vector<std::vector<int>> cellRuns(tree.cells_.size());
  for (size_t f = 0; f < tree.faces_.size(); ++f) {
    const Surface& s = *tree.faces_[f].surface;
    const TrimLoops& trim = s.model().trim;
    if (trim.empty()) continue;
    const PatchRange range = s.patches();
    const int nv = range.v.last - range.v.first + 1;
    const std::vector<int>& starts = patchCells[f];
    const BSplineSurfaceData& d = s.knotData();
    const PatchAxis axisU{s.usesKnotVector(), d.knotsU, d.orderU, d.rows, range.u};
    const PatchAxis axisV{s.usesKnotVector(), d.knotsV, d.orderV, d.cols, range.v};
    const auto [uMin, uMax] = s.parameterRangeU();
    const auto [vMin, vMax] = s.parameterRangeV();
    // The cells a stretch of parameter space meets, their boxes' union; false past kMaxRunCells.
    const auto cellsMet = [&](glm::dvec2 lo, glm::dvec2 hi, Box& box, std::vector<int>& cells) {
      lo = glm::clamp(lo, glm::dvec2(uMin, vMin), glm::dvec2(uMax, vMax));
      hi = glm::clamp(hi, glm::dvec2(uMin, vMin), glm::dvec2(uMax, vMax));
      cells.clear();
      for (int i = axisU.patchOf(lo.x); i <= axisU.patchOf(hi.x); ++i) {
        const double a = (lo.x - axisU.start(i)) / axisU.width(i), b = (hi.x - axisU.start(i)) / axisU.width(i);
        for (int j = axisV.patchOf(lo.y); j <= axisV.patchOf(hi.y); ++j) {
          const double c = (lo.y - axisV.start(j)) / axisV.width(j), e = (hi.y - axisV.start(j)) / axisV.width(j);
          const size_t patch = static_cast<size_t>(i - range.u.first) * nv + (j - range.v.first);
          for (int k = starts[patch]; k < starts[patch + 1]; ++k) {
            const ProjectionCell& cell = tree.cells_[k];
            if (cell.u0 > b || cell.u1 < a || cell.v0 > e || cell.v1 < c) continue;
            box.add(cellBoxes[k]);
            cells.push_back(k);
          }
        }
      }
    };
    std::vector<int> cells;
    for (int l = 0; l < static_cast<int>(trim.loops.size()); ++l) {
      const std::vector<glm::dvec2>& loop = trim.loops[l];
      const int segments = static_cast<int>(loop.size());
      for (int k = 0; k < segments; ++k) {
        const glm::dvec2 a = loop[k], ab = loop[(k + 1) % segments] - a;
        // Halved until each piece meets few cells: the piece is then nearly straight on the
        // surface, and Newton along it finds its nearest point.
        const std::function<void(double, double, int)> addPiece = [&](double t0, double t1, int depth) {
          Box box;
          cellsMet(glm::min(a + t0 * ab, a + t1 * ab), glm::max(a + t0 * ab, a + t1 * ab), box, cells);
          if (cells.size() > kRunCells && depth < kMaxRunDepth) {
            addPiece(t0, 0.5 * (t0 + t1), depth + 1);
            addPiece(0.5 * (t0 + t1), t1, depth + 1);
            return;
          }
          if (cells.empty()) return;
          for (const int c : cells) {
            met[c] = 1;
            cellRuns[c].push_back(static_cast<int>(tree.runs_.size()));
          }
          ProjectionRun run{static_cast<int>(f), l, k, t0, t1, {}};
          run.box = sampledBox(s, a, ab, t0, t1);
          tree.runs_.push_back(run);
        };
        addPiece(0.0, 1.0, 0);
      }
    }
    const TrimClassifier inside(trim);
    for (int k = starts.front(); k < starts.back(); ++k) {
      if (met[k]) continue;
      const ProjectionCell& c = tree.cells_[k];
      const auto [U, V] = s.parameterOf(c.i, c.j, 0.5 * (c.u0 + c.u1), 0.5 * (c.v0 + c.v1));
      keep[k] = inside.inside({U, V});
    }
  }

  for (size_t k = 0; k < tree.cells_.size(); ++k)
    if (keep[k]) tree.leaves_.push_back({cellBoxes[k], LeafKind::Cell, static_cast<int>(k)});
  tree.cellRunStart_.assign(1, 0);
  for (size_t k = 0; k < tree.cells_.size(); ++k) {
    tree.cells_[k].index = static_cast<int>(k);
    tree.cellRuns_.insert(tree.cellRuns_.end(), cellRuns[k].begin(), cellRuns[k].end());
    tree.cellRunStart_.push_back(static_cast<int>(tree.cellRuns_.size()));
  }
  tree.buildHierarchy();
  return tree;
}

ProjectionTree ProjectionTree::ofPart(const Part& part) {
  std::vector<ProjectionFace> faces;
  faces.reserve(part.faces.size());
  for (const PartFace& face : part.faces) faces.push_back({&face.surface, face.id, face.reversed});
  return ofFaces(std::move(faces));
}

ProjectionTree ProjectionTree::ofCurve(const Curve& curve) {
  ProjectionTree tree;
  tree.curve_ = &curve;
  if (curve.parameterization() == Parameterization::AlphaEB) refuseAlphaEB("curve");
  SpanBasis one;  // the constant 1 in the second direction: a curve as a one-row patch
  one.count = 1;
  one.degree = 0;
  one.coef[0][0] = 1.0;
  const SpanRange spans = curve.spans();
  for (int span = spans.first; span <= spans.last; ++span) {
    BezierNet net;
    if (curve.usesKnotVector()) {
      const BSplineCurveData& d = curve.knotData();
      if (d.knots[span] == d.knots[span + 1]) continue;
      const int p0 = span - d.order + 1;
      net = bezierOf(knotIntervalBasis(d.order, d.knots, span), one, [&](int r, int) {
        const double w = d.weights.empty() ? 1.0 : d.weights[p0 + r];
        return glm::dvec4(w * d.points[p0 + r], w);
      });
    } else {
      const glm::dvec3* first = &curve.spanPoints()[span + curve.spanPointOffset()];
      net = bezierOf(curve.basis(), one, [&](int r, int) { return glm::dvec4(first[r], 1.0); });
    }
    std::vector<ProjectionCell> pieces;
    std::vector<Box> boxes;
    cutPatch(net, 0, span, 0, 0.0, 1.0, 0.0, 1.0, 0, kMaxDepth, pieces, boxes);
    if (tree.spans_.size() + pieces.size() > kMaxCells) refuseSize(tree.spans_.size() + pieces.size());
    for (size_t k = 0; k < pieces.size(); ++k) {
      tree.leaves_.push_back({boxes[k], LeafKind::Span, static_cast<int>(tree.spans_.size())});
      tree.spans_.push_back({span, pieces[k].u0, pieces[k].u1});
    }
  }
  tree.buildHierarchy();
  return tree;
}

void ProjectionTree::buildHierarchy() {
  nodes_.clear();
  if (leaves_.empty()) return;
  nodes_.reserve(2 * leaves_.size() / kLeafSize + 2);
  // Median splits along the widest axis of the leaves' centres, children stored depth first.
  const std::function<int(int, int)> build = [&](int first, int last) -> int {
    const int index = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Box box, centres;
    for (int k = first; k < last; ++k) {
      box.add(leaves_[k].box);
      centres.add(leaves_[k].box.centre());
    }
    nodes_[index].box = box;
    if (last - first <= kLeafSize) {
      nodes_[index].first = first;
      nodes_[index].count = last - first;
      return index;
    }
    const glm::dvec3 extent = centres.hi - centres.lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const int middle = first + (last - first) / 2;
    std::nth_element(leaves_.begin() + first, leaves_.begin() + middle, leaves_.begin() + last,
                     [axis](const Leaf& a, const Leaf& b) { return a.box.centre()[axis] < b.box.centre()[axis]; });
    build(first, middle);
    const int right = build(middle, last);
    nodes_[index].right = right;
    return index;
  };
  build(0, static_cast<int>(leaves_.size()));
  diagonal_ = glm::length(nodes_.front().box.hi - nodes_.front().box.lo);
}

}  // namespace shapespline::part
