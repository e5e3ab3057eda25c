#include <shapespline/sampling/gpu_limits.h>

#include <shapespline/core/value_scan.h>

#include <algorithm>
#include <cstdio>

namespace shapespline::sampling {
namespace {

std::optional<std::string> limitation(const FamilySpec& family, const std::vector<double>& alpha, Precision precision) {
  const bool fp32 = precision == Precision::Float;
  char text[96];
  if (fp32 && family.construction == Construction::GB && family.lambda > kMaxGBLambdaFloat) {
    std::snprintf(text, sizeof text, "GB lambda = %.3g", family.lambda);
    return std::string(text) +
           " is beyond what the fp32 GPU kernels resolve (above 1e4 normals lose more than 3 of 7 digits)";
  }
  if (family.construction == Construction::AlphaEB) {
    const double limit = fp32 ? kMinAlphaGpuFloat : kMinAlphaGpuDouble;
    const double lowest = alpha.empty() ? limit : valueRange(alpha.data(), alpha.size()).min;
    if (lowest < limit) {
      std::snprintf(text, sizeof text, "alpha = %.3g is below %.0e", lowest, limit);
      return std::string(text) + ", the smallest the " + (fp32 ? "fp32" : "fp64") +
             " GPU kernels represent in V = P + ((1-alpha)/alpha)(P - node)";
    }
  }
  return std::nullopt;
}

std::optional<std::string> knotLimitation(const std::vector<double>& knots, const char* field, Precision precision) {
  const bool fp32 = precision == Precision::Float;
  const double limit = fp32 ? kMinKnotIntervalGpuFloat : kMinKnotIntervalGpuDouble;
  char text[160];
  if (fp32 && knots.size() > kMaxKnotsGpuFloat) {
    std::snprintf(text, sizeof text, "%s: %zu knots; the fp32 GPU kernels index their records exactly for at most %zu",
                  field, knots.size(), kMaxKnotsGpuFloat);
    return std::string(text);
  }
  for (size_t i = 1; i < knots.size(); ++i) {
    const double h = knots[i] - knots[i - 1];
    if (!(h > 0.0)) continue;
    if (h < limit) {
      std::snprintf(text, sizeof text, "%s[%zu]: knot interval %.3g is below %.0e, the smallest the %s GPU kernels divide by",
                    field, i, h, limit, fp32 ? "fp32" : "fp64");
      return std::string(text);
    }
    if (fp32 && !(static_cast<float>(knots[i]) > static_cast<float>(knots[i - 1]))) {
      std::snprintf(text, sizeof text, "%s[%zu]: knot interval %.3g vanishes when the knots are rounded to fp32", field,
                    i, h);
      return std::string(text);
    }
  }
  return std::nullopt;
}

// Weights of a rational B-spline multiply the (scaled) net and are summed with it: far from 1 they
// would leave the precision's range before the quotient brings them back.
std::optional<std::string> weightLimitation(const std::vector<double>& weights, Precision precision) {
  const double limit = precision == Precision::Float ? 1e15 : 1e150;
  const auto [lo, hi] = std::minmax_element(weights.begin(), weights.end());
  if (lo == weights.end() || (*lo >= 1.0 / limit && *hi <= limit)) return std::nullopt;
  char text[160];
  std::snprintf(text, sizeof text, "weights from %.3g to %.3g leave [%.0e, %.0e], what the %s GPU kernels sum", *lo, *hi,
                1.0 / limit, limit, precision == Precision::Float ? "fp32" : "fp64");
  return std::string(text);
}

}  // namespace

std::optional<std::string> gpuLimitation(const Curve& curve, Precision precision) {
  if (curve.usesKnotVector()) {
    if (auto why = knotLimitation(curve.model().knots, "knots", precision)) return why;
    if (auto why = weightLimitation(curve.model().weights, precision)) return why;
  }
  return limitation(curve.model().family, curve.model().alpha, precision);
}

std::optional<std::string> gpuLimitation(const SurfaceShape& shape, double smallestAlpha, Precision precision) {
  if (parameterizationOf(shape) == Parameterization::KnotVector)
    throw std::logic_error("gpuLimitation: a knot-vector surface's limits need its knots and weights");
  return limitation(shape.family, {smallestAlpha}, precision);
}

std::optional<std::string> gpuLimitation(const Surface& surface, Precision precision) {
  if (surface.usesKnotVector()) {
    if (auto why = knotLimitation(surface.model().knotsU, "knots[0]", precision)) return why;
    if (auto why = knotLimitation(surface.model().knotsV, "knots[1]", precision)) return why;
    if (auto why = weightLimitation(surface.weights(), precision)) return why;
  }
  return limitation(surface.model().family, surface.model().alpha, precision);
}

}  // namespace shapespline::sampling
