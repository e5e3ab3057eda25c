#include <shapespline/gpu/list_packing.h>

#include <shapespline/core/bspline.h>
#include <shapespline/gpu/kernels.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace shapespline::gpu {
namespace {

// The span core/bspline.h evalBSplineCurve/Surface uses at knot parameter x, and x clamped to the
// domain, as a (span, parameter) pair for the SAMPLES buffer.
std::pair<uint32_t, double> knotSpanOf(int order, const std::vector<double>& knots, int count, double x) {
  const int span = findKnotSpan(order, knots, count, x);
  return {uint32_t(span), std::clamp(x, knots[order - 1], knots[count])};
}

}  // namespace

std::vector<layout::ListSampleD> curveListSamples(const GpuCurve& curve, std::span<const CurveSample> samples) {
  std::vector<layout::ListSampleD> s(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const CurveSample& x = samples[i];
    if (x.span < curve.spans().first || x.span > curve.spans().last || !(x.t >= 0.0 && x.t <= 1.0))
      throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " (span " + std::to_string(x.span) +
                              ", t " + std::to_string(x.t) + ") is outside the curve");
    if (curve.knotVector()) {
      // core/curve.cpp Curve::evaluate: the knot parameter a + t (b - a), then findKnotSpan.
      const auto& kn = curve.model().knots;
      const double a = kn[x.span], b = kn[x.span + 1];
      if (!(b > a))
        throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " lies on the empty knot interval " +
                                std::to_string(x.span));
      const auto [span, u] = knotSpanOf(curve.model().family.order, kn, int(curve.model().points.size()),
                                        a + x.t * (b - a));
      s[i] = {span, 0u, 0u, 0u, u, 0.0, 0.0, 0.0};
      continue;
    }
    s[i] = {uint32_t(x.span), 0u, 0u, 0u, x.t, 0.0, 0.0, 0.0};
  }
  return s;
}

std::vector<layout::ListSampleD> curveListSamplesAt(const GpuCurve& curve, std::span<const double> u) {
  const auto [lo, hi] = curve.parameterRange();
  std::vector<layout::ListSampleD> s(u.size());
  std::vector<CurveSample> local;
  for (size_t i = 0; i < u.size(); ++i) {
    const double x = u[i];
    if (!(x >= lo && x <= hi))
      throw std::out_of_range("evaluateListAt: u[" + std::to_string(i) + "] = " + std::to_string(x) +
                              " outside the parameter range");
    if (curve.knotVector()) {
      // core/curve.cpp Curve::evaluateAt: evalBSplineCurve at the knot parameter itself.
      const auto [span, xc] =
          knotSpanOf(curve.model().family.order, curve.model().knots, int(curve.model().points.size()), x);
      s[i] = {span, 0u, 0u, 0u, xc, 0.0, 0.0, 0.0};
      continue;
    }
    // core/curve.cpp Curve::spanOfParameter.
    const SpanRange r = curve.spans();
    const auto& kn = curve.spanKnots();
    CurveSample cs;
    if (!kn.empty()) {
      int sp = int(std::upper_bound(kn.begin(), kn.end(), x) - kn.begin()) - 1;
      sp = std::clamp(sp, 0, int(kn.size()) - 2);
      cs = {r.first + sp, std::clamp((x - kn[sp]) / (kn[sp + 1] - kn[sp]), 0.0, 1.0)};
    } else {
      const int j = std::clamp(int(std::floor(x)), r.first, r.last);
      cs = {j, std::clamp(x - j, 0.0, 1.0)};
    }
    local.push_back(cs);
  }
  return curve.knotVector() ? s : curveListSamples(curve, local);
}

std::vector<layout::ListSampleD> surfaceListSamples(const GpuSurface& surface, std::span<const SurfaceSample> samples) {
  const PatchRange r = surface.patches();
  std::vector<layout::ListSampleD> s(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const SurfaceSample& x = samples[i];
    if (x.i < r.u.first || x.i > r.u.last || x.j < r.v.first || x.j > r.v.last || !(x.u >= 0.0 && x.u <= 1.0) ||
        !(x.v >= 0.0 && x.v <= 1.0))
      throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " (patch " + std::to_string(x.i) + "," +
                              std::to_string(x.j) + ") is outside the surface");
    if (surface.knotVector()) {
      // core/surface.cpp evalPatch: knot parameters u0 + u (u1 - u0), then evalBSplineSurface.
      const SurfaceModel& m = surface.model();
      const int ku = m.family.order, kv = m.orderV > 0 ? m.orderV : m.family.order;
      const double u0 = m.knotsU[x.i], u1 = m.knotsU[x.i + 1], v0 = m.knotsV[x.j], v1 = m.knotsV[x.j + 1];
      if (!(u1 > u0) || !(v1 > v0))
        throw std::out_of_range("evaluateList: sample " + std::to_string(i) + " lies on an empty knot interval");
      const auto [spanU, xu] = knotSpanOf(ku, m.knotsU, m.rows, u0 + x.u * (u1 - u0));
      const auto [spanV, xv] = knotSpanOf(kv, m.knotsV, m.cols, v0 + x.v * (v1 - v0));
      s[i] = {spanU, spanV, uint32_t(x.i), uint32_t(x.j), xu, xv, x.u, x.v};
      continue;
    }
    s[i] = {uint32_t(x.i), uint32_t(x.j), 0u, 0u, x.u, x.v, 0.0, 0.0};
  }
  return s;
}

std::vector<SurfaceSample> surfaceSamplesAt(const GpuSurface& surface, std::span<const std::pair<double, double>> uv) {
  const auto [ulo, uhi] = surface.parameterRangeU();
  const auto [vlo, vhi] = surface.parameterRangeV();
  const SurfaceModel& m = surface.model();
  const PatchRange r = surface.patches();
  std::vector<SurfaceSample> local(uv.size());
  for (size_t i = 0; i < uv.size(); ++i) {
    const auto [U, V] = uv[i];
    if (!(U >= ulo && U <= uhi) || !(V >= vlo && V <= vhi))
      throw std::out_of_range("evaluateListAt: sample " + std::to_string(i) + " outside the parameter range");
    if (surface.knotVector()) {
      // core/surface.cpp Surface::evaluateAt: knot spans, then local parameters.
      const int ku = m.family.order, kv = m.orderV > 0 ? m.orderV : m.family.order;
      const int a = findKnotSpan(ku, m.knotsU, m.rows, U), b = findKnotSpan(kv, m.knotsV, m.cols, V);
      const double u = (U - m.knotsU[a]) / (m.knotsU[a + 1] - m.knotsU[a]);
      const double v = (V - m.knotsV[b]) / (m.knotsV[b + 1] - m.knotsV[b]);
      local[i] = {a, b, std::clamp(u, 0.0, 1.0), std::clamp(v, 0.0, 1.0)};
      continue;
    }
    // core/surface.cpp Surface::patchOf.
    const int a = std::clamp(int(std::floor(U)), r.u.first, r.u.last);
    const int b = std::clamp(int(std::floor(V)), r.v.first, r.v.last);
    local[i] = {a, b, std::clamp(U - a, 0.0, 1.0), std::clamp(V - b, 0.0, 1.0)};
  }
  return local;
}

std::vector<std::byte> packListSamples(const std::vector<layout::ListSampleD>& samples, Precision p) {
  std::vector<std::byte> bytes;
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

}  // namespace shapespline::gpu
