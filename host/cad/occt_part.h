#pragma once
// The Open CASCADE side of the importer (internal: tests use it to compare against OCCT): reading a
// part, and converting one face or edge into a shapespline model beside the OCCT B-spline it came
// from.
#include <shapespline/core/model.h>

#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_Surface.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapespline::cad {

struct PartShape {
  TopoDS_Shape shape;  // assemblies' placements applied (STEPControl_Reader::OneShape)
  std::string format;  // "step" or "iges"
  std::string units;   // the length unit OCCT converted the part to ("mm")
};

// Registers OCCT's STEP and IGES controllers (their process-wide parameter tables), once. OCCT
// never frees those tables, so under LeakSanitizer the registration runs with leak detection
// paused: a one-time allocation inside OCCT, not a leak to report. Every reader and writer of
// parts in this project (readPart, the tests' part writers) calls it first.
void initOcctControllers();

// Reads a STEP (.step/.stp) or IGES (.iges/.igs) file. Throws CadError for a missing, empty,
// oversized or unreadable file, or a part without faces and edges.
PartShape readPart(const std::filesystem::path& path, std::uint64_t maxFileBytes);

// Why a face or an edge was not converted (listed in part.json, the rest of the part goes on).
class ConversionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One edge's run of a face's trim loop (cad/trim_loops.h, docs/cad.md "Coedges"): the loop points
// start, start + 1, ..., start + t.size() - 1 (modulo the loop's point count) lie on `edge`, point
// start + j at the edge's own parameter t[j] (the one its p-curve and 3-D curve share). Consecutive
// coedges share a point; the last one of a closed loop ends at point 0. t runs backwards where the
// wire uses the edge reversed.
struct TrimCoedge {
  TopoDS_Edge edge;
  int start = 0;
  std::vector<double> t;
};

struct ConvertedFace {
  SurfaceModel model;                  // bspline with knots, weights when rational, trim loops
  Handle(Geom_BSplineSurface) bspline; // what `model` was made from (OCCT evaluates it the same)
  Handle(Geom_Surface) source;         // the face's own surface, located
  double bounds[4] = {0, 0, 0, 0};     // the face's (u0, u1, v0, v1) on `source`
  std::string surfaceType;             // "Geom_CylindricalSurface", ...
  bool reversed = false;               // the face's normal is -(du x dv) of the model
  int clampedTrimPoints = 0;           // trim points clamped into the knot domain (cad/trim_points.h)
  std::string mapFailure;              // why the ParameterMap failed; empty when it held
  double projectionGap = 0.0;          // with projected trims: the largest face-to-B-spline distance
  std::vector<std::vector<TrimCoedge>> coedges;  // per loop of model.trim: the edges its points lie on
};

struct ConvertedEdge {
  CurveModel model;
  Handle(Geom_BSplineCurve) bspline;
  std::string curveType;
};

// `relativeTolerance`: ImportOptions::trimTolerance. Throws ConversionError.
ConvertedFace convertFace(const TopoDS_Face& face, double relativeTolerance);
ConvertedEdge convertEdge(const TopoDS_Edge& edge);

}  // namespace shapespline::cad
