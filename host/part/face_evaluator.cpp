#include <shapespline/core/list_eval.h>
#include <shapespline/part/face_evaluator.h>

#include <algorithm>
#include <stdexcept>

namespace shapespline::part {

std::vector<SurfaceQuery> clampedQueries(const Surface& face, std::span<const glm::dvec2> uv) {
  const auto [u0, u1] = face.parameterRangeU();
  const auto [v0, v1] = face.parameterRangeV();
  std::vector<SurfaceQuery> queries(uv.size());
  for (size_t k = 0; k < uv.size(); ++k) {
    queries[k].global = true;
    queries[k].u = std::clamp(uv[k].x, u0, u1);
    queries[k].v = std::clamp(uv[k].y, v0, v1);
  }
  return queries;
}

sampling::DeviceRequest meshDeviceRequest(sampling::DeviceRequest request) {
  if (request.device == sampling::DeviceKind::Auto) request.device = sampling::DeviceKind::Cpu;
  return request;
}

void CpuFaceEvaluator::evaluate(const Surface& face, std::span<const glm::dvec2> uv, std::span<SurfaceFirst> out) {
  const std::vector<SurfaceQuery> queries = clampedQueries(face, uv);
  evaluateList(face, queries, ListFields::FirstDerivatives, out);
}

void SessionFaceEvaluator::evaluate(const Surface& face, std::span<const glm::dvec2> uv, std::span<SurfaceFirst> out) {
  const std::vector<SurfaceQuery> queries = clampedQueries(face, uv);
  std::lock_guard lock(mutex_);
  auto& resident = resident_[&face];
  if (!resident) resident = session_.resident(face, request_);
  const std::vector<SurfaceFirst> points = resident->evaluate(queries, ListFields::FirstDerivatives);
  if (points.size() != out.size()) throw std::logic_error("the session returned a list of another size");
  std::copy(points.begin(), points.end(), out.begin());
}

}  // namespace shapespline::part
