#pragma once
// From a face's own surface parameters to those of the B-spline OCCT converted it to. For planes
// and B-spline faces they are the same; an analytic surface (cylinder, cone, sphere, torus,
// revolution) is converted to a rational B-spline whose parameter is not the angle, but the map is
// separable: u' depends on u alone and v' on v alone (GeomConvert converts each direction on its
// own). Each direction is found by projecting the face's points along one reference iso-line onto
// the B-spline's matching iso-curve (a table of 33 nodes, each the nearest of 513 points refined by
// Newton; a query starts Newton from the table's interpolation), and the map is checked at a 9 x 9 grid of the face: a conversion that does
// not keep the parameter lines is a ParameterMapError.
#include <shapespline/cad/occt_part.h>

#include <Geom_BSplineSurface.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>

#include <glm/vec2.hpp>

#include <functional>
#include <vector>

namespace shapespline::cad {

// The map does not hold for this face (the conversion is not separable, or not exact enough): the
// face's trims are then projected instead (cad/trim_points.h).
class ParameterMapError : public ConversionError {
 public:
  using ConversionError::ConversionError;
};

class ParameterMap {
 public:
  // `bounds`: the face's (u0, u1, v0, v1) on `source`; `bspline` spans them (GeomConvert of the
  // rectangular trimmed surface).
  ParameterMap(const Handle(Geom_Surface)& source, const double bounds[4], const Handle(Geom_BSplineSurface)& bspline);

  glm::dvec2 operator()(double u, double v) const { return {u_(u), v_(v)}; }

 private:
  // One direction: source parameter s on [s0, s1] to B-spline parameter t on [t0, t1].
  class Axis {
   public:
    Axis() = default;
    Axis(std::function<gp_Pnt(double)> sourcePoint, double s0, double s1, Handle(Geom_Curve) iso, double t0, double t1,
         double scale);
    double operator()(double s) const;

   private:
    double newton(const gp_Pnt& target, double guess) const;  // the nearest point of the iso-curve
    std::function<gp_Pnt(double)> sourcePoint_;
    Handle(Geom_Curve) iso_;
    double s0_ = 0, s1_ = 0, t0_ = 0, t1_ = 0, scale_ = 1;
    std::vector<double> table_;  // t at s0 + (s1 - s0) i / (n - 1)
    bool identity_ = true;
  };

  Axis u_, v_;
};

}  // namespace shapespline::cad
