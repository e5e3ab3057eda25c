#pragma once
// A coedge as its face sees it: the run of trim-loop points that lie on one edge, each with the
// edge's own parameter t there (part.json's `coedges`, docs/cad.md). The mesher asks it where, in
// the face's parameters, the edge's point at any t lies: linear between the loop points, which
// import flattened within the trim tolerance of the face's curve on the surface.
#include <shapespline/io/part_manifest.h>

#include <glm/vec2.hpp>

#include <vector>

namespace shapespline::part {

class CoedgePath {
 public:
  // The coedge's points of `loop` (indices start .. start + t.size() - 1, modulo the loop's size).
  CoedgePath(const io::PartCoedge& coedge, const std::vector<glm::dvec2>& loop);

  int edge() const { return edge_; }
  // t runs down the loop's direction when the face uses the edge reversed.
  bool descending() const { return t_.back() < t_.front(); }
  double firstT() const { return t_.front(); }
  double lastT() const { return t_.back(); }
  // The face's (U, V) at edge parameter t (clamped into the coedge's range).
  glm::dvec2 uvAt(double t) const;
  const std::vector<glm::dvec2>& uv() const { return uv_; }

 private:
  int edge_;
  std::vector<double> t_;
  std::vector<glm::dvec2> uv_;
};

}  // namespace shapespline::part
