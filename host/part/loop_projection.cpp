#include <shapespline/part/loop_projection.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace shapespline::part {
namespace {

constexpr int kSteps = 4;  // quadratic near the foot: 4 steps take a 1e-3 start to rounding

}  // namespace

void projectLoopVertices(const Surface& surface, std::vector<std::vector<LoopVertex>>& loops,
                         const std::vector<glm::dvec3>& positions, FaceEvaluator& evaluator) {
  // A vertex moves by less than a quarter of the way to its loop neighbours, so that the loop keeps
  // its shape: where the map is singular (a pole's side, where all of a segment maps to one point)
  // the steps could otherwise slide a vertex onto its neighbour's segment.
  std::vector<LoopVertex*> vertices;
  std::vector<double> reach;
  for (auto& loop : loops)
    for (size_t k = 0; k < loop.size(); ++k) {
      vertices.push_back(&loop[k]);
      const glm::dvec2 uv = loop[k].uv;
      reach.push_back(0.25 * std::min(glm::length(uv - loop[(k + 1) % loop.size()].uv),
                                      glm::length(uv - loop[(k + loop.size() - 1) % loop.size()].uv)));
    }
  const auto [u0, u1] = surface.parameterRangeU();
  const auto [v0, v1] = surface.parameterRangeV();
  std::vector<glm::dvec2> uv(vertices.size()), trial(vertices.size());
  for (size_t k = 0; k < vertices.size(); ++k) uv[k] = vertices[k]->uv;
  std::vector<SurfaceFirst> at(uv.size()), next(uv.size());
  evaluator.evaluate(surface, uv, at);
  std::vector<bool> moving(uv.size(), true);
  for (int step = 0; step < kSteps; ++step) {
    for (size_t k = 0; k < uv.size(); ++k) {
      trial[k] = uv[k];
      if (!moving[k]) continue;
      const glm::dvec3 r = at[k].point - positions[vertices[k]->vertex];
      const glm::dvec3 &du = at[k].du, &dv = at[k].dv;
      const double a = glm::dot(du, du), b = glm::dot(du, dv), c = glm::dot(dv, dv), det = a * c - b * b;
      if (!(det > 1e-12 * a * c)) {  // parallel or vanishing partials: no direction to move in
        moving[k] = false;
        continue;
      }
      const double gu = glm::dot(du, r), gv = glm::dot(dv, r);
      trial[k] = {std::clamp(uv[k].x - (c * gu - b * gv) / det, u0, u1),
                  std::clamp(uv[k].y - (a * gv - b * gu) / det, v0, v1)};
      if (!(glm::length(trial[k] - vertices[k]->uv) < reach[k])) {
        trial[k] = uv[k];
        moving[k] = false;
      }
    }
    evaluator.evaluate(surface, trial, next);
    for (size_t k = 0; k < uv.size(); ++k) {
      if (!moving[k]) continue;
      const glm::dvec3 p = positions[vertices[k]->vertex];
      if (glm::length(next[k].point - p) < glm::length(at[k].point - p)) {
        uv[k] = trial[k];
        at[k] = next[k];
      } else {
        moving[k] = false;  // at the foot, to rounding
      }
    }
  }
  for (size_t k = 0; k < uv.size(); ++k) vertices[k]->uv = uv[k];
}

}  // namespace shapespline::part
