#pragma once
// Exact 2-D orientation and in-circle signs (Shewchuk, "Adaptive Precision Floating-Point
// Arithmetic and Fast Robust Geometric Predicates", 1997): a floating-point determinant whose sign
// is returned when it exceeds a bound on its rounding error, otherwise the determinant computed
// exactly as an expansion (a sum of non-overlapping doubles). Assumes IEEE doubles with
// round-to-nearest and no contraction into FMA (the part module compiles with -ffp-contract=off).
#include <glm/vec2.hpp>

namespace shapespline::part {

// +1 when a, b, c turn counter-clockwise, -1 clockwise, 0 when collinear (exactly).
int orient2d(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c);

// +1 when d lies strictly inside the circle through the counter-clockwise a, b, c, -1 outside,
// 0 on it (exactly). For clockwise a, b, c the sign is reversed.
int incircle(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d);

}  // namespace shapespline::part
