#pragma once
// Which side of a face's trimming loops a parameter point lies on (docs/format.md "Trim"): inside
// by the even-odd rule over all loops (a ray towards +u crosses the loops an odd number of times),
// and a point within the loops' tolerance of an edge counts as inside, so a sample on the boundary
// is kept whichever way rounding puts it. Edges are sorted into horizontal slabs of the loops'
// v-range, so a query reads only the few edges of its own slab; building is O(edges), a query
// O(edges in one slab).
#include <shapespline/core/model.h>

#include <glm/vec2.hpp>

#include <vector>

namespace shapespline {

// Distance from p to the segment [a, b] (a point when a == b).
double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b);

class TrimClassifier {
 public:
  explicit TrimClassifier(const TrimLoops& trim);

  bool inside(glm::dvec2 p) const;

  struct Edge {
    glm::dvec2 a, b;
  };
  // The index as inside() reads it, for a copy that runs elsewhere (the GPU's closest points):
  // slab s of `slabs` covers v in [v0 + s h, v0 + (s + 1) h) (the first and last reach on) and
  // lists edges slabEdges[slabStart[s] .. slabStart[s + 1]).
  const std::vector<Edge>& edges() const { return edges_; }
  const std::vector<int>& slabStart() const { return slabStart_; }
  const std::vector<int>& slabEdges() const { return slabEdges_; }
  double v0() const { return v0_; }
  double slabHeight() const { return slabHeight_; }
  double tolerance() const { return tolerance_; }
  int slabs() const { return slabs_; }

 private:
  int slabOf(double v) const;

  std::vector<Edge> edges_;
  // Edge indices per slab (an edge is listed in every slab its v-range, widened by the tolerance,
  // touches), in one array: slab s holds slabEdges_[slabStart_[s] .. slabStart_[s + 1]).
  std::vector<int> slabStart_, slabEdges_;
  double v0_ = 0.0, slabHeight_ = 1.0, tolerance_ = 0.0;
  int slabs_ = 1;
};

}  // namespace shapespline
