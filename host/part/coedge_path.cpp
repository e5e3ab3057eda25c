#include <shapespline/part/coedge_path.h>

#include <algorithm>
#include <stdexcept>

namespace shapespline::part {

CoedgePath::CoedgePath(const io::PartCoedge& coedge, const std::vector<glm::dvec2>& loop)
    : edge_(coedge.edge), t_(coedge.t) {
  if (loop.empty() || t_.size() < 2) throw std::invalid_argument("a coedge needs two points of a non-empty loop");
  uv_.reserve(t_.size());
  for (size_t j = 0; j < t_.size(); ++j) uv_.push_back(loop[(static_cast<size_t>(coedge.start) + j) % loop.size()]);
}

glm::dvec2 CoedgePath::uvAt(double t) const {
  // Search on ascending t whichever way the coedge runs.
  const bool down = descending();
  const auto less = [down](double a, double b) { return down ? a > b : a < b; };
  if (!less(t_.front(), t)) return uv_.front();
  if (!less(t, t_.back())) return uv_.back();
  const size_t j = static_cast<size_t>(std::upper_bound(t_.begin(), t_.end(), t, less) - t_.begin());  // t_[j-1] <= t < t_[j]
  const double span = t_[j] - t_[j - 1];
  const double s = span == 0.0 ? 0.0 : (t - t_[j - 1]) / span;
  return uv_[j - 1] + s * (uv_[j] - uv_[j - 1]);
}

}  // namespace shapespline::part
