#pragma once
// Where a point of a face's trim (a point of an edge's p-curve, in the face's own surface
// parameters) lands in the parameters of the B-spline the face was converted to, with the two
// rules that keep real parts' faces (docs/cad.md "Trim points at the edge of the domain" and
// "Faces whose parameter map fails"):
//   * a point further than trim.tolerance outside the knot domain is clamped onto it when the
//     B-spline's point there lies within twice the edge's own OCCT tolerance
//     (BRep_Tool::Tolerance) of the face's point;
//   * when the separable ParameterMap fails, the face's point is projected onto the B-spline
//     (ShapeAnalysis_Surface), held to the same tolerance.
// Anything further is a ConversionError that names the point, the distance and the tolerance.
#include <shapespline/cad/parameter_map.h>

#include <Geom_BSplineSurface.hxx>
#include <Geom_Surface.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <TopoDS_Edge.hxx>

#include <glm/vec2.hpp>

namespace shapespline::cad {

class TrimPoints {
 public:
  // `map`: null for the projection (the map failed); otherwise the map is used and not copied.
  // `trimTolerance`: the model's trim.tolerance (a point that close to the domain is left as is).
  TrimPoints(const Handle(Geom_Surface)& source, const Handle(Geom_BSplineSurface)& bspline, const ParameterMap* map,
             double trimTolerance);

  // The model's parameters of the face's point (u, v) on `edge`'s p-curve.
  glm::dvec2 operator()(const TopoDS_Edge& edge, double u, double v);

  // The largest distance from the face's point to the model's over the points taken so far.
  double largestGap() const { return largestGap_; }
  // How many points were clamped into the knot domain (those beyond trim.tolerance).
  int clamped() const { return clamped_; }

 private:
  glm::dvec2 project(const gp_Pnt& point, double tolerance);
  glm::dvec2 clampIntoDomain(glm::dvec2 q, const gp_Pnt& point, double tolerance);
  bool inDomain(glm::dvec2 q) const;  // within the trim tolerance of the knot domain

  Handle(Geom_Surface) source_;
  Handle(Geom_BSplineSurface) bspline_;
  const ParameterMap* map_;
  double trimTolerance_;
  Handle(ShapeAnalysis_Surface) projector_;  // only for the projection
  gp_Pnt2d previous_;
  bool hasPrevious_ = false;
  double a0_ = 0, a1_ = 0, b0_ = 0, b1_ = 0;  // the knot domain
  double largestGap_ = 0.0;
  int clamped_ = 0;
};

// The largest distance from the face's own surface to the B-spline at a 9 x 9 grid of the face's
// parameter box (each point projected onto the B-spline): how far the conversion is from the face
// where no parameter map ties the two.
double surfaceGap(const Handle(Geom_Surface)& source, const double bounds[4], const Handle(Geom_BSplineSurface)& bspline);

}  // namespace shapespline::cad
