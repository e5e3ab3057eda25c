#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/trim_points.h>

#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>

#include <algorithm>
#include <string>

namespace shapespline::cad {
namespace {

// How far a clamped trim point's surface point may lie from the face's: twice the edge's tolerance,
// so that it stays within three times that tolerance of the edge's 3-D curve (the p-curve's point
// is itself within one tolerance of it), the order of accuracy OCCT holds the edge to.
constexpr double kEdgeToleranceMultiple = 2.0;

std::string text(double x) {
  char s[32];
  std::snprintf(s, sizeof s, "%.6g", x);
  return s;
}

}  // namespace

TrimPoints::TrimPoints(const Handle(Geom_Surface)& source, const Handle(Geom_BSplineSurface)& bspline,
                       const ParameterMap* map, double trimTolerance)
    : source_(source), bspline_(bspline), map_(map), trimTolerance_(trimTolerance) {
  bspline_->Bounds(a0_, a1_, b0_, b1_);
  if (!map_) projector_ = new ShapeAnalysis_Surface(bspline_);
}

glm::dvec2 TrimPoints::operator()(const TopoDS_Edge& edge, double u, double v) {
  const double tolerance = BRep_Tool::Tolerance(edge);
  // Through the map and within the trim tolerance of the domain (nearly every point): valid as it
  // is (core's checkTrim), and its point is the face's (the map's own check): the face's point is
  // not needed.
  if (map_) {
    const glm::dvec2 q = (*map_)(u, v);
    return inDomain(q) ? q : clampIntoDomain(q, source_->Value(u, v), tolerance);
  }
  const gp_Pnt point = source_->Value(u, v);
  return clampIntoDomain(project(point, tolerance), point, tolerance);
}

bool TrimPoints::inDomain(glm::dvec2 q) const {
  const double slack = trimTolerance_;
  return q.x >= a0_ - slack && q.x <= a1_ + slack && q.y >= b0_ - slack && q.y <= b1_ + slack;
}

glm::dvec2 TrimPoints::project(const gp_Pnt& point, double tolerance) {
  // Start from the previous point's parameters (the points of a loop come in order); where that
  // lands off the face, search the whole surface, then OCCT's exhaustive projection.
  gp_Pnt2d uv = hasPrevious_ ? projector_->NextValueOfUV(previous_, point, tolerance) : projector_->ValueOfUV(point, tolerance);
  if (projector_->Gap() > tolerance) uv = projector_->ValueOfUV(point, tolerance);
  if (projector_->Gap() > tolerance) {
    GeomAPI_ProjectPointOnSurf exhaustive(point, bspline_);
    if (exhaustive.NbPoints() > 0) {
      double u = 0, v = 0;
      exhaustive.LowerDistanceParameters(u, v);
      uv.SetCoord(u, v);
    }
  }
  previous_ = uv;
  hasPrevious_ = true;
  return {uv.X(), uv.Y()};
}

glm::dvec2 TrimPoints::clampIntoDomain(glm::dvec2 q, const gp_Pnt& point, double edgeTolerance) {
  // Within the trim tolerance of the domain: left unchanged, but a projected point is measured.
  const bool inside = inDomain(q);
  const glm::dvec2 kept = inside ? q : glm::dvec2(std::clamp(q.x, a0_, a1_), std::clamp(q.y, b0_, b1_));
  const double gap = bspline_->Value(kept.x, kept.y).Distance(point);
  const double allowed = kEdgeToleranceMultiple * edgeTolerance;
  if (gap > allowed)
    throw ConversionError("trim point (" + text(q.x) + ", " + text(q.y) + ") of the knot domain [" + text(a0_) + ", " +
                          text(a1_) + "] x [" + text(b0_) + ", " + text(b1_) + "]" + (map_ ? "" : ", projected") +
                          ": the surface at (" + text(kept.x) + ", " + text(kept.y) + ") is " + text(gap) +
                          " from the face's point, more than " + text(kEdgeToleranceMultiple) +
                          " x the edge's tolerance " + text(edgeTolerance));
  largestGap_ = std::max(largestGap_, gap);
  if (!inside) ++clamped_;
  return kept;
}

double surfaceGap(const Handle(Geom_Surface)& source, const double bounds[4], const Handle(Geom_BSplineSurface)& bspline) {
  ShapeAnalysis_Surface projector(bspline);
  double worst = 0.0;
  constexpr int kGrid = 9;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const double u = bounds[0] + (bounds[1] - bounds[0]) * i / (kGrid - 1);
      const double v = bounds[2] + (bounds[3] - bounds[2]) * j / (kGrid - 1);
      const gp_Pnt p = source->Value(u, v);
      projector.ValueOfUV(p, 1e-7);
      worst = std::max(worst, projector.Gap());
    }
  return worst;
}

}  // namespace shapespline::cad
