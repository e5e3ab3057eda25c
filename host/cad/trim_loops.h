#pragma once
// A face's wires as closed polylines in its B-spline's parameters (docs/format.md "Trim"): each
// edge's curve on the face (its p-curve), taken in the wire's order and the edge's orientation,
// taken to the model's parameters by TrimPoints (the ParameterMap, or the projection) and subdivided until every piece is within `tolerance` of the
// mapped p-curve (checked at the middle and quarter points). The outer wire becomes the first loop,
// counter-clockwise; the others clockwise. Each loop also says which edge each of its points lies
// on, and where (its coedges, docs/cad.md "Coedges"), so a mesher can share an edge's points
// between the faces that use it.
#include <shapespline/cad/trim_points.h>
#include <shapespline/core/model.h>

#include <TopoDS_Face.hxx>

#include <vector>

namespace shapespline::cad {

// The loops and, per loop, its coedges (TrimCoedge, cad/occt_part.h) in the loop's final order.
struct FaceTrim {
  TrimLoops trim;
  std::vector<std::vector<TrimCoedge>> coedges;  // per loop of `trim`, in the loop's order
};

// The enclosed area of a closed polyline, positive when counter-clockwise (shoelace).
double signedArea(const std::vector<glm::dvec2>& loop);

FaceTrim faceTrimLoops(const TopoDS_Face& face, TrimPoints& points, double tolerance);

}  // namespace shapespline::cad
