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

void checkAlpha(const SmallestAlpha& smallest, const Namer& name, std::vector<Warning>& out) {
  if (!smallest.any || !(smallest.value < kAlphaWarn)) return;
  out.push_back({name(smallest.where),
                 "alpha = " + num(smallest.value) + " is below " + num(kAlphaWarn) +
                     ": V = P + ((1-alpha)/alpha)(P - node) amplifies rounding errors by 1/alpha (docs/math.md "
                     "section 14), so about " + num(std::floor(-std::log10(smallest.value))) + " digits are lost"});
}

void checkPoints(const PointSpread& spread, const Namer& name, std::vector<Warning>& out) {
  if (!spread.any) return;
  const int dims = spread.dims, axis = spread.axis;
  const double biggest = spread.biggest, biggestValue = spread.biggestValue;
  const size_t where = spread.where;
  const glm::dvec3 &lo = spread.lo, &hi = spread.hi;
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

// A surface's warnings from its points' spread and its smallest α.
std::vector<Warning> surfaceWarnings(const SurfaceShape& model, const PointSpread& points, const SmallestAlpha& alpha) {
  std::vector<Warning> out;
  const size_t cols = static_cast<size_t>(std::max(model.cols, 1));
  const auto grid = [cols](const char* what) {
    return [what, cols](size_t k) {
      return std::string(what) + "[" + std::to_string(k / cols) + "][" + std::to_string(k % cols) + "]";
    };
  };
  checkFamily(model.family, out);
  checkPoints(points, grid("points"), out);
  checkAlpha(alpha, grid("alpha"), out);
  checkKnots(model.knotsU, "knots[0]", out);
  checkKnots(model.knotsV, "knots[1]", out);
  return out;
}

template <class ForEach>
std::vector<Warning> surfaceWarnings(const SurfaceShape& model, ForEach&& forEachPoint) {
  PointSpread points{3};
  forEachPoint([&](size_t, const glm::dvec3& p) { points.add(p); });
  SmallestAlpha alpha;
  alpha.add(model.alpha.data(), model.alpha.size());
  return surfaceWarnings(model, points, alpha);
}

}  // namespace

std::vector<Warning> precisionWarnings(const CurveModel& model) {
  CurveWarningScan scan(model);
  scan.points(model.points.data(), model.points.size());
  scan.alphas(model.alpha.data(), model.alpha.size());
  return scan.warnings();
}

std::vector<Warning> CurveWarningScan::warnings() const {
  std::vector<Warning> out;
  checkFamily(shape_.family, out);
  checkPoints(spread(), [](size_t k) { return "points[" + std::to_string(k) + "]"; }, out);
  checkAlpha(smallestAlpha(), [](size_t k) { return "alpha[" + std::to_string(k) + "]"; }, out);
  checkKnots(shape_.knots, "knots", out);
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

void PointSpread::add(const glm::dvec3& p) {
  if (!any) lo = hi = p, any = true;
  for (int d = 0; d < dims; ++d) {
    const double a = std::abs(p[d]);
    if (a > biggest) biggest = a, biggestValue = p[d], where = seen, axis = d;
    lo[d] = std::min(lo[d], p[d]);
    hi[d] = std::max(hi[d], p[d]);
  }
  ++seen;
}

void SmallestAlpha::add(const double* alpha, size_t count) {
  for (size_t k = 0; k < count; ++k, ++seen)
    if (!any || alpha[k] < value) value = alpha[k], where = seen, any = true;
}

std::vector<Warning> SurfaceWarningScan::warnings() const { return surfaceWarnings(shape_, spread(), smallestAlpha()); }

std::string formatWarning(const Warning& warning) { return "warning: " + warning.field + ": " + warning.message; }

}  // namespace shapespline
