// Written here rather than taken from a package: Debian has no permissively licensed constrained
// Delaunay triangulator (CGAL's 2-D triangulations are GPL, Triangle is non-free, poly2tri is not
// packaged and not robust).
//
// The method: every distinct point inserted into a large enclosing triangle in Hilbert-curve order
// (a walk from the last triangle then takes a few steps), each insertion split-and-flip (Lawson);
// every constraint segment recovered by flipping the edges it crosses (Sloan 1993: flip a crossing
// edge when its quadrilateral is strictly convex, otherwise try it again later) and the new edges
// flipped back to Delaunay; triangles kept by the parity of constraint crossings from the outside.
// All decisions go through the exact predicates, so the structure never sees an inconsistent answer.
#include <shapespline/part/constrained_delaunay.h>

#include <shapespline/core/value_text.h>
#include <shapespline/part/exact_predicates.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
#include <utility>

namespace shapespline::part {
namespace {

constexpr int kSuper = 3;  // the enclosing triangle's vertices come first: point i is vertex i + 3

inline int nextEdge(int e) { return e % 3 == 2 ? e - 2 : e + 1; }
inline int prevEdge(int e) { return e % 3 == 0 ? e + 2 : e - 1; }

std::string pointText(glm::dvec2 p) {
  return "(" + shortestText(p.x) + ", " + shortestText(p.y) + ")";
}

// Position along the Hilbert curve through a 2^16 x 2^16 grid.
uint64_t hilbertIndex(uint32_t x, uint32_t y) {
  constexpr uint32_t kN = 1u << 16;
  uint64_t d = 0;
  for (uint32_t s = kN / 2; s > 0; s /= 2) {
    const uint32_t rx = (x & s) ? 1 : 0;
    const uint32_t ry = (y & s) ? 1 : 0;
    d += uint64_t(s) * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = kN - 1 - x;
        y = kN - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

}  // namespace

struct ConstrainedDelaunay::Impl {
  std::vector<glm::dvec2> xy;   // vertex coordinates: the enclosing triangle's, then every point
  std::vector<int> dup;         // point index -> the point index of its vertex
  // Half-edges: 3t, 3t+1, 3t+2 are triangle t's, counter-clockwise; half-edge e runs from tri[e]
  // to tri[nextEdge(e)]. twin: the opposite half-edge (-1 on the enclosing triangle's sides).
  // count: how many constraint segments lie on the edge (both half-edges carry it); seg: one of them.
  std::vector<int> tri, twin, count, seg;
  std::vector<int> vertexEdge;  // a half-edge leaving each vertex (-1 for a duplicate)
  int last = 0;                 // the triangle the last walk ended in
  uint32_t random = 2463534242u;
  std::vector<int> flipStack;

  enum class Where { Inside, OnEdge, OnVertex, Outside };
  struct Location {
    Where where;
    int edge;    // Inside: a half-edge of the triangle; OnEdge: the half-edge; OnVertex: unused
    int vertex;  // OnVertex: the vertex
  };

  int addTriangle(int a, int b, int c) {
    const int t = int(tri.size()) / 3;
    tri.insert(tri.end(), {a, b, c});
    twin.insert(twin.end(), {-1, -1, -1});
    count.insert(count.end(), {0, 0, 0});
    seg.insert(seg.end(), {-1, -1, -1});
    return t;
  }
  void link(int e, int f) {
    twin[e] = f;
    if (f >= 0) twin[f] = e;
  }
  void setEdge(int e, int twinEdge, int n, int s) {
    link(e, twinEdge);
    count[e] = n;
    seg[e] = s;
  }
  uint32_t nextRandom() {
    random ^= random << 13;
    random ^= random >> 17;
    random ^= random << 5;
    return random;
  }

  // Stochastic visibility walk (terminates with probability one on any triangulation, Devillers
  // et al. 2002); falls back to a scan of every triangle should it ever run long.
  Location locate(glm::dvec2 p) {
    int t = last;
    const int triangleCount = int(tri.size()) / 3;
    for (int steps = 0; steps < 4 * triangleCount + 64; ++steps) {
      const Location where = classify(t, p);
      if (where.where != Where::Outside || where.edge < 0) {
        last = t;
        return where;
      }
      if (twin[where.edge] < 0) return {Where::Outside, -1, -1};
      t = twin[where.edge] / 3;
    }
    for (t = 0; t < triangleCount; ++t) {
      const Location where = classify(t, p);
      if (where.where != Where::Outside) {
        last = t;
        return where;
      }
    }
    return {Where::Outside, -1, -1};
  }

  // Where p lies relative to triangle t; Outside with the half-edge p lies beyond.
  Location classify(int t, glm::dvec2 p) {
    const int start = int(nextRandom() % 3);
    int zeros = 0, zeroEdge = -1, nonZeroEdge = -1;
    for (int k = 0; k < 3; ++k) {
      const int e = 3 * t + (start + k) % 3;
      const int o = orient2d(xy[tri[e]], xy[tri[nextEdge(e)]], p);
      if (o < 0) return {Where::Outside, e, -1};
      if (o == 0) {
        ++zeros;
        zeroEdge = e;
      } else {
        nonZeroEdge = e;
      }
    }
    if (zeros == 0) return {Where::Inside, 3 * t, -1};
    if (zeros == 1) {
      if (twin[zeroEdge] < 0) return {Where::Outside, -1, -1};
      return {Where::OnEdge, zeroEdge, -1};
    }
    return {Where::OnVertex, -1, tri[prevEdge(nonZeroEdge)]};
  }

  // Half-edge from u to v, or -1.
  int findEdge(int u, int v) const {
    const int start = vertexEdge[u];
    int e = start;
    do {
      if (tri[nextEdge(e)] == v) return e;
      e = twin[prevEdge(e)];
    } while (e >= 0 && e != start);
    if (e < 0) {  // on the enclosing triangle's side: turn the other way
      e = start;
      while (twin[e] >= 0) {
        e = nextEdge(twin[e]);
        if (e == start) break;
        if (tri[nextEdge(e)] == v) return e;
      }
    }
    return -1;
  }

  // Lawson flip of the edge a (not a constraint, inside a strictly convex quadrilateral):
  //   before: (p, q, r) with a = p->q and (q, p, s) with b = q->p
  //   after:  (s, q, r) with a = s->q and (r, p, s) with b = r->p; the new edge is r-s.
  void flip(int a) {
    const int b = twin[a];
    const int a1 = nextEdge(a), a2 = prevEdge(a), b1 = nextEdge(b), b2 = prevEdge(b);
    const int p = tri[a], q = tri[a1], r = tri[a2], s = tri[b2];
    const int ta2 = twin[a2], tb2 = twin[b2];
    const int na2 = count[a2], nb2 = count[b2], sa2 = seg[a2], sb2 = seg[b2];
    tri[a] = s;
    tri[b] = r;
    setEdge(a, tb2, nb2, sb2);
    setEdge(b, ta2, na2, sa2);
    link(a2, b2);
    count[a2] = count[b2] = 0;
    seg[a2] = seg[b2] = -1;
    vertexEdge[s] = a;
    vertexEdge[r] = b;
    vertexEdge[q] = a1;
    vertexEdge[p] = b1;
  }

  // Restores the Delaunay property around a new vertex: every half-edge on `stack` is opposite it.
  void legalizeAround(std::vector<int>& stack) {
    while (!stack.empty()) {
      const int e = stack.back();
      stack.pop_back();
      const int b = twin[e];
      if (b < 0 || count[e] > 0) continue;
      if (incircle(xy[tri[e]], xy[tri[nextEdge(e)]], xy[tri[prevEdge(e)]], xy[tri[prevEdge(b)]]) > 0) {
        const int b1 = nextEdge(b);
        flip(e);
        stack.push_back(e);
        stack.push_back(b1);
      }
    }
  }

  // Splits triangle t at the new vertex v into three.
  void splitTriangle(int t, int v, std::vector<int>& stack) {
    const int e0 = 3 * t, e1 = e0 + 1, e2 = e0 + 2;
    const int a = tri[e0], b = tri[e1], c = tri[e2];
    const int tw1 = twin[e1], tw2 = twin[e2];
    const int n1 = count[e1], n2 = count[e2], s1 = seg[e1], s2 = seg[e2];
    const int f0 = 3 * addTriangle(b, c, v), g0 = 3 * addTriangle(c, a, v);
    tri[e2] = v;  // (a, b, v)
    setEdge(f0, tw1, n1, s1);
    setEdge(g0, tw2, n2, s2);
    setEdge(e1, f0 + 2, 0, -1);
    setEdge(f0 + 1, g0 + 2, 0, -1);
    setEdge(g0 + 1, e2, 0, -1);
    count[e2] = 0;  // e2 was c->a and is now v->a
    seg[e2] = -1;
    vertexEdge[v] = e2;
    vertexEdge[a] = e0;
    vertexEdge[b] = f0;
    vertexEdge[c] = g0;
    stack.insert(stack.end(), {e0, f0, g0});
  }

  // Splits the edge h (p0->p1, triangles (p0, p1, r) and (p1, p0, s)) at the new vertex m into four
  // triangles; both halves keep the edge's constraints.
  void splitEdge(int h, int m, std::vector<int>& stack) {
    const int k = twin[h];
    const int h1 = nextEdge(h), h2 = prevEdge(h), k1 = nextEdge(k), k2 = prevEdge(k);
    const int p0 = tri[h], p1 = tri[k], r = tri[h2], s = tri[k2];
    const int n = count[h], sg = seg[h];
    const int th1 = twin[h1], tk1 = twin[k1];
    const int nh1 = count[h1], nk1 = count[k1], sh1 = seg[h1], sk1 = seg[k1];
    tri[h1] = m;  // (p0, m, r)
    tri[k1] = m;  // (p1, m, s)
    const int x0 = 3 * addTriangle(m, p1, r), y0 = 3 * addTriangle(m, p0, s);
    setEdge(h, y0, n, sg);
    setEdge(k, x0, n, sg);
    count[x0] = count[y0] = n;
    seg[x0] = seg[y0] = sg;
    setEdge(h1, x0 + 2, 0, -1);
    setEdge(k1, y0 + 2, 0, -1);
    setEdge(x0 + 1, th1, nh1, sh1);
    setEdge(y0 + 1, tk1, nk1, sk1);
    vertexEdge[m] = h1;
    vertexEdge[p0] = h;
    vertexEdge[p1] = k;
    vertexEdge[r] = h2;
    vertexEdge[s] = k2;
    stack.insert(stack.end(), {h2, x0 + 1, k2, y0 + 1});
  }

  // Inserts vertex v at a location found for it (Inside or OnEdge) and flips back to Delaunay.
  void insertAt(int v, const Location& at) {
    std::vector<int>& stack = flipStack;  // kept between insertions: no allocation per point
    if (at.where != Where::Inside && at.where != Where::OnEdge)
      throw std::logic_error("constrained Delaunay: a vertex inserted where no triangle holds it");
    if (at.where == Where::Inside) {
      splitTriangle(at.edge / 3, v, stack);
    } else {
      splitEdge(at.edge, v, stack);
    }
    legalizeAround(stack);
  }

  void recover(int a, int b, int segment, const std::vector<int>& segmentAt);
  [[noreturn]] void throwPointOn(int segment, int vertex, const std::vector<int>& segmentAt) const;
};

void ConstrainedDelaunay::Impl::throwPointOn(int segment, int vertex, const std::vector<int>& segmentAt) const {
  const int point = vertex - kSuper;
  const glm::dvec2 p = xy[vertex];
  // A point that ends another segment makes the two segments overlap or touch: name that segment.
  if (segmentAt[vertex] >= 0) {
    throw CrossingConstraints(segment, segmentAt[vertex],
                              "constraint segments " + std::to_string(segment) + " and " +
                                  std::to_string(segmentAt[vertex]) + " cross at " + pointText(p) +
                                  " (point " + std::to_string(point) + " lies on segment " +
                                  std::to_string(segment) + ")");
  }
  throw CrossingConstraints(segment, -1 - point,
                            "constraint segment " + std::to_string(segment) + " passes through point " +
                                std::to_string(point) + " at " + pointText(p));
}

// Makes a-b an edge by flipping the edges that cross it, then marks it a constraint.
void ConstrainedDelaunay::Impl::recover(int a, int b, int segment, const std::vector<int>& segmentAt) {
  const glm::dvec2 pa = xy[a], pb = xy[b];
  auto markConstraint = [&](int e) {
    for (const int h : {e, twin[e]}) {
      ++count[h];
      if (seg[h] < 0) seg[h] = segment;
    }
  };
  if (const int e = findEdge(a, b); e >= 0) {
    markConstraint(e);
    return;
  }
  // The triangle at a that the segment leaves through: (a, u, w) with u right of a->b and w left.
  int h = -1;
  {
    const int start = vertexEdge[a];
    int e = start;
    do {
      const int u = tri[nextEdge(e)];
      const int ou = orient2d(pa, pb, xy[u]);
      if (ou == 0 && glm::dot(xy[u] - pa, pb - pa) > 0.0) throwPointOn(segment, u, segmentAt);
      if (ou < 0 && orient2d(pa, pb, xy[tri[prevEdge(e)]]) > 0) {
        h = nextEdge(e);
        break;
      }
      e = twin[prevEdge(e)];
    } while (e >= 0 && e != start);
  }
  if (h < 0) throw std::logic_error("constrained Delaunay: no triangle at a segment's start");
  // Walk along the segment, collecting the crossed edges (u right, w left).
  std::deque<std::pair<int, int>> crossing;
  for (;;) {
    const int u = tri[h], w = tri[nextEdge(h)];
    if (count[h] > 0) {
      const glm::dvec2 d = pb - pa, uw = xy[w] - xy[u];
      const double t = (xy[u].x - pa.x) * uw.y - (xy[u].y - pa.y) * uw.x;
      const double denominator = d.x * uw.y - d.y * uw.x;
      const glm::dvec2 at = pa + d * (t / denominator);
      throw CrossingConstraints(segment, seg[h],
                                "constraint segments " + std::to_string(segment) + " and " +
                                    std::to_string(seg[h]) + " cross at " + pointText(at));
    }
    crossing.emplace_back(u, w);
    const int g = twin[h];
    const int x = tri[prevEdge(g)];
    if (x == b) break;
    const int ox = orient2d(pa, pb, xy[x]);
    if (ox == 0) throwPointOn(segment, x, segmentAt);
    h = ox < 0 ? prevEdge(g) : nextEdge(g);
  }
  // Sloan: flip crossing edges whose quadrilateral is strictly convex until none crosses.
  std::vector<std::pair<int, int>> created;
  size_t stalled = 0;
  while (!crossing.empty()) {
    const auto [u, w] = crossing.front();
    crossing.pop_front();
    const int e = findEdge(u, w);
    const int y = tri[prevEdge(e)], x = tri[prevEdge(twin[e])];
    if (orient2d(xy[x], xy[y], xy[u]) * orient2d(xy[x], xy[y], xy[w]) >= 0) {
      crossing.emplace_back(u, w);
      if (++stalled > 2 * crossing.size() + 2)
        throw std::logic_error("constrained Delaunay: segment recovery made no progress");
      continue;
    }
    stalled = 0;
    flip(e);
    if (orient2d(pa, pb, xy[x]) * orient2d(pa, pb, xy[y]) < 0) {
      crossing.emplace_back(x, y);
    } else {
      created.emplace_back(x, y);
    }
  }
  const int e = findEdge(a, b);
  if (e < 0) throw std::logic_error("constrained Delaunay: segment not recovered");
  markConstraint(e);
  // The new edges back to (constrained) Delaunay; each flip may unsettle the quadrilateral's sides.
  while (!created.empty()) {
    const auto [u, v] = created.back();
    created.pop_back();
    const int f = findEdge(u, v);
    if (f < 0 || count[f] > 0 || twin[f] < 0) continue;
    const int g = twin[f];
    if (incircle(xy[tri[f]], xy[tri[nextEdge(f)]], xy[tri[prevEdge(f)]], xy[tri[prevEdge(g)]]) > 0) {
      const int p = tri[f], q = tri[nextEdge(f)], r = tri[prevEdge(f)], s = tri[prevEdge(g)];
      flip(f);
      created.insert(created.end(), {{p, r}, {q, r}, {p, s}, {q, s}});
    }
  }
}

ConstrainedDelaunay::ConstrainedDelaunay(std::vector<glm::dvec2> points,
                                         const std::vector<std::array<int, 2>>& constraints)
    : points_(std::move(points)), impl_(std::make_shared<Impl>()) {
  Impl& m = *impl_;
  const int n = int(points_.size());
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(points_[i].x) || !std::isfinite(points_[i].y))
      throw std::invalid_argument("point " + std::to_string(i) + " is " + pointText(points_[i]) +
                                  ": coordinates must be finite");
  }
  for (size_t s = 0; s < constraints.size(); ++s) {
    for (const int i : constraints[s]) {
      if (i < 0 || i >= n)
        throw std::invalid_argument("constraint segment " + std::to_string(s) + " names point " +
                                    std::to_string(i) + ", outside 0.." + std::to_string(n - 1));
    }
  }
  // Exactly equal points: one vertex, the first of them.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int i, int j) {
    const glm::dvec2 a = points_[i], b = points_[j];
    return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : i < j;
  });
  m.dup.resize(n);
  for (int k = 0; k < n; ++k) {
    const int i = order[k];
    m.dup[i] = k > 0 && points_[order[k - 1]] == points_[i] ? m.dup[order[k - 1]] : i;
  }
  // The enclosing triangle: far enough that later points outside the loops still fall inside it.
  glm::dvec2 lo(0.0), hi(0.0);
  if (n > 0) {
    lo = hi = points_[0];
    for (const glm::dvec2& p : points_) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  }
  const glm::dvec2 centre = 0.5 * (lo + hi);
  double radius = std::max(hi.x - lo.x, hi.y - lo.y);
  if (!(radius > 0.0)) radius = std::max(1.0, std::max(std::fabs(centre.x), std::fabs(centre.y)));
  radius *= 1024.0;
  m.xy.reserve(kSuper + n);
  m.xy.push_back(centre + glm::dvec2(-2.0 * radius, -radius));
  m.xy.push_back(centre + glm::dvec2(2.0 * radius, -radius));
  m.xy.push_back(centre + glm::dvec2(0.0, 2.0 * radius));
  m.xy.insert(m.xy.end(), points_.begin(), points_.end());
  m.vertexEdge.assign(kSuper + n, -1);
  const size_t triangleCapacity = 2 * size_t(n) + 8;
  m.tri.reserve(3 * triangleCapacity);
  m.twin.reserve(3 * triangleCapacity);
  m.count.reserve(3 * triangleCapacity);
  m.seg.reserve(3 * triangleCapacity);
  m.addTriangle(0, 1, 2);
  m.vertexEdge[0] = 0;
  m.vertexEdge[1] = 1;
  m.vertexEdge[2] = 2;
  // Insertion along a Hilbert curve: each point is near the previous one, so walks are short.
  std::vector<std::pair<uint64_t, int>> keyed;
  keyed.reserve(n);
  const glm::dvec2 extent = glm::max(hi - lo, glm::dvec2(1e-300));
  for (int i = 0; i < n; ++i) {
    if (m.dup[i] != i) continue;
    const glm::dvec2 f = (points_[i] - lo) / extent * 65535.0;
    keyed.emplace_back(hilbertIndex(uint32_t(f.x), uint32_t(f.y)), i);
  }
  std::sort(keyed.begin(), keyed.end());
  for (const auto& [key, i] : keyed) {
    const int v = i + kSuper;
    m.insertAt(v, m.locate(m.xy[v]));  // distinct and inside the enclosing triangle: Inside or OnEdge
  }
  std::vector<int> segmentAt(kSuper + n, -1);
  for (size_t s = 0; s < constraints.size(); ++s) {
    for (const int i : constraints[s]) {
      if (segmentAt[m.dup[i] + kSuper] < 0) segmentAt[m.dup[i] + kSuper] = int(s);
    }
  }
  for (size_t s = 0; s < constraints.size(); ++s) {
    const int a = m.dup[constraints[s][0]] + kSuper, b = m.dup[constraints[s][1]] + kSuper;
    if (a != b) m.recover(a, b, int(s), segmentAt);  // a segment between equal points is no edge
  }
}

int ConstrainedDelaunay::insert(glm::dvec2 point) {
  Impl& m = *impl_;
  if (!std::isfinite(point.x) || !std::isfinite(point.y))
    throw std::invalid_argument("inserted point " + pointText(point) + ": coordinates must be finite");
  const Impl::Location at = m.locate(point);
  if (at.where == Impl::Where::OnVertex && at.vertex >= kSuper) return at.vertex - kSuper;
  if (at.where == Impl::Where::Outside || at.where == Impl::Where::OnVertex)
    throw std::invalid_argument("inserted point " + pointText(point) +
                                " lies beyond the triangulation's reach (about 1000 times the given points' extent)");
  const int index = int(points_.size());
  points_.push_back(point);
  m.xy.push_back(point);
  m.dup.push_back(index);
  m.vertexEdge.push_back(-1);
  m.insertAt(index + kSuper, at);
  return index;
}

std::vector<std::array<int, 3>> ConstrainedDelaunay::triangles() const {
  const Impl& m = *impl_;
  const int triangleCount = int(m.tri.size()) / 3;
  // Parity of constraint crossings from the enclosing triangle's corner, breadth first.
  std::vector<int8_t> inside(triangleCount, -1);
  std::vector<int> queue;
  queue.reserve(triangleCount);
  const int start = m.vertexEdge[0] / 3;
  inside[start] = 0;
  queue.push_back(start);
  for (size_t k = 0; k < queue.size(); ++k) {
    const int t = queue[k];
    for (int e = 3 * t; e < 3 * t + 3; ++e) {
      const int f = m.twin[e];
      if (f < 0 || inside[f / 3] >= 0) continue;
      inside[f / 3] = int8_t(inside[t] ^ (m.count[e] & 1));
      queue.push_back(f / 3);
    }
  }
  std::vector<std::array<int, 3>> result;
  for (int t = 0; t < triangleCount; ++t) {
    const int a = m.tri[3 * t], b = m.tri[3 * t + 1], c = m.tri[3 * t + 2];
    if (inside[t] == 1 && a >= kSuper && b >= kSuper && c >= kSuper)
      result.push_back({a - kSuper, b - kSuper, c - kSuper});
  }
  return result;
}

int ConstrainedDelaunay::vertexOf(int index) const {
  if (index < 0 || index >= int(impl_->dup.size()))
    throw std::invalid_argument("point index " + std::to_string(index) + " outside 0.." +
                                std::to_string(int(impl_->dup.size()) - 1));
  return impl_->dup[index];
}

}  // namespace shapespline::part
