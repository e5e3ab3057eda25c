#include <shapespline/gpu/list_packing.h>

#include <shapespline/gpu/kernels.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace shapespline::gpu {

// Knot-vector samples carry the knot span and the knot parameter itself (bspline kernels); the
// parameter is formed and looked up by core (Curve/Surface::parameterOf, spanAt, patchAt), so a
// sample reaches the same span and value as the CPU evaluation.

std::vector<layout::ListSampleD> curveListSamples(const GpuCurve& curve, std::span<const CurveSample> samples) {
  const Curve& c = curve.curve();
  std::vector<layout::ListSampleD> s(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const CurveSample& x = samples[i];
    if (x.span < c.spans().first || x.span > c.spans().last || !(x.t >= 0.0 && x.t <= 1.0))
      throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " (span " + std::to_string(x.span) +
                              ", t " + std::to_string(x.t) + ") is outside the curve");
    if (curve.knotVector()) {
      const auto& kn = c.model().knots;
      if (!(kn[x.span + 1] > kn[x.span]))
        throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " lies on the empty knot interval " +
                                std::to_string(x.span));
      const auto [lo, hi] = c.parameterRange();
      const double u = std::clamp(c.parameterOf(x.span, x.t), lo, hi);
      double t = 0.0;
      s[i] = {uint32_t(c.spanAt(u, t)), 0u, 0u, 0u, u, 0.0, 0.0, 0.0};
      continue;
    }
    s[i] = {uint32_t(x.span), 0u, 0u, 0u, x.t, 0.0, 0.0, 0.0};
  }
  return s;
}

std::vector<layout::ListSampleD> curveListSamplesAt(const GpuCurve& curve, std::span<const double> u) {
  const Curve& c = curve.curve();
  const auto [lo, hi] = c.parameterRange();
  std::vector<layout::ListSampleD> s(u.size());
  for (size_t i = 0; i < u.size(); ++i) {
    const double x = u[i];
    if (!(x >= lo && x <= hi))
      throw std::out_of_range("evaluateListAt: u[" + std::to_string(i) + "] = " + std::to_string(x) +
                              " outside the parameter range");
    double t = 0.0;
    const uint32_t span = uint32_t(c.spanAt(x, t));
    // Knot vectors: Curve::evaluateAt evaluates at the knot parameter itself.
    s[i] = {span, 0u, 0u, 0u, curve.knotVector() ? x : t, 0.0, 0.0, 0.0};
  }
  return s;
}

std::vector<layout::ListSampleD> surfaceListSamples(const GpuSurface& surface, std::span<const SurfaceSample> samples) {
  const Surface& f = surface.surface();
  const PatchRange r = f.patches();
  std::vector<layout::ListSampleD> s(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const SurfaceSample& x = samples[i];
    if (x.i < r.u.first || x.i > r.u.last || x.j < r.v.first || x.j > r.v.last || !(x.u >= 0.0 && x.u <= 1.0) ||
        !(x.v >= 0.0 && x.v <= 1.0))
      throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " (patch " + std::to_string(x.i) + "," +
                              std::to_string(x.j) + ") is outside the surface");
    if (surface.knotVector()) {
      const SurfaceShape& m = f.model();
      if (!(m.knotsU[x.i + 1] > m.knotsU[x.i]) || !(m.knotsV[x.j + 1] > m.knotsV[x.j]))
        throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " lies on an empty knot interval");
      const auto [ulo, uhi] = f.parameterRangeU();
      const auto [vlo, vhi] = f.parameterRangeV();
      const auto [U, V] = f.parameterOf(x.i, x.j, x.u, x.v);
      const double xu = std::clamp(U, ulo, uhi), xv = std::clamp(V, vlo, vhi);
      int spanU = 0, spanV = 0;
      double lu = 0.0, lv = 0.0;
      f.patchAt(xu, xv, spanU, spanV, lu, lv);
      s[i] = {uint32_t(spanU), uint32_t(spanV), uint32_t(x.i), uint32_t(x.j), xu, xv, x.u, x.v};
      continue;
    }
    s[i] = {uint32_t(x.i), uint32_t(x.j), 0u, 0u, x.u, x.v, 0.0, 0.0};
  }
  return s;
}

std::vector<SurfaceSample> surfaceSamplesAt(const GpuSurface& surface, std::span<const std::pair<double, double>> uv) {
  const Surface& f = surface.surface();
  const auto [ulo, uhi] = f.parameterRangeU();
  const auto [vlo, vhi] = f.parameterRangeV();
  std::vector<SurfaceSample> local(uv.size());
  for (size_t i = 0; i < uv.size(); ++i) {
    const auto [U, V] = uv[i];
    if (!(U >= ulo && U <= uhi) || !(V >= vlo && V <= vhi))
      throw std::out_of_range("evaluateListAt: sample " + std::to_string(i) + " outside the parameter range");
    SurfaceSample& x = local[i];
    f.patchAt(U, V, x.i, x.j, x.u, x.v);
  }
  return local;
}

std::vector<std::byte> packListSamples(const std::vector<layout::ListSampleD>& samples, Precision p) {
  std::vector<std::byte> bytes;
  if (samples.empty()) return bytes;  // memcpy of nothing from a null data() is still undefined
  if (p == Precision::Double) {
    bytes.resize(samples.size() * sizeof(layout::ListSampleD));
    std::memcpy(bytes.data(), samples.data(), bytes.size());
    return bytes;
  }
  std::vector<layout::ListSampleF> f(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const layout::ListSampleD& s = samples[i];
    f[i] = {s.i, s.j, s.intervalU, s.intervalV, float(s.u), float(s.v), float(s.localU), float(s.localV)};
  }
  bytes.resize(f.size() * sizeof(layout::ListSampleF));
  std::memcpy(bytes.data(), f.data(), bytes.size());
  return bytes;
}

void readReals(const std::byte* src, Precision p, size_t n, double* out) {
  if (p == Precision::Double) {
    std::memcpy(out, src, n * 8);
    return;
  }
  for (size_t i = 0; i < n; ++i) {
    float x;
    std::memcpy(&x, src + 4 * i, 4);
    out[i] = x;
  }
}

FieldMask listFields(FieldMask asked, FieldMask all) {
  if (asked == 0 || (asked & ~all) != 0)
    throw std::invalid_argument("a list evaluation's fields must be a non-empty subset of the model's (mask " +
                                std::to_string(asked) + ", allowed " + std::to_string(all) + ")");
  return asked;
}

}  // namespace shapespline::gpu
