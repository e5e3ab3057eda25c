#pragma once
// The list kernel: a curve or surface evaluated at a list of parameters, computing only the fields
// asked for (the point, or the point and first derivatives), on the CPU in fp64. Each result has
// the bits that Curve/Surface::evaluate and evaluateAt give for that field: the sums are theirs, in
// their order, less the second derivatives and the normal. The knot interval of each query is first
// looked for where the previous query's was, and a basis is reused when the next query asks for the
// same parameter in that direction, so a list sorted or grouped by parameter (rows of a grid, Newton
// steps near one point) skips the binary search and half the basis work. The GPU list kernels
// (`*_eval.comp` with the fields as a specialization constant) are the same formula in GLSL.
#include <shapespline/core/curve.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/core/surface.h>

#include <cstddef>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

namespace shapespline {

// One sample of a list: local (span, t) / (patch i, j, u, v) or, with `global`, the global
// parameter u (curves; t unused) / (U, V) = (u, v) (surfaces; i, j unused).
struct CurveQuery {
  bool global = false;
  int span = 0;
  double t = 0.0, u = 0.0;
};
struct SurfaceQuery {
  bool global = false;
  int i = 0, j = 0;
  double u = 0.0, v = 0.0;
};

// A sample outside the model's parameter range: index() is its position in the list.
class QueryRangeError : public std::out_of_range {
 public:
  QueryRangeError(size_t index, const std::string& what) : std::out_of_range(what), index_(index) {}
  size_t index() const noexcept { return index_; }

 private:
  size_t index_;
};

// What a list evaluation computes: the point, or the point and first derivatives (curves d1,
// surfaces du and dv). Fields not computed are left 0.
enum class ListFields { Point, FirstDerivatives };

// The list evaluation that computes `fields` of a curve or surface: nullopt when they ask for more
// than the point and first derivatives (second derivatives, the normal).
std::optional<ListFields> listFieldsFor(FieldMask fields, bool surface);
// The fields a list evaluation computes, as a FieldMask.
FieldMask fieldMaskOf(ListFields fields, bool surface);
// A list result in the full evaluation's type, the fields it did not compute 0.
CurvePoint pointOf(const CurveFirst& f);
SurfacePoint pointOf(const SurfaceFirst& f);

// out[k] for queries[k] (out.size() == queries.size()). Throws QueryRangeError for the first query
// outside the model, as Curve/Surface::evaluate and evaluateAt would for it.
void evaluateList(const Curve& curve, std::span<const CurveQuery> queries, ListFields fields,
                  std::span<CurveFirst> out);
void evaluateList(const Surface& surface, std::span<const SurfaceQuery> queries, ListFields fields,
                  std::span<SurfaceFirst> out);

}  // namespace shapespline
