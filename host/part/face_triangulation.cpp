#include <shapespline/part/constrained_delaunay.h>
#include <shapespline/part/face_triangulation.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <unordered_map>
#include <unordered_set>

namespace shapespline::part {
namespace {

// Rounds of refinement at most: each inserts an independent set of points, so a face converges in
// tens of rounds (70 on the largest real face seen); the cap only stops a surface that never does.
constexpr int kMaxRounds = 400;
// Twice a sliver's area in the scaled plane over its longest side squared: corners within 5e-10
// of the side's length from one line.
constexpr double kSliver = 1e-9;

glm::dvec3 unitOrZero(glm::dvec3 v) {
  const double l = glm::length(v);
  return l > 0.0 && std::isfinite(l) ? v / l : glm::dvec3(0.0);
}

double angleBetweenUnits(glm::dvec3 a, glm::dvec3 b) { return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)); }

// The point of the segment [a, b] nearest p.
glm::dvec3 nearestOnSegment(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
  const glm::dvec3 d = b - a;
  const double length2 = glm::dot(d, d);
  const double s = length2 > 0.0 ? std::clamp(glm::dot(p - a, d) / length2, 0.0, 1.0) : 0.0;
  return a + s * d;
}

double distanceToSegment3(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) { return glm::length(p - nearestOnSegment(p, a, b)); }

// The distance from p to the triangle abc: to its plane where p projects inside it, else to the
// nearest side (a degenerate triangle is its sides).
double distanceToTriangle(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double n2 = glm::dot(n, n);
  if (n2 > 0.0) {
    const glm::dvec3 q = p - glm::dot(p - a, n) / n2 * n;
    const bool inside = glm::dot(glm::cross(b - a, q - a), n) >= 0.0 && glm::dot(glm::cross(c - b, q - b), n) >= 0.0 &&
                        glm::dot(glm::cross(a - c, q - c), n) >= 0.0;
    if (inside) return glm::length(p - q);
  }
  return std::min({distanceToSegment3(p, a, b), distanceToSegment3(p, b, c), distanceToSegment3(p, c, a)});
}

// The plane's scale of each parameter, so that Delaunay triangles in (su U, sv V) are about as
// long in each direction as the deflection allows. A chord of length h along a direction of normal
// curvature k leaves the surface by about k h^2 / 8, so a direction's scale is its speed |S_u|
// times the square root of its curvature: a cylinder's triangles come out long along its axis, as
// BRepMesh's do, instead of fanning. Speeds and curvatures are means over a 5 x 5 grid of the
// loops' box (the curvature from the change of the partials between neighbours, along the normal).
// The flatter direction's curvature is taken as at least 1/64 of the other's (at most 8 times longer
// triangles); a plane, flat both ways, keeps the speeds alone.
glm::dvec2 parameterScale(const Surface& surface, glm::dvec2 lo, glm::dvec2 hi, FaceEvaluator& evaluator) {
  constexpr int n = 5;
  std::vector<glm::dvec2> uv;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) uv.push_back(lo + (hi - lo) * glm::dvec2((i + 0.5) / n, (j + 0.5) / n));
  std::vector<SurfaceFirst> out(uv.size());
  evaluator.evaluate(surface, uv, out);
  glm::dvec2 speed(0.0), bend(0.0);
  int bends[2] = {0, 0};
  const glm::dvec2 step = (hi - lo) / double(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const SurfaceFirst& s = out[size_t(i * n + j)];
      speed += glm::dvec2(glm::length(s.du), glm::length(s.dv));
      const glm::dvec3 normal = glm::cross(s.du, s.dv);
      const double area = glm::length(normal);
      if (!(area > 0.0) || !std::isfinite(area)) continue;
      // |n . S_uu| / |S_u|^2 from the next grid point along u (and likewise v).
      if (i + 1 < n && step.x > 0.0) {
        const SurfaceFirst& t = out[size_t((i + 1) * n + j)];
        const double l2 = glm::dot(s.du, s.du);
        if (l2 > 0.0) bend.x += std::abs(glm::dot(normal / area, (t.du - s.du) / step.x)) / l2, ++bends[0];
      }
      if (j + 1 < n && step.y > 0.0) {
        const SurfaceFirst& t = out[size_t(i * n + j + 1)];
        const double l2 = glm::dot(s.dv, s.dv);
        if (l2 > 0.0) bend.y += std::abs(glm::dot(normal / area, (t.dv - s.dv) / step.y)) / l2, ++bends[1];
      }
    }
  glm::dvec2 scale = speed / double(out.size());
  // A direction with no length (a degenerate box) takes the other's scale, or 1.
  if (!(scale.x > 0.0) || !std::isfinite(scale.x)) scale.x = scale.y > 0.0 && std::isfinite(scale.y) ? scale.y : 1.0;
  if (!(scale.y > 0.0) || !std::isfinite(scale.y)) scale.y = scale.x;
  glm::dvec2 curvature(bends[0] ? bend.x / bends[0] : 0.0, bends[1] ? bend.y / bends[1] : 0.0);
  const double most = std::max(curvature.x, curvature.y);
  if (most > 0.0 && std::isfinite(most)) {
    curvature = glm::max(curvature, glm::dvec2(most / 64.0));
    scale *= glm::sqrt(curvature / most);
  }
  return scale;
}

class FaceRefiner {
 public:
  FaceRefiner(const Surface& surface, bool reversed, const FaceTolerances& tol, FaceEvaluator& evaluator)
      : surface_(surface), sign_(reversed ? -1.0 : 1.0), tol_(tol), evaluator_(evaluator) {}

  FaceTriangles run(const std::vector<std::vector<LoopVertex>>& loops, const std::vector<glm::dvec3>& positions,
                    std::atomic<int64_t>& budget) {
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    std::vector<glm::dvec2> loopUv;
    for (const auto& loop : loops)
      for (const LoopVertex& v : loop) {
        lo = glm::min(lo, v.uv);
        hi = glm::max(hi, v.uv);
        loopUv.push_back(v.uv);
      }
    scale_ = parameterScale(surface_, lo, hi, evaluator_);

    // The loops' own vertices: their part-wide points, and this face's normal there.
    std::vector<SurfaceFirst> atLoops(loopUv.size());
    evaluator_.evaluate(surface_, loopUv, atLoops);
    FaceTriangles result;
    std::vector<glm::dvec2> planePoints;
    std::vector<std::array<int, 2>> constraints;
    for (const auto& loop : loops) {
      const int first = static_cast<int>(planePoints.size());
      for (size_t k = 0; k < loop.size(); ++k) {
        const int index = static_cast<int>(planePoints.size());
        planePoints.push_back(loop[k].uv * scale_);
        vertices_.push_back({loop[k].uv, positions[loop[k].vertex], normalOf(atLoops[size_t(index)]), loop[k].vertex});
        result.loopNormals.push_back(vertices_.back().normal);
        constraints.push_back({index, k + 1 == loop.size() ? first : index + 1});
      }
    }
    std::optional<ConstrainedDelaunay> cdt;
    try {
      cdt.emplace(std::move(planePoints), constraints);
    } catch (const CrossingConstraints& e) {
      throw CrossingTrimLoops(e.what());
    }

    for (int round = 0; round < kMaxRounds; ++round) {
      const std::vector<std::array<int, 3>> triangles = cdt->triangles();
      if (static_cast<int64_t>(triangles.size()) > budget.load())
        throw TriangleBudgetExceeded("the face needs more triangles than the budget has left");
      const std::vector<std::pair<glm::dvec2, Vertex>> added = refinementPoints(triangles);
      if (added.empty()) {
        collect(triangles, result);
        budget -= static_cast<int64_t>(result.triangles.size());
        return result;
      }
      for (const auto& [uv, vertex] : added) {
        const int index = cdt->insert(uv * scale_);
        if (static_cast<size_t>(index) == vertices_.size()) vertices_.push_back(vertex);
      }
    }
    collect(cdt->triangles(), result);
    budget -= static_cast<int64_t>(result.triangles.size());
    return result;
  }

 private:
  struct Vertex {
    glm::dvec2 uv;
    glm::dvec3 point, normal;
    uint32_t id;  // part-wide for loop vertices; interior ones are numbered in collect()
  };

  // The unit normal, or zero where the partials are (nearly) parallel or vanish, as at a pole: there
  // the rounded cross product points anywhere and would fail every angle test.
  glm::dvec3 normalOf(const SurfaceFirst& s) const {
    const glm::dvec3 n = glm::cross(s.du, s.dv);
    const double scale = std::max(glm::dot(s.du, s.du), glm::dot(s.dv, s.dv));
    if (!(glm::length(n) > 1e-10 * scale)) return glm::dvec3(0.0);
    return sign_ * unitOrZero(n);
  }

  // Whether p is within a thousandth of the deflection of one of `corners`: a point there adds no
  // accuracy, and where the surface is singular (a side drawn nearly to a point) inserting it only
  // piles points onto the spot, folding triangles smaller than any tolerance.
  bool nearAny(glm::dvec3 p, std::initializer_list<const Vertex*> corners) const {
    for (const Vertex* c : corners)
      if (glm::length(p - c->point) < 1e-3 * tol_.deflection) return true;
    return false;
  }

  // A triangle or inner edge found fine in an earlier round (no point to add) is not looked at
  // again: its test depends on its own vertices alone, which do not move. Triangles by their
  // sorted corners, edges by edgeKey.
  static std::array<int, 3> sortedCorners(const std::array<int, 3>& t) {
    std::array<int, 3> k = t;
    std::sort(k.begin(), k.end());
    return k;
  }
  struct CornersHash {
    size_t operator()(const std::array<int, 3>& k) const {
      return std::hash<uint64_t>()((uint64_t(uint32_t(k[0])) << 42) ^ (uint64_t(uint32_t(k[1])) << 21) ^ uint32_t(k[2]));
    }
  };
  std::unordered_set<std::array<int, 3>, CornersHash> fineTriangles_;
  std::unordered_set<uint64_t> fineEdges_;
  // The edge between vertices a < b.
  static uint64_t edgeKey(int a, int b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); }

  // The centroids of the triangles and the midpoints of the inner edges where the mesh is too far
  // from the surface or turns too much, as new vertices (evaluated once, here).
  std::vector<std::pair<glm::dvec2, Vertex>> refinementPoints(const std::vector<std::array<int, 3>>& triangles) {
    // Each triangle's centroid, summed in the order of its sorted corners (the same bits whichever
    // corner the triangulation lists first); -1: not evaluated (fine before, or a sliver).
    std::vector<glm::dvec2> uv;
    std::vector<ptrdiff_t> at(triangles.size(), -1);
    uv.reserve(triangles.size() * 2);
    // Slivers: triangles whose corners are (nearly) on one line in the plane, as three loop
    // vertices along a straight side are after rounding. A sliver's centroid and the midpoint of
    // its long side lie on the loop, and inserting them only makes more slivers there; its surface
    // is the loop's, cut to the deflection already, so neither it nor its sides are split.
    std::vector<bool> sliver(triangles.size());
    for (size_t k = 0; k < triangles.size(); ++k) {
      const glm::dvec2 a = vertices_[size_t(triangles[k][0])].uv * scale_, b = vertices_[size_t(triangles[k][1])].uv * scale_,
                       c = vertices_[size_t(triangles[k][2])].uv * scale_;
      const glm::dvec2 ab = b - a, ac = c - a, bc = c - b;
      const double longest2 = std::max({glm::dot(ab, ab), glm::dot(ac, ac), glm::dot(bc, bc)});
      sliver[k] = std::abs(ab.x * ac.y - ab.y * ac.x) <= kSliver * longest2;
      if (sliver[k]) continue;
      const std::array<int, 3> c3 = sortedCorners(triangles[k]);
      if (fineTriangles_.count(c3)) continue;
      at[k] = static_cast<ptrdiff_t>(uv.size());
      uv.push_back((vertices_[size_t(c3[0])].uv + vertices_[size_t(c3[1])].uv + vertices_[size_t(c3[2])].uv) / 3.0);
    }
    // Inner edges: those two triangles share (each listed once, from its lower vertex), unless one
    // of them is a sliver.
    struct EdgeUse {
      int triangles = 0;
      bool sliver = false;
      size_t first = 0;
    };
    struct InnerEdge {
      int a, b;
      size_t left, right;  // its two triangles
    };
    std::unordered_map<uint64_t, EdgeUse> seen;
    std::vector<InnerEdge> inner;
    std::vector<std::vector<size_t>> neighbours(triangles.size());
    seen.reserve(triangles.size() * 3);
    for (size_t k = 0; k < triangles.size(); ++k)
      for (int j = 0; j < 3; ++j) {
        const auto& t = triangles[k];
        const int a = std::min(t[j], t[(j + 1) % 3]), b = std::max(t[j], t[(j + 1) % 3]);
        EdgeUse& use = seen[edgeKey(a, b)];
        use.sliver = use.sliver || sliver[k];
        if (++use.triangles == 1) use.first = k;
        if (use.triangles == 2) {
          neighbours[k].push_back(use.first);
          neighbours[use.first].push_back(k);
          if (!use.sliver && !fineEdges_.count(edgeKey(a, b)))
            inner.push_back({a, b, use.first, k});
        }
      }
    const size_t firstEdge = uv.size();
    for (const InnerEdge& e : inner) uv.push_back(0.5 * (vertices_[size_t(e.a)].uv + vertices_[size_t(e.b)].uv));
    std::vector<SurfaceFirst> s(uv.size());
    evaluator_.evaluate(surface_, uv, s);

    std::vector<std::pair<glm::dvec2, Vertex>> added;
    struct Candidate {
      double score;             // how far past the tolerance, in its units
      size_t triangle, other;   // the triangles it splits (other: SIZE_MAX for a centroid)
      std::pair<glm::dvec2, Vertex> point;
    };
    std::vector<Candidate> candidates;
    for (size_t k = 0; k < triangles.size(); ++k) {
      if (at[k] < 0) continue;
      const Vertex& a = vertices_[size_t(triangles[k][0])];
      const Vertex& b = vertices_[size_t(triangles[k][1])];
      const Vertex& c = vertices_[size_t(triangles[k][2])];
      const SurfaceFirst& centroid = s[size_t(at[k])];
      const glm::dvec3 normal = normalOf(centroid);
      bool split = distanceToTriangle(centroid.point, a.point, b.point, c.point) > tol_.deflection;
      // The surface's own turn across the triangle (its normals at the corners against the one at
      // the centroid), not the triangle's plane: a sliver's plane says nothing of the surface, and
      // splitting slivers for it only makes more of them.
      // A triangle already shorter than the deflection is flat enough whatever its normals do.
      const double longest = std::max({glm::length(b.point - a.point), glm::length(c.point - b.point),
                                       glm::length(a.point - c.point)});
      for (const Vertex* corner : {&a, &b, &c})
        if (!split && longest > tol_.deflection && normal != glm::dvec3(0.0) && corner->normal != glm::dvec3(0.0))
          split = angleBetweenUnits(normal, corner->normal) > tol_.angle;
      const glm::dvec2 centre = uv[size_t(at[k])];
      if (split && !nearAny(centroid.point, {&a, &b, &c}))
        candidates.push_back({distanceToTriangle(centroid.point, a.point, b.point, c.point) / tol_.deflection, k, SIZE_MAX,
                              {centre, {centre, centroid.point, normal, 0}}});
      else
        fineTriangles_.insert(sortedCorners(triangles[k]));
    }
    // An inner edge's midpoint is measured from the edge along the surface normal there: where the
    // parameters run unevenly (a plane whose net is no parallelogram) the surface point slides along
    // the surface, which is no distance from the mesh. Where there is no normal (a pole), the whole
    // distance.
    for (size_t k = 0; k < inner.size(); ++k) {
      const size_t mid = firstEdge + k;
      const glm::dvec3 a = vertices_[size_t(inner[k].a)].point, b = vertices_[size_t(inner[k].b)].point;
      const glm::dvec3 normal = normalOf(s[mid]);
      const double off = normal == glm::dvec3(0.0) ? distanceToSegment3(s[mid].point, a, b)
                                                   : std::abs(glm::dot(normal, s[mid].point - nearestOnSegment(s[mid].point, a, b)));
      if (off > tol_.deflection && !nearAny(s[mid].point, {&vertices_[size_t(inner[k].a)], &vertices_[size_t(inner[k].b)]}))
        candidates.push_back({off / tol_.deflection, inner[k].left, inner[k].right, {uv[mid], {uv[mid], s[mid].point, normal, 0}}});
      else
        fineEdges_.insert(edgeKey(inner[k].a, inner[k].b));
    }
    // The worst first, and none beside a triangle split this round: one point often mends its
    // neighbours too, and splitting them all at once over-refines (twice BRepMesh's count on a
    // sphere). Those left wait for the next round, which looks at them again.
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const Candidate& x, const Candidate& y) { return x.score > y.score; });
    std::vector<bool> locked(triangles.size(), false);
    for (const Candidate& c : candidates) {
      if (locked[c.triangle] || (c.other != SIZE_MAX && locked[c.other])) continue;
      for (size_t t : {c.triangle, c.other}) {
        if (t == SIZE_MAX) continue;
        locked[t] = true;
        for (size_t n : neighbours[t]) locked[n] = true;
      }
      added.push_back(c.point);
    }
    return added;
  }

  // The triangles with part-wide ids (interior vertices numbered as they are first used), wound
  // so that they face along the face's outward normal.
  void collect(const std::vector<std::array<int, 3>>& triangles, FaceTriangles& out) {
    const size_t loopVertices = out.loopNormals.size();
    std::vector<uint32_t> interiorId(vertices_.size(), UINT32_MAX);
    for (const auto& t : triangles) {
      std::array<uint32_t, 3> ids{};
      for (int k = 0; k < 3; ++k) {
        const size_t v = size_t(t[k]);
        if (v < loopVertices) {
          ids[size_t(k)] = vertices_[v].id;
          continue;
        }
        if (interiorId[v] == UINT32_MAX) {
          interiorId[v] = FaceTriangles::kInterior + static_cast<uint32_t>(out.points.size());
          out.points.push_back(vertices_[v].point);
          out.normals.push_back(vertices_[v].normal);
        }
        ids[size_t(k)] = interiorId[v];
      }
      if (sign_ < 0.0) std::swap(ids[1], ids[2]);
      out.triangles.push_back(ids);
    }
  }

  const Surface& surface_;
  double sign_;
  const FaceTolerances& tol_;
  FaceEvaluator& evaluator_;
  glm::dvec2 scale_{1.0};
  std::vector<Vertex> vertices_;  // by the triangulation's point index
};

}  // namespace

FaceTriangles triangulateFace(const Surface& surface, bool reversed, const std::vector<std::vector<LoopVertex>>& loops,
                              const std::vector<glm::dvec3>& positions, const FaceTolerances& tolerances,
                              FaceEvaluator& evaluator, std::atomic<int64_t>& budget) {
  return FaceRefiner(surface, reversed, tolerances, evaluator).run(loops, positions, budget);
}

}  // namespace shapespline::part
