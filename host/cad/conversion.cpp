// Faces and edges as shapespline `bspline` models: OCCT's GeomConvert gives the (rational)
// B-spline, restricted to the face's parameter bounds or the edge's range; periodic knot vectors
// are unrolled into open ones; the model is checked by core's validateSurface / validateCurve.
#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/parameter_map.h>
#include <shapespline/cad/trim_loops.h>
#include <shapespline/cad/trim_points.h>
#include <shapespline/core/validate.h>

#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GeomConvert.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TColStd_Array1OfReal.hxx>

#include <algorithm>
#include <string>

namespace shapespline::cad {
namespace {

constexpr int kMaxOrder = 10;  // docs/format.md: bspline orders 2..10

std::vector<double> flatKnots(int poles, int degree, const std::function<void(TColStd_Array1OfReal&)>& fill) {
  TColStd_Array1OfReal knots(1, poles + degree + 1);
  fill(knots);
  return std::vector<double>(&knots.First(), &knots.First() + knots.Length());
}

void checkOrder(int order, const char* what) {
  if (order > kMaxOrder)
    throw ConversionError(std::string(what) + " degree " + std::to_string(order - 1) + " is above the largest order " +
                          std::to_string(kMaxOrder) + " a bspline model takes");
}

std::string failureText(const Standard_Failure& e) {
  const char* text = e.GetMessageString();
  return std::string(e.DynamicType()->Name()) + (text && *text ? std::string(": ") + text : "");
}

// The period of a direction of the surface, or of the periodic surface it cuts; 0 when none.
double periodOf(const Handle(Geom_Surface)& surface, int direction) {
  Handle(Geom_Surface) periodic = surface;
  if (const Handle(Geom_RectangularTrimmedSurface) cut = Handle(Geom_RectangularTrimmedSurface)::DownCast(surface))
    periodic = cut->BasisSurface();
  if (direction == 0) return periodic->IsUPeriodic() ? periodic->UPeriod() : 0.0;
  return periodic->IsVPeriodic() ? periodic->VPeriod() : 0.0;
}

// The bounds of a face's p-curves can stick out of its surface by rounding or the edges'
// tolerance (a sphere's v beyond pi/2, a torus' u over a period after an IGES round trip), which
// GeomConvert refuses: clamp them to the surface's range, and a periodic direction to one period.
// A whole period is cut a hair short: GeomConvert makes a whole period a periodic B-spline whose
// parameters start elsewhere on the circle (a cylinder's seam moved by 2 degrees), and the face's
// loops would cross the B-spline's ends. The hair (1e-9 of the period) is far inside the clamping
// of trim points (docs/cad.md).
void keepInsideSurface(const Handle(Geom_Surface)& surface, double bounds[4]) {
  double range[4];
  surface->Bounds(range[0], range[1], range[2], range[3]);
  const bool periodic[2] = {surface->IsUPeriodic(), surface->IsVPeriodic()};
  for (int d = 0; d < 2; ++d) {
    double& lo = bounds[2 * d];
    double& hi = bounds[2 * d + 1];
    if (!periodic[d]) {
      lo = std::max(lo, range[2 * d]);
      hi = std::min(hi, range[2 * d + 1]);
    }
    if (const double period = periodOf(surface, d); period > 0.0) hi = std::min(hi, lo + period * (1.0 - 1e-9));
  }
}

// The distance within which OCCT holds the face's geometry: the largest of the face's tolerance and
// its edges' (a valid shape's edges lie on the face within their own tolerance).
double faceTolerance(const TopoDS_Face& face) {
  double tolerance = BRep_Tool::Tolerance(face);
  for (TopExp_Explorer edges(face, TopAbs_EDGE); edges.More(); edges.Next())
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Edge(edges.Current())));
  return tolerance;
}

}  // namespace

ConvertedFace convertFace(const TopoDS_Face& face, double relativeTolerance) {
  ConvertedFace out;
  try {
    out.source = BRep_Tool::Surface(face);  // a located copy when the face has a placement
    if (out.source.IsNull()) throw ConversionError("the face has no surface");
    out.surfaceType = out.source->DynamicType()->Name();
    out.reversed = face.Orientation() == TopAbs_REVERSED;
    BRepTools::UVBounds(face, out.bounds[0], out.bounds[1], out.bounds[2], out.bounds[3]);
    keepInsideSurface(out.source, out.bounds);
    if (!(out.bounds[1] > out.bounds[0] && out.bounds[3] > out.bounds[2]))
      throw ConversionError("the face's parameter bounds are empty");
    Handle(Geom_RectangularTrimmedSurface) restricted =
        new Geom_RectangularTrimmedSurface(out.source, out.bounds[0], out.bounds[1], out.bounds[2], out.bounds[3]);
    out.bspline = GeomConvert::SurfaceToBSplineSurface(restricted);
    if (out.bspline->IsUPeriodic()) out.bspline->SetUNotPeriodic();
    if (out.bspline->IsVPeriodic()) out.bspline->SetVNotPeriodic();
  } catch (const Standard_Failure& e) {
    throw ConversionError("Open CASCADE could not convert the " + out.surfaceType + " to a B-spline (" +
                          failureText(e) + ")");
  }
  const Handle(Geom_BSplineSurface)& s = out.bspline;
  SurfaceModel& m = out.model;
  m.family.construction = Construction::BSpline;
  m.family.order = s->UDegree() + 1;
  m.orderV = s->VDegree() + 1;
  checkOrder(m.family.order, "u");
  checkOrder(m.orderV, "v");
  m.rows = s->NbUPoles();
  m.cols = s->NbVPoles();
  m.points.reserve(static_cast<size_t>(m.rows) * m.cols);
  const bool rational = s->IsURational() || s->IsVRational();
  for (int i = 1; i <= m.rows; ++i)
    for (int j = 1; j <= m.cols; ++j) {
      const gp_Pnt p = s->Pole(i, j);
      m.points.emplace_back(p.X(), p.Y(), p.Z());
      if (rational) m.weights.push_back(s->Weight(i, j));
    }
  m.knotsU = flatKnots(m.rows, s->UDegree(), [&](TColStd_Array1OfReal& k) { s->UKnotSequence(k); });
  m.knotsV = flatKnots(m.cols, s->VDegree(), [&](TColStd_Array1OfReal& k) { s->VKnotSequence(k); });
  try {
    double a0, a1, b0, b1;
    s->Bounds(a0, a1, b0, b1);
    const double trimTolerance = relativeTolerance * std::max(a1 - a0, b1 - b0);
    try {
      const ParameterMap map(out.source, out.bounds, s);
      TrimPoints points(out.source, s, &map, trimTolerance);
      FaceTrim trim = faceTrimLoops(face, points, trimTolerance);
      m.trim = std::move(trim.trim);
      out.coedges = std::move(trim.coedges);
      out.clampedTrimPoints = points.clamped();
    } catch (const ParameterMapError& e) {
      // Not separable (or not exact enough for the map's check): project the face's points instead,
      // if the B-spline is the face within the tolerance OCCT gives the face and its edges.
      out.mapFailure = e.what();
      const double tolerance = faceTolerance(face);
      const double gap = surfaceGap(out.source, out.bounds, s);
      if (gap > tolerance)
        throw ConversionError("the parameter map failed (" + out.mapFailure + ") and the converted B-spline is " +
                              std::to_string(gap) + " from the face, more than its tolerance " + std::to_string(tolerance));
      TrimPoints points(out.source, s, nullptr, trimTolerance);
      FaceTrim trim = faceTrimLoops(face, points, trimTolerance);
      m.trim = std::move(trim.trim);
      out.coedges = std::move(trim.coedges);
      out.clampedTrimPoints = points.clamped();
      out.projectionGap = std::max(gap, points.largestGap());
    }
  } catch (const Standard_Failure& e) {
    throw ConversionError("Open CASCADE failed on the face's trimming loops (" + failureText(e) + ")");
  }
  try {
    validateSurface(m);
  } catch (const ModelError& e) {
    throw ConversionError(std::string("the converted surface is not a valid bspline model: ") + e.what());
  }
  return out;
}

ConvertedEdge convertEdge(const TopoDS_Edge& edge) {
  ConvertedEdge out;
  std::string type = "(none)";
  try {
    double first = 0.0, last = 0.0;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, first, last);  // located copy
    if (curve.IsNull()) throw ConversionError("the edge has no 3-D curve");
    out.curveType = type = curve->DynamicType()->Name();
    Handle(Geom_TrimmedCurve) restricted = new Geom_TrimmedCurve(curve, first, last);
    out.bspline = GeomConvert::CurveToBSplineCurve(restricted);
    if (out.bspline->IsPeriodic()) out.bspline->SetNotPeriodic();
  } catch (const Standard_Failure& e) {
    throw ConversionError("Open CASCADE could not convert the " + type + " to a B-spline (" + failureText(e) + ")");
  }
  const Handle(Geom_BSplineCurve)& c = out.bspline;
  CurveModel& m = out.model;
  m.family.construction = Construction::BSpline;
  m.family.order = c->Degree() + 1;
  checkOrder(m.family.order, "the edge's");
  m.dimension = 3;
  for (int i = 1; i <= c->NbPoles(); ++i) {
    const gp_Pnt p = c->Pole(i);
    m.points.emplace_back(p.X(), p.Y(), p.Z());
    if (c->IsRational()) m.weights.push_back(c->Weight(i));
  }
  m.knots = flatKnots(c->NbPoles(), c->Degree(), [&](TColStd_Array1OfReal& k) { c->KnotSequence(k); });
  try {
    validateCurve(m);
  } catch (const ModelError& e) {
    throw ConversionError(std::string("the converted curve is not a valid bspline model: ") + e.what());
  }
  return out;
}

}  // namespace shapespline::cad
