#include <shapespline/core/diagnostics.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

namespace shapespline {

namespace {

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

// Names entry k (0-based over the flat array) of a curve ("points[k]") or a row-major surface
// array ("points[i][j]") as in model files.
using Namer = std::function<std::string(size_t)>;

void checkAlpha(const std::vector<double>& alpha, const Namer& name, std::vector<Warning>& out) {
  if (alpha.empty()) return;
  const auto it = std::min_element(alpha.begin(), alpha.end());
  if (*it < kAlphaWarn)
    out.push_back({name(static_cast<size_t>(it - alpha.begin())),
                   "alpha = " + num(*it) + " is below " + num(kAlphaWarn) +
                       ": V = P + ((1-alpha)/alpha)(P - node) amplifies rounding errors by 1/alpha (docs/math.md "
                       "section 14), so about " + num(std::floor(-std::log10(*it))) + " digits are lost"});
}

// `forEach(f)` calls f(k, P_k) for every point in order (a vector, or a surface's net in place).
template <class ForEach>
void checkPoints(ForEach&& forEach, int dims, const Namer& name, std::vector<Warning>& out) {
  double biggest = 0.0, biggestValue = 0.0;
  size_t where = 0;
  int axis = 0;
  bool any = false;
  glm::dvec3 lo(0.0), hi(0.0);
  forEach([&](size_t k, const glm::dvec3& p) {
    if (!any) lo = hi = p, any = true;
    for (int d = 0; d < dims; ++d) {
      const double a = std::abs(p[d]);
      if (a > biggest) biggest = a, biggestValue = p[d], where = k, axis = d;
      lo[d] = std::min(lo[d], p[d]);
      hi[d] = std::max(hi[d], p[d]);
    }
  });
  if (!any) return;
  // Extent as the largest per-axis width: never squares, so it cannot overflow or underflow itself.
  // hi - lo may overflow to inf for coordinates near DBL_MAX; that case is caught by `biggest`.
  double extent = 0.0;
  for (int d = 0; d < dims; ++d) extent = std::max(extent, hi[d] - lo[d]);
  const std::string at = name(where) + "[" + std::to_string(axis) + "]";
  if (biggest > kHugeCoordinate) {
    out.push_back({at, "coordinate " + num(biggestValue) + " exceeds " + num(kHugeCoordinate) +
                           " in magnitude: products of coordinates overflow fp64, so normals and lengths lose "
                           "precision and derivatives may overflow"});
  } else if (extent > 0.0 && extent < kTinyExtent) {
    out.push_back({name(0), "the control net spans only " + num(extent) + " (below " + num(kTinyExtent) +
                                "): squared differences underflow fp64, so normals and lengths lose precision"});
  }
  if (extent > 0.0 && extent < kRelativeExtent * biggest)
    out.push_back({at, "the control net spans only " + num(extent) + " but lies " + num(biggest) +
                           " from the origin: fewer than " +
                           num(std::max(0.0, std::floor(16 + std::log10(extent / biggest)))) +
                           " significant digits describe its shape"});
}

// Strictly or weakly increasing knots; `field` names the array ("knots", "knots[0]").
void checkKnots(const std::vector<double>& knots, const std::string& field, std::vector<Warning>& out) {
  if (knots.size() < 2) return;
  const double range = knots.back() - knots.front();
  double smallest = INFINITY;
  size_t where = 0;
  for (size_t k = 1; k < knots.size(); ++k) {
    const double h = knots[k] - knots[k - 1];
    if (h > 0.0 && h < smallest) smallest = h, where = k;
  }
  if (!(range > 0.0) || smallest == INFINITY) return;
  if (smallest < kKnotRatio * range || smallest < kTinyKnot || !std::isfinite(range))
    out.push_back({field + "[" + std::to_string(where) + "]",
                   "knot interval " + num(smallest) + " is below " + num(kKnotRatio) + " of the knot range " +
                       num(range) + " or below " + num(kTinyKnot) +
                       ": derivatives scale with 1/h^r and lose precision or overflow"});
}

void checkFamily(const FamilySpec& f, std::vector<Warning>& out) {
  if (f.construction == Construction::GB && f.lambda > kGBLambdaWarn)
    out.push_back({"lambda", "GB lambda = " + num(f.lambda) + " exceeds " + num(kGBLambdaWarn) +
                                 ": the basis equals its lambda -> infinity limit to within rounding (docs/math.md "
                                 "section 7.1)"});
}

auto eachOf(const std::vector<glm::dvec3>& points) {
  return [&points](auto&& f) {
    for (size_t k = 0; k < points.size(); ++k) f(k, points[k]);
  };
}

template <class ForEach>
std::vector<Warning> surfaceWarnings(const SurfaceShape& model, ForEach&& forEachPoint) {
  std::vector<Warning> out;
  const size_t cols = static_cast<size_t>(std::max(model.cols, 1));
  const auto grid = [cols](const char* what) {
    return [what, cols](size_t k) {
      return std::string(what) + "[" + std::to_string(k / cols) + "][" + std::to_string(k % cols) + "]";
    };
  };
  checkFamily(model.family, out);
  checkPoints(forEachPoint, 3, grid("points"), out);
  checkAlpha(model.alpha, grid("alpha"), out);
  checkKnots(model.knotsU, "knots[0]", out);
  checkKnots(model.knotsV, "knots[1]", out);
  return out;
}

}  // namespace

std::vector<Warning> precisionWarnings(const CurveModel& model) {
  std::vector<Warning> out;
  checkFamily(model.family, out);
  checkPoints(eachOf(model.points), model.dimension, [](size_t k) { return "points[" + std::to_string(k) + "]"; }, out);
  checkAlpha(model.alpha, [](size_t k) { return "alpha[" + std::to_string(k) + "]"; }, out);
  checkKnots(model.knots, "knots", out);
  return out;
}

std::vector<Warning> precisionWarnings(const SurfaceModel& model) {
  return surfaceWarnings(model, eachOf(model.points));
}

std::vector<Warning> precisionWarnings(const Surface& surface) {
  return surfaceWarnings(surface.model(), [&surface](auto&& f) {
    size_t k = 0;
    surface.forEachControlPoint([&](const glm::dvec3& p) { f(k++, p); });
  });
}

std::string formatWarning(const Warning& warning) { return "warning: " + warning.field + ": " + warning.message; }

}  // namespace shapespline
