#include <shapespline/core/trim_classifier.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace shapespline {

double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

TrimClassifier::TrimClassifier(const TrimLoops& trim) : tolerance_(trim.tolerance) {
  double lo = 1e300, hi = -1e300;
  for (const auto& loop : trim.loops)
    for (size_t i = 0; i < loop.size(); ++i) {
      edges_.push_back({loop[i], loop[(i + 1) % loop.size()]});
      lo = std::min(lo, loop[i].y);
      hi = std::max(hi, loop[i].y);
    }
  if (edges_.empty()) return;
  // About two edges a slab on average: few enough that a query is short, the index linear in size.
  slabs_ = static_cast<int>(std::clamp<size_t>(edges_.size() / 2, 1, 1 << 16));
  v0_ = lo - tolerance_;
  slabHeight_ = std::max((hi + tolerance_ - v0_) / slabs_, 1e-300);
  std::vector<int> count(static_cast<size_t>(slabs_) + 1, 0);
  auto range = [&](const Edge& e) {
    return std::pair{slabOf(std::min(e.a.y, e.b.y) - tolerance_), slabOf(std::max(e.a.y, e.b.y) + tolerance_)};
  };
  for (const Edge& e : edges_) {
    const auto [first, last] = range(e);
    for (int s = first; s <= last; ++s) ++count[static_cast<size_t>(s) + 1];
  }
  slabStart_.assign(static_cast<size_t>(slabs_) + 1, 0);
  for (int s = 0; s < slabs_; ++s) slabStart_[static_cast<size_t>(s) + 1] = slabStart_[static_cast<size_t>(s)] + count[static_cast<size_t>(s) + 1];
  slabEdges_.resize(static_cast<size_t>(slabStart_.back()));
  std::vector<int> fill(slabStart_.begin(), slabStart_.end() - 1);
  for (size_t e = 0; e < edges_.size(); ++e) {
    const auto [first, last] = range(edges_[e]);
    for (int s = first; s <= last; ++s) slabEdges_[static_cast<size_t>(fill[static_cast<size_t>(s)]++)] = static_cast<int>(e);
  }
}

int TrimClassifier::slabOf(double v) const {
  const double s = std::floor((v - v0_) / slabHeight_);
  return static_cast<int>(std::clamp(s, 0.0, static_cast<double>(slabs_ - 1)));
}

bool TrimClassifier::inside(glm::dvec2 p) const {
  if (edges_.empty()) return true;
  const int s = slabOf(p.y);
  bool odd = false;
  for (int k = slabStart_[static_cast<size_t>(s)]; k < slabStart_[static_cast<size_t>(s) + 1]; ++k) {
    const Edge& e = edges_[static_cast<size_t>(slabEdges_[static_cast<size_t>(k)])];
    if (distanceToSegment(p, e.a, e.b) <= tolerance_) return true;
    // Half-open in v (a <= v < b, either way up), so a ray through a vertex counts it once.
    if ((e.a.y <= p.y) != (e.b.y <= p.y)) {
      const double u = e.a.x + (p.y - e.a.y) / (e.b.y - e.a.y) * (e.b.x - e.a.x);
      if (u > p.x) odd = !odd;
    }
  }
  return odd;
}

}  // namespace shapespline
