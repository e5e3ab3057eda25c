#pragma once
// Exact power-of-two scaling of a control net for the GPU kernels, and of their results back.
// Every field but the unit normal is linear in the net, so evaluating 2^k * net and multiplying by
// 2^-k gives the same values (exact unless a value leaves the precision's range, where it rounds
// once). Exponents, not factors: for a subnormal net 2^k is beyond the fp64 range, while
// std::ldexp(x, k) scales every coordinate exactly.
#include <shapespline/core/curve.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/core/surface.h>

#include <glm/vec3.hpp>

#include <array>
#include <vector>

namespace shapespline::sampling {

// Exponent k such that the GPU evaluates 2^k * net: 0 for nets of ordinary magnitude; for nets
// whose largest coordinate M lies outside [2^-20, 2^20] (fp32) or [2^-200, 2^200] (fp64), the k
// that brings M into [1, 2). Products of coordinates inside the kernels (normals, squared lengths)
// then stay in range.
int netScale(const std::vector<glm::dvec3>& points, Precision precision);
int netScale(const Curve& curve, Precision precision);
int netScale(const Surface& surface, Precision precision);
// The same in two steps, for a caller that needs the exponent of more than one precision (one
// pass over a big net): the largest |coordinate| of the net, and the exponent for it.
double largestCoordinate(const std::vector<glm::dvec3>& points);
double largestCoordinate(const Curve& curve);
double largestCoordinate(const Surface& surface);
int netScaleFor(double largestCoordinate, Precision precision);
// The exponent the CPU path uses: it scales only nets beyond 2^200 down (where sums and products
// would overflow); fp64 holds tiny nets as they are, and scaling them up would make the
// derivatives of tiny knot intervals (net / h^r) overflow.
int cpuNetScaleFor(double magnitude);

// The model with its net multiplied by 2^k (validated again by create).
Curve scaledCurve(const Curve& curve, int k);
Surface scaledSurface(const Surface& surface, int k);

// Results of the scaled net multiplied by 2^-k (normals untouched: unit vectors).
void unscale(std::vector<CurvePoint>& points, int k);
void unscale(std::vector<SurfacePoint>& points, int k);
void unscale(std::vector<CurveFirst>& points, int k);
void unscale(std::vector<SurfaceFirst>& points, int k);

// Hands each chunk of the scaled net's grid to `consumer` with every field but the normal
// multiplied by 2^-k (k = 0: the chunk itself). Keeps one buffer per field between chunks.
class ChunkUnscaler {
 public:
  explicit ChunkUnscaler(int k) : k_(-k) {}
  void operator()(const GridChunk& chunk, const ChunkConsumer& consumer);

 private:
  int k_;
  std::array<std::vector<double>, kFieldCount> doubles_;
  std::array<std::vector<float>, kFieldCount> floats_;
};

// What a chunk computed on a scaled net goes through before the caller sees it: scaled back, then
// the slice work (`slice`, may be empty; on every core at once, SliceConsumer work being
// order-free), then `consumer`. The three must outlive the returned consumer. The one path of the
// CPU sampler on a scaled net, the session's GPU jobs and the Python module's resident mirrors.
ChunkConsumer unscaledDelivery(ChunkUnscaler& unscale, const SliceConsumer& slice, const ChunkConsumer& consumer);

}  // namespace shapespline::sampling
