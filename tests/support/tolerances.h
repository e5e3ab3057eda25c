#pragma once
// Every tolerance of the suite, derived from the arithmetic precision, in one place.
// "scale" is the bounding-box diagonal of the control net (or 1 for basis functions, whose values
// are bounded by 1); derivative tolerances scale with the same quantity times the derivative's
// natural magnitude because d/dt of a sum of bounded basis functions times points is bounded by
// (sum |B_r'|) * scale.
namespace shapespline::test {

// fp64: a handful of roundings per Horner step on values <= scale; 1e-12 leaves room for the
// 1/alpha_min amplification of alpha-EB V points (docs/math.md §14) at alpha >= 1/64.
inline constexpr double kFp64Rel = 1e-12;
// fp32: a few ulps (2^-23 ~ 1.2e-7) accumulated over up to ~30 multiply-adds: 4e-6 of the box.
inline constexpr double kFp32Rel = 4e-6;

}  // namespace shapespline::test
