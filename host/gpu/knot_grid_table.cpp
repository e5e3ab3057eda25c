#include <shapespline/gpu/knot_grid_table.h>

#include <shapespline/core/bspline.h>
#include <shapespline/core/knot_table.h>

#include <span>

namespace shapespline::gpu {
namespace {

// Appends one direction's entries; false when an interval needs scaled derivatives or the table
// would grow past maxValues.
bool appendDirection(int order, std::span<const double> knots, int pointCount, int samples, size_t maxValues,
                     std::vector<double>& out) {
  const size_t stride = 1 + 3 * static_cast<size_t>(order);
  size_t intervals = 0;
  for (int i = order - 1; i < pointCount; ++i) intervals += knots[static_cast<size_t>(i)] < knots[static_cast<size_t>(i) + 1];
  if (intervals * static_cast<size_t>(samples) * stride > maxValues - out.size()) return false;
  out.reserve(out.size() + intervals * static_cast<size_t>(samples) * stride);
  KnotTable t;
  for (int i = order - 1; i < pointCount; ++i) {
    if (!(knots[static_cast<size_t>(i)] < knots[static_cast<size_t>(i) + 1])) continue;
    tabulateKnotInterval(order, knots, pointCount, i, samples, t);
    if (t.scaled) return false;
    for (int a = 0; a < samples; ++a) {
      out.push_back(static_cast<double>(t.span[static_cast<size_t>(a)]));
      for (int d = 0; d < 3; ++d)
        for (int r = 0; r < order; ++r) out.push_back(t.row(d, r)[a]);
    }
  }
  return true;
}

}  // namespace

std::optional<KnotGridTable> knotGridTable(const Curve& curve, int samples, size_t maxValues) {
  const BSplineCurveData& d = curve.knotData();
  KnotGridTable t;
  if (!appendDirection(d.order, d.knots, static_cast<int>(d.points.size()), samples, maxValues, t.values))
    return std::nullopt;
  return t;
}

std::optional<KnotGridTable> knotGridTable(const Surface& surface, int samplesU, int samplesV, size_t maxValues) {
  const BSplineSurfaceData& d = surface.knotData();
  KnotGridTable t;
  if (!appendDirection(d.orderU, d.knotsU, d.rows, samplesU, maxValues, t.values)) return std::nullopt;
  t.offsetV = static_cast<uint32_t>(t.values.size());
  if (!appendDirection(d.orderV, d.knotsV, d.cols, samplesV, maxValues, t.values)) return std::nullopt;
  return t;
}

}  // namespace shapespline::gpu
