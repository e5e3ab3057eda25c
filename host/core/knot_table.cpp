#include <shapespline/core/knot_table.h>

#include <shapespline/core/bspline.h>

#include <algorithm>

namespace shapespline {

namespace {

// The continuity order p - m of the spline at knot t_k, m its multiplicity (equal knots are
// neighbours in a non-decreasing knot vector).
int continuity(std::span<const double> knots, int order, int k) {
  const double t = knots[static_cast<size_t>(k)];
  size_t first = static_cast<size_t>(k), end = first + 1;
  while (first > 0 && knots[first - 1] == t) --first;
  while (end < knots.size() && knots[end] == t) ++end;
  return order - 1 - static_cast<int>(end - first);
}

}  // namespace

void tabulateKnotInterval(int order, std::span<const double> knots, int pointCount, int interval, int samples,
                          KnotTable& out) {
  const size_t S = static_cast<size_t>(samples);
  out.order = order;
  out.samples = samples;
  out.interval = interval;
  out.scaled = false;
  out.span.resize(S);
  for (auto& b : out.b) b.assign(static_cast<size_t>(order) * S, 0.0);
  const double t0 = knots[static_cast<size_t>(interval)], t1 = knots[static_cast<size_t>(interval) + 1];
  const double lo = knots[static_cast<size_t>(order) - 1], hi = knots[static_cast<size_t>(pointCount)];
  const int derivs = std::min(2, order - 1);
  for (size_t a = 0; a < S; ++a) {
    const double s = samples > 1 ? static_cast<double>(a) / static_cast<double>(samples - 1) : 0.0;
    const double x = t0 + s * (t1 - t0);
    int span = findKnotSpan(order, knots, pointCount, x);
    // On a knot where the spline is C^derivs, the interval's own polynomial gives the same values
    // (its limit from the left): keeping one span for the whole row saves the samplers a second
    // contraction of the net per row. Where a derivative jumps, the span findKnotSpan picks stays.
    if (span != interval && continuity(knots, order, span) >= derivs) span = interval;
    double d[kMaxBasisCount][kMaxBasisCount];
    if (bsplineBasisDerivsScaled(order, knots, span, std::clamp(x, lo, hi), derivs, d) != 0) out.scaled = true;
    out.span[a] = span;
    for (int k = 0; k <= derivs; ++k)
      for (int r = 0; r < order; ++r) out.b[k][static_cast<size_t>(r) * S + a] = d[k][r];
  }
}

KnotTables::KnotTables(int order, std::span<const double> knots, int pointCount, int samples, size_t maxBytes)
    : order_(order), pointCount_(pointCount), samples_(samples), knots_(knots) {
  const size_t intervals = static_cast<size_t>(pointCount) + 1;  // indices up to n; empty ones unused
  const size_t bytes = intervals * static_cast<size_t>(samples) * (3 * static_cast<size_t>(order) + 1) * sizeof(double);
  if (bytes > maxBytes) return;
  all_.resize(intervals);
  for (int i = order - 1; i < pointCount; ++i)
    if (knots[static_cast<size_t>(i)] < knots[static_cast<size_t>(i) + 1])
      tabulateKnotInterval(order, knots, pointCount, i, samples, all_[static_cast<size_t>(i)]);
}

const KnotTable& KnotTables::of(int interval, KnotTable& scratch) const {
  if (!all_.empty()) return all_[static_cast<size_t>(interval)];
  if (scratch.interval != interval || scratch.samples != samples_ || scratch.order != order_)
    tabulateKnotInterval(order_, knots_, pointCount_, interval, samples_, scratch);
  return scratch;
}

}  // namespace shapespline
