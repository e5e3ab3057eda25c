#pragma once
// The colour scale of pictures that colour a surface by a value (render --distance): t = 0 (none)
// to 1 (the most) from pale yellow through orange to dark red, light to dark so that it reads in
// grey too. Used for the surface and for its legend's colour bar alike.
#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace shapespline::render {

inline glm::vec3 heatColour(double t) {
  const glm::vec3 stops[] = {{0.99f, 0.96f, 0.74f}, {0.96f, 0.56f, 0.16f}, {0.55f, 0.0f, 0.11f}};
  const float x = float(glm::clamp(t, 0.0, 1.0)) * 2.0f;
  const int i = x < 1.0f ? 0 : 1;
  return glm::mix(stops[i], stops[i + 1], x - float(i));
}

}  // namespace shapespline::render
