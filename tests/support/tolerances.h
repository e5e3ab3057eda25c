#pragma once
// Every tolerance of the suite, derived from the arithmetic precision, in one place.
// "scale" is the bounding-box diagonal of the control net (or 1 for basis functions, whose values
// are bounded by 1); derivative tolerances scale with the same quantity times the derivative's
// natural magnitude because d/dt of a sum of bounded basis functions times points is bounded by
// (sum |B_r'|) * scale.
#include <glm/vec3.hpp>

#include <cstring>

namespace shapespline::test {

// fp64: a handful of roundings per Horner step on values <= scale; 1e-12 leaves room for the
// 1/alpha_min amplification of alpha-EB V points (docs/math.md §14) at alpha >= 1/64.
inline constexpr double kFp64Rel = 1e-12;
// fp32: a few ulps (2^-23 ~ 1.2e-7) accumulated over up to ~30 multiply-adds: 4e-6 of the box.
inline constexpr double kFp32Rel = 4e-6;

// Central finite differences, step 2^-14: truncation h^2/6 |f'''| ~ 1e-9 |f'''|, rounding eps/h ~
// 4e-12 |f|; kFdRel leaves two orders of magnitude above both for the O(1..100) functions and the
// nets the tests difference.
inline constexpr double kFdStep = 1.0 / 16384.0;
inline constexpr double kFdRel = 1e-6;

// The same bits: results that must not depend on how they were reached (a lookup, a slice).
inline bool sameBits(const glm::dvec3& a, const glm::dvec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace shapespline::test
