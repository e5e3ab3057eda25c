#include <shapespline/core/tess_patches.h>

namespace shapespline {
namespace {

std::vector<int> nonEmpty(const SpanRange& range, const std::vector<double>& knots) {
  std::vector<int> out;
  for (int i = range.first; i <= range.last; ++i)
    if (knots.empty() || knots[i] < knots[i + 1]) out.push_back(i);
  return out;
}

}  // namespace

TessPatches::TessPatches(const Surface& surface) {
  const SurfaceShape& m = surface.model();
  const bool knot = surface.usesKnotVector();
  u = nonEmpty(surface.patches().u, knot ? m.knotsU : std::vector<double>{});
  v = nonEmpty(surface.patches().v, knot ? m.knotsV : std::vector<double>{});
}

std::array<float, 2> TessPatches::uv(const Surface& surface, const TessSample& s) const {
  const int i = u[s.a], j = v[s.b];
  if (surface.usesKnotVector()) {
    const auto [U, V] = surface.parameterOf(i, j, s.u, s.v);
    return {float(U), float(V)};
  }
  return {float(i) + float(s.u), float(j) + float(s.v)};
}

TessRates uniformTessRates(const Surface& surface, int rate) {
  const TessPatches p(surface);
  return TessRates::uniform(p.countU(), p.countV(), surface.model().closedU, surface.model().closedV, rate);
}

}  // namespace shapespline
