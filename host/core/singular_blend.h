#pragma once
// The singular blending function S(t) of [XW] §3 (docs/math.md §3): piecewise cubic on thirds, C^2,
// S(0)=0, S(1)=1, S'=S''=0 at both ends.
namespace shapespline {

struct BlendValue {
  double s, d1, d2;
};

BlendValue singularBlend(double t);

}  // namespace shapespline
