#pragma once
// A constrained Delaunay triangulation of points in the plane, the domain bounded by closed
// constraint loops (a face's trim loops in its parameters, docs/cad.md "Meshing a part"). Exact
// orientation and in-circle predicates (floating-point filter, exact expansion arithmetic where the
// filter cannot decide), so the result never depends on rounding: no inverted or zero-area
// triangle, every constraint segment an edge of the result.
//
// Triangles are kept inside the loops by the even-odd rule (a triangle is inside when a path from it
// to the outside crosses constraint segments an odd number of times), so holes come out as holes
// whatever the loops' orientations.
#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapespline::part {

// Constraint segments that cross, or a constraint that passes through a point that is not its end:
// `first` and `second` are the indices of the two segments (a point on a segment that ends another
// segment, as where two collinear segments overlap, names that segment; any other point on a segment
// makes `second` -1 - the point's index).
class CrossingConstraints : public std::runtime_error {
 public:
  CrossingConstraints(int first, int second, const std::string& what)
      : std::runtime_error(what), first_(first), second_(second) {}
  int first() const { return first_; }
  int second() const { return second_; }

 private:
  int first_, second_;
};

class ConstrainedDelaunay {
 public:
  // Triangulates `points` with every segment of `constraints` (indices into `points`) an edge.
  // Points at exactly the same coordinates are one vertex (`vertexOf` says which). Throws
  // CrossingConstraints as above, std::invalid_argument for a non-finite coordinate or an index
  // out of range.
  ConstrainedDelaunay(std::vector<glm::dvec2> points, const std::vector<std::array<int, 2>>& constraints);

  // Adds a point (a refinement's Steiner point) and restores the constrained Delaunay property
  // around it; returns its index. A point on a constraint segment splits that segment. A point
  // outside the domain is accepted; its triangles are simply not among `triangles()`.
  int insert(glm::dvec2 point);

  // The triangles inside the loops, counter-clockwise, as indices into the points given and
  // inserted (duplicates mapped to the first of them).
  std::vector<std::array<int, 3>> triangles() const;

  // The point given at `index` is the vertex `vertexOf(index)` (itself unless a duplicate).
  int vertexOf(int index) const;

  const std::vector<glm::dvec2>& points() const { return points_; }

 private:
  struct Impl;
  std::vector<glm::dvec2> points_;
  std::shared_ptr<Impl> impl_;
};

}  // namespace shapespline::part
