#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/parameter_map.h>

#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace shapespline::cad {
namespace {

constexpr int kTableNodes = 33;
constexpr int kCheckGrid = 9;
constexpr int kSearchPoints = 512;
// The map's accuracy, relative to the B-spline's size: Newton converges to rounding, so anything
// near this bound means the two parameterizations are not separable.
constexpr double kMapTolerance = 1e-9;

double lerp(double a, double b, double t) { return a + (b - a) * t; }

// Length of the polyline through 17 points of a parameter line, to tell a degenerate boundary (a
// sphere's pole, a cone's apex) from a usable one.
double isoLength(const std::function<gp_Pnt(double)>& point, double s0, double s1) {
  double length = 0.0;
  gp_Pnt previous = point(s0);
  for (int i = 1; i <= 16; ++i) {
    const gp_Pnt p = point(lerp(s0, s1, i / 16.0));
    length += p.Distance(previous);
    previous = p;
  }
  return length;
}

double poleBoxDiagonal(const Handle(Geom_BSplineSurface)& s) {
  gp_XYZ lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
  for (int i = 1; i <= s->NbUPoles(); ++i)
    for (int j = 1; j <= s->NbVPoles(); ++j) {
      const gp_XYZ p = s->Pole(i, j).XYZ();
      for (int d = 1; d <= 3; ++d) {
        lo.SetCoord(d, std::min(lo.Coord(d), p.Coord(d)));
        hi.SetCoord(d, std::max(hi.Coord(d), p.Coord(d)));
      }
    }
  return std::max((hi - lo).Modulus(), 1e-300);
}

}  // namespace

ParameterMap::Axis::Axis(std::function<gp_Pnt(double)> sourcePoint, double s0, double s1, Handle(Geom_Curve) iso,
                         double t0, double t1, double scale)
    : sourcePoint_(std::move(sourcePoint)), iso_(std::move(iso)), s0_(s0), s1_(s1), t0_(t0), t1_(t1), scale_(scale),
      identity_(false) {
  table_.resize(kTableNodes);
  table_.front() = t0;
  table_.back() = t1;
  // The iso-curve's search points, evaluated once for every node.
  std::vector<gp_Pnt> searched(kSearchPoints + 1);
  for (int k = 0; k <= kSearchPoints; ++k) searched[static_cast<size_t>(k)] = iso_->Value(lerp(t0, t1, double(k) / kSearchPoints));
  for (int i = 1; i + 1 < kTableNodes; ++i) {
    // The nearest of kSearchPoints points of the iso-curve (between equally near ones, the two ends
    // of a closed iso-curve, the one nearest the linear guess); operator() refines it by Newton.
    const double guess = lerp(t0, t1, double(i) / (kTableNodes - 1));
    const gp_Pnt target = sourcePoint_(lerp(s0, s1, double(i) / (kTableNodes - 1)));
    double best = guess, bestDistance = 1e300;
    for (int k = 0; k <= kSearchPoints; ++k) {
      const double t = lerp(t0, t1, double(k) / kSearchPoints);
      const double d = searched[static_cast<size_t>(k)].Distance(target);
      if (d < bestDistance - kMapTolerance * scale_ ||
          (d < bestDistance + kMapTolerance * scale_ && std::abs(t - guess) < std::abs(best - guess))) {
        best = t;
        bestDistance = std::min(bestDistance, d);
      }
    }
    table_[static_cast<size_t>(i)] = newton(target, best);
  }
  for (int i = 1; i < kTableNodes; ++i)
    if (!(table_[static_cast<size_t>(i)] > table_[static_cast<size_t>(i - 1)]))
      throw ParameterMapError("the converted B-spline's parameter does not grow with the face's");
}

double ParameterMap::Axis::operator()(double s) const {
  if (identity_) return s;
  if (s <= s0_) return t0_;
  if (s >= s1_) return t1_;
  const double x = (s - s0_) / (s1_ - s0_) * (kTableNodes - 1);
  const int i = std::min(static_cast<int>(x), kTableNodes - 2);
  const gp_Pnt target = sourcePoint_(s);
  const double t = newton(target, lerp(table_[static_cast<size_t>(i)], table_[static_cast<size_t>(i + 1)], x - i));
  if (iso_->Value(t).Distance(target) > 1e3 * kMapTolerance * scale_)
    throw ParameterMapError("a face point is not on its converted B-spline (the parameter map failed)");
  return t;
}

double ParameterMap::Axis::newton(const gp_Pnt& target, double t) const {
  gp_Pnt c;
  gp_Vec d1, d2;
  for (int iteration = 0; iteration < 40; ++iteration) {  // Newton on |C(t) - target|^2
    iso_->D2(t, c, d1, d2);
    const gp_Vec r(target, c);
    const double h = d1.SquareMagnitude() + r.Dot(d2);
    if (!(h > 0.0)) break;
    const double step = -r.Dot(d1) / h;
    t = std::clamp(t + step, t0_, t1_);
    if (std::abs(step) <= 1e-16 * (t1_ - t0_)) break;
  }
  return t;
}

ParameterMap::ParameterMap(const Handle(Geom_Surface)& source, const double bounds[4],
                           const Handle(Geom_BSplineSurface)& bspline) {
  const double u0 = bounds[0], u1 = bounds[1], v0 = bounds[2], v1 = bounds[3];
  double a0, a1, b0, b1;  // the B-spline's domain
  bspline->Bounds(a0, a1, b0, b1);
  const double scale = poleBoxDiagonal(bspline);

  auto deviation = [&](auto&& mapU, auto&& mapV) {
    double worst = 0.0;
    for (int i = 0; i < kCheckGrid; ++i)
      for (int j = 0; j < kCheckGrid; ++j) {
        const double u = lerp(u0, u1, double(i) / (kCheckGrid - 1)), v = lerp(v0, v1, double(j) / (kCheckGrid - 1));
        worst = std::max(worst, source->Value(u, v).Distance(bspline->Value(mapU(u), mapV(v))));
      }
    return worst;
  };
  auto same = [](double x) { return x; };
  const double span = std::max({std::abs(u1 - u0), std::abs(v1 - v0), 1.0});
  const bool sameDomain = std::abs(a0 - u0) <= 1e-12 * span && std::abs(a1 - u1) <= 1e-12 * span &&
                          std::abs(b0 - v0) <= 1e-12 * span && std::abs(b1 - v1) <= 1e-12 * span;
  if (sameDomain && deviation(same, same) <= kMapTolerance * scale) return;  // planes, B-spline faces

  auto along = [&](bool alongU, double fixed) {  // a parameter line of the face's own surface
    return std::function<gp_Pnt(double)>([=](double s) { return alongU ? source->Value(s, fixed) : source->Value(fixed, s); });
  };
  const double atU0 = isoLength(along(false, u0), v0, v1), atU1 = isoLength(along(false, u1), v0, v1);
  const double atV0 = isoLength(along(true, v0), u0, u1), atV1 = isoLength(along(true, v1), u0, u1);
  const double degenerate = 1e-7 * scale;
  if (std::max(atU0, atU1) > degenerate) {
    // v first, along the longer u boundary (a boundary maps onto the B-spline's boundary), then u
    // along the middle v line.
    const bool first = atU0 >= atU1;
    v_ = Axis(along(false, first ? u0 : u1), v0, v1, bspline->UIso(first ? a0 : a1), b0, b1, scale);
    const double vMiddle = 0.5 * (v0 + v1);
    u_ = Axis(along(true, vMiddle), u0, u1, bspline->VIso(v_(vMiddle)), a0, a1, scale);
  } else if (std::max(atV0, atV1) > degenerate) {
    const bool first = atV0 >= atV1;
    u_ = Axis(along(true, first ? v0 : v1), u0, u1, bspline->VIso(first ? b0 : b1), a0, a1, scale);
    const double uMiddle = 0.5 * (u0 + u1);
    v_ = Axis(along(false, uMiddle), v0, v1, bspline->UIso(u_(uMiddle)), b0, b1, scale);
  } else {
    throw ParameterMapError("every boundary of the face is degenerate");
  }
  const double worst = deviation([&](double u) { return u_(u); }, [&](double v) { return v_(v); });
  if (worst > kMapTolerance * scale)
    throw ParameterMapError("the converted B-spline does not keep the face's parameter lines (deviation " +
                          std::to_string(worst / scale) + " of the size)");
}

}  // namespace shapespline::cad
