#include <shapespline/core/list_eval.h>

namespace shapespline {

namespace {

FieldMask firstOrderOf(bool surface) {
  return surface ? fieldBit(Field::Du) | fieldBit(Field::Dv) : fieldBit(Field::D1);
}

}  // namespace

std::optional<ListFields> listFieldsFor(FieldMask fields, bool surface) {
  const FieldMask firstOrder = firstOrderOf(surface);
  if (fields & ~(fieldBit(Field::Point) | firstOrder)) return std::nullopt;
  return fields & firstOrder ? ListFields::FirstDerivatives : ListFields::Point;
}

FieldMask fieldMaskOf(ListFields fields, bool surface) {
  return fieldBit(Field::Point) | (fields == ListFields::FirstDerivatives ? firstOrderOf(surface) : 0u);
}

CurvePoint pointOf(const CurveFirst& f) { return {f.point, f.d1, glm::dvec3(0.0)}; }

SurfacePoint pointOf(const SurfaceFirst& f) {
  SurfacePoint p;
  p.point = f.point, p.du = f.du, p.dv = f.dv, p.normal = glm::dvec3(0.0);
  return p;
}

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
