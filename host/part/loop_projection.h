#pragma once
// A face's loop vertices moved in (U, V) onto their part-wide points. A shared edge vertex is the
// first face's surface point at that face's coedge, so on every other face its (U, V) from the
// coedge's polyline is a little off: along the edge where two faces parametrise the edge
// differently (a circle by angle on a cap, by a rational knot on the cylinder), across it by the
// polylines' sag. Triangulating in (U, V) points that do not map to the vertices' points folds
// triangles near the loops; a few Gauss-Newton steps on |S(U, V) - P|^2 from the coedge's (U, V)
// remove the mismatch down to the faces' own gap at the edge.
#include <shapespline/part/face_evaluator.h>
#include <shapespline/part/face_triangulation.h>

#include <glm/vec3.hpp>

#include <vector>

namespace shapespline::part {

// Each loop vertex's uv moved towards positions[vertex] while that brings the surface point nearer;
// vertices where the partials are (nearly) parallel, as at a pole, keep their uv.
void projectLoopVertices(const Surface& surface, std::vector<std::vector<LoopVertex>>& loops,
                         const std::vector<glm::dvec3>& positions, FaceEvaluator& evaluator);

}  // namespace shapespline::part
