#include <shapespline/core/list_eval.h>

namespace shapespline {

void evaluateList(const Curve& curve, std::span<const CurveQuery> queries, ListFields fields,
                  std::span<CurveFirst> out) {
  if (out.size() != queries.size()) throw std::invalid_argument("evaluateList: one result per query");
  const bool derivatives = fields == ListFields::FirstDerivatives;
  KnotBasisCache cache;
  for (size_t k = 0; k < queries.size(); ++k) {
    const CurveQuery& q = queries[k];
    try {
      out[k] = q.global ? curve.evaluateFirstAt(q.u, derivatives, cache)
                        : curve.evaluateFirst(q.span, q.t, derivatives, cache);
    } catch (const std::out_of_range& e) {
      throw QueryRangeError(k, e.what());
    }
  }
}

void evaluateList(const Surface& surface, std::span<const SurfaceQuery> queries, ListFields fields,
                  std::span<SurfaceFirst> out) {
  if (out.size() != queries.size()) throw std::invalid_argument("evaluateList: one result per query");
  const bool derivatives = fields == ListFields::FirstDerivatives;
  SurfaceListCache cache;
  for (size_t k = 0; k < queries.size(); ++k) {
    const SurfaceQuery& q = queries[k];
    try {
      out[k] = q.global ? surface.evaluateFirstAt(q.u, q.v, derivatives, cache)
                        : surface.evaluateFirst(q.i, q.j, q.u, q.v, derivatives, cache);
    } catch (const std::out_of_range& e) {
      throw QueryRangeError(k, e.what());
    }
  }
}

}  // namespace shapespline
