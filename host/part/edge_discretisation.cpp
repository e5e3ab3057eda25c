#include <shapespline/part/edge_discretisation.h>

#include <shapespline/core/parallel_for.h>
#include <shapespline/part/face_triangulation.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

namespace shapespline::part {
namespace {

// A point's distance from the line through a and b (from a when a == b).
double distanceToChord(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
  const glm::dvec3 d = b - a;
  const double length2 = glm::dot(d, d);
  if (length2 == 0.0) return glm::length(p - a);
  const double s = std::clamp(glm::dot(p - a, d) / length2, 0.0, 1.0);
  return glm::length(p - (a + s * d));
}

double angleBetween(glm::dvec3 a, glm::dvec3 b) {
  const double la = glm::length(a), lb = glm::length(b);
  if (la == 0.0 || lb == 0.0) return 0.0;
  return std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0));
}

constexpr int kMaxDepth = 30;  // 2^-30 of an edge's range: far below any deflection a budget allows

// One edge's cut: intervals of t tested in rounds (one list evaluation per round) and halved where
// they fail; each interval carries its middle point from its parent's quarter point.
class EdgeCutter {
 public:
  EdgeCutter(const PartFace& face, const CoedgePath& path, const EdgeTolerances& tol, FaceEvaluator& evaluator,
             std::atomic<int64_t>& budget)
      : face_(face), path_(path), tol_(tol), evaluator_(evaluator), budget_(budget) {}

  void cut(DiscreteEdge& edge) {
    const double t0 = std::min(path_.firstT(), path_.lastT()), t1 = std::max(path_.firstT(), path_.lastT());
    const std::vector<glm::dvec3> ends = points({t0, t1});
    // A closed edge (a whole circle) has no chord to test: start from quarters.
    const int pieces = glm::length(ends[1] - ends[0]) <= tol_.deflection ? 4 : 1;
    std::vector<double> ts;
    for (int k = 0; k <= pieces; ++k) ts.push_back(k == pieces ? t1 : t0 + (t1 - t0) * k / pieces);
    std::vector<glm::dvec3> ps = pieces == 1 ? ends : points(ts);
    std::vector<Interval> pending;
    for (int k = 0; k < pieces; ++k) pending.push_back({ts[k], ts[k + 1], ps[k], ps[k + 1], std::nullopt, 0});
    std::map<double, glm::dvec3> vertices;
    for (size_t k = 0; k < ts.size(); ++k) vertices[ts[k]] = ps[k];
    while (!pending.empty()) {
      std::vector<double> ask;
      for (const Interval& i : pending) {
        const double m = 0.5 * (i.a + i.b);
        if (!i.middle) ask.push_back(m);
        ask.push_back(0.5 * (i.a + m));
        ask.push_back(0.5 * (m + i.b));
      }
      const std::vector<glm::dvec3> got = points(ask);
      std::vector<Interval> next;
      size_t k = 0;
      for (const Interval& i : pending) {
        const double m = 0.5 * (i.a + i.b);
        const glm::dvec3 pm = i.middle ? *i.middle : got[k++];
        const glm::dvec3 q1 = got[k++], q3 = got[k++];
        const bool flat = distanceToChord(pm, i.pa, i.pb) <= tol_.deflection &&
                          distanceToChord(q1, i.pa, i.pb) <= tol_.deflection &&
                          distanceToChord(q3, i.pa, i.pb) <= tol_.deflection &&
                          2.0 * angleBetween(pm - i.pa, i.pb - pm) <= tol_.angle;
        if (flat || i.depth >= kMaxDepth || !(i.a < m && m < i.b)) continue;
        vertices[m] = pm;
        next.push_back({i.a, m, i.pa, pm, q1, i.depth + 1});
        next.push_back({m, i.b, pm, i.pb, q3, i.depth + 1});
      }
      // Every edge vertex costs at least one triangle of each face that uses the edge.
      if ((budget_ -= static_cast<int64_t>(next.size() / 2)) < 0)
        throw TriangleBudgetExceeded("an edge needs more vertices than the triangle budget");
      pending = std::move(next);
    }
    for (const auto& [t, p] : vertices) {
      edge.t.push_back(t);
      edge.points.push_back(p);
    }
  }

 private:
  struct Interval {
    double a, b;
    glm::dvec3 pa, pb;
    std::optional<glm::dvec3> middle;
    int depth;
  };

  std::vector<glm::dvec3> points(const std::vector<double>& ts) {
    std::vector<glm::dvec2> uv;
    uv.reserve(ts.size());
    for (double t : ts) uv.push_back(path_.uvAt(t));
    std::vector<SurfaceFirst> out(uv.size());
    evaluator_.evaluate(face_.surface, uv, out);
    std::vector<glm::dvec3> p;
    p.reserve(out.size());
    for (const SurfaceFirst& s : out) p.push_back(s.point);
    return p;
  }

  const PartFace& face_;
  const CoedgePath& path_;
  const EdgeTolerances& tol_;
  FaceEvaluator& evaluator_;
  std::atomic<int64_t>& budget_;
};

}  // namespace

std::vector<DiscreteEdge> discretiseEdges(const Part& part, const CoedgePaths& paths, const EdgeTolerances& tolerances,
                                          FaceEvaluator& evaluator, int threads, int64_t maxVertices) {
  std::atomic<int64_t> budget{maxVertices};
  std::map<int, std::vector<EdgeUse>> usesById;
  for (size_t f = 0; f < paths.size(); ++f)
    for (size_t l = 0; l < paths[f].size(); ++l)
      for (size_t c = 0; c < paths[f][l].size(); ++c)
        usesById[paths[f][l][c].edge()].push_back({static_cast<int>(f), static_cast<int>(l), static_cast<int>(c)});
  std::vector<DiscreteEdge> edges;
  edges.reserve(usesById.size());
  for (auto& [id, uses] : usesById) {
    DiscreteEdge& edge = edges.emplace_back();
    edge.id = id;
    const io::PartEdgeEntry* entry = part.edge(id);
    edge.degenerate = entry && entry->degenerate;
    edge.uses = std::move(uses);
  }
  parallelFor(edges.size(), threads, [&](size_t e) {
    DiscreteEdge& edge = edges[e];
    const EdgeUse& use = edge.uses.front();
    const PartFace& face = part.faces[static_cast<size_t>(use.face)];
    const CoedgePath& path = paths[static_cast<size_t>(use.face)][static_cast<size_t>(use.loop)][static_cast<size_t>(use.coedge)];
    if (edge.degenerate) {
      const double t = std::min(path.firstT(), path.lastT());
      const glm::dvec2 uv = path.uvAt(t);
      SurfaceFirst p;
      evaluator.evaluate(face.surface, std::span(&uv, 1), std::span(&p, 1));
      edge.t = {t};
      edge.points = {p.point};
      return;
    }
    EdgeCutter(face, path, tolerances, evaluator, budget).cut(edge);
  });
  return edges;
}

}  // namespace shapespline::part
