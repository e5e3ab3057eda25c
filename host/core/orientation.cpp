// Signed volume of a closed surface's sampled triangles (core/orientation.h).
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/orientation.h>

#include <glm/geometric.hpp>

namespace shapespline {

double signedVolume(const Surface& surface, int samples) {
  GridSpec grid;
  grid.samplesU = grid.samplesV = samples;
  double volume = 0.0;
  const size_t s = static_cast<size_t>(samples);
  sampleSurfaceGrid(surface, grid, fieldBit(Field::Point), [&](const GridChunk& chunk) {
    const auto* p = static_cast<const double*>(chunk.planes[static_cast<size_t>(Field::Point)]);
    // Whole patches only: each patch's cells are triangulated on their own (shared edges are
    // traversed once from each side, so their contributions cancel on a closed surface).
    for (size_t item = 0; item < chunk.itemCount; ++item) {
      const double* q = p + item * s * s * 3;
      auto at = [&](size_t a, size_t b) { return glm::dvec3(q[(a * s + b) * 3], q[(a * s + b) * 3 + 1], q[(a * s + b) * 3 + 2]); };
      for (size_t a = 0; a + 1 < s; ++a) {
        for (size_t b = 0; b + 1 < s; ++b) {
          const glm::dvec3 p00 = at(a, b), p10 = at(a + 1, b), p11 = at(a + 1, b + 1), p01 = at(a, b + 1);
          volume += glm::dot(p00, glm::cross(p10, p11)) + glm::dot(p00, glm::cross(p11, p01));
        }
      }
    }
  }, {});
  return volume / 6.0;
}

}  // namespace shapespline
