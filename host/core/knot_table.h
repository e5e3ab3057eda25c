#pragma once
// Knot-vector B-spline bases tabulated at the grid samples of one knot interval, so that the grid
// samplers evaluate de Boor–Cox once per sample row or column instead of once per point (the
// uniform families' DirectionTable does the same for span bases). Private to core.
#include <shapespline/core/span_basis.h>

#include <cstddef>
#include <span>
#include <vector>

namespace shapespline {

// The bases of one direction at samples a = 0..S-1 of knot interval i (non-empty): the knot
// parameter t_i + s_a (t_{i+1} - t_i), s_a = a / (S-1), exactly as Curve/Surface::evaluate form it,
// on the span findKnotSpan picks there: i, except that the last sample lies on the next non-empty
// interval where a derivative up to the second jumps at t_{i+1} (elsewhere i's polynomial gives the
// same values there, and keeps the row in one span). b[d][r * S + a] = d-th derivative of
// N_{span[a] - order + 1 + r} at that parameter (rows above order - 1 are zero).
struct KnotTable {
  int order = 0, samples = 0;
  int interval = -1;        // the interval tabulated (-1: none yet)
  std::vector<int> span;    // per sample
  std::vector<double> b[3];
  // Some sample needed bsplineBasisDerivsScaled's exponent (knot widths below 2^-500): the table
  // holds no usable derivatives and the samplers take the per-point path for the interval.
  bool scaled = false;

  const double* row(int d, int r) const { return b[d].data() + static_cast<size_t>(r) * samples; }
  // Samples [first, end) share span[first]: the end of the run that starts at `first`.
  int runEnd(int first) const {
    int e = first + 1;
    while (e < samples && span[static_cast<size_t>(e)] == span[static_cast<size_t>(first)]) ++e;
    return e;
  }
};

// Fills `out` (reusing its storage) for interval `interval` of a knot vector of `pointCount`
// control points.
void tabulateKnotInterval(int order, std::span<const double> knots, int pointCount, int interval, int samples,
                          KnotTable& out);

// The tables of every non-empty interval of one direction, built once per job when they fit
// `maxBytes` (then shared read-only by the workers); otherwise of(i) fills the caller's scratch
// table when it holds another interval.
class KnotTables {
 public:
  static constexpr size_t kMaxKnotTableBytes = size_t{32} << 20;
  KnotTables(int order, std::span<const double> knots, int pointCount, int samples,
             size_t maxBytes = kMaxKnotTableBytes);
  const KnotTable& of(int interval, KnotTable& scratch) const;

 private:
  int order_, pointCount_, samples_;
  std::span<const double> knots_;
  std::vector<KnotTable> all_;  // by interval; empty when over the budget
};

}  // namespace shapespline
