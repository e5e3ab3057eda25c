#include <shapespline/sampling/gpu_limits.h>

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
    const auto lowest = std::min_element(alpha.begin(), alpha.end());
    if (lowest != alpha.end() && *lowest < limit) {
      std::snprintf(text, sizeof text, "alpha = %.3g is below %.0e", *lowest, limit);
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

}  // namespace

std::optional<std::string> gpuLimitation(const Curve& curve, Precision precision) {
  if (curve.usesKnotVector()) {
    if (auto why = knotLimitation(curve.model().knots, "knots", precision)) return why;
  }
  return limitation(curve.model().family, curve.model().alpha, precision);
}

std::optional<std::string> gpuLimitation(const Surface& surface, Precision precision) {
  if (surface.usesKnotVector()) {
    if (auto why = knotLimitation(surface.model().knotsU, "knots[0]", precision)) return why;
    if (auto why = knotLimitation(surface.model().knotsV, "knots[1]", precision)) return why;
  }
  return limitation(surface.model().family, surface.model().alpha, precision);
}

}  // namespace shapespline::sampling
