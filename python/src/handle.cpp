#include "handle.h"

#include <atomic>
#include <cmath>
#include <mutex>
#include <string>

namespace shapespline::python {
namespace {

std::mutex contextMutex;
std::atomic<bool> contextResolved{false};

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

sampling::Session& session() {
  // preferFp64: one context serves both precisions (a device with shaderFloat64 ranks first).
  static sampling::Session s([] {
    vk::ContextOptions o;
    o.preferFp64 = true;
    return o;
  }());
  return s;
}

template <class Model>
sampling::Report plan(const Model& model, const sampling::DeviceRequest& request) {
  if (request.device == sampling::DeviceKind::Cpu || contextResolved.load(std::memory_order_acquire)) {
    return session().plan(model, request);
  }
  // The first GPU request creates the session's context; later ones only read it.
  std::lock_guard lock(contextMutex);
  try {
    sampling::Report r = session().plan(model, request);
    contextResolved.store(true, std::memory_order_release);
    return r;
  } catch (const sampling::DeviceError& e) {
    if (e.fallbackRefused()) contextResolved.store(true, std::memory_order_release);
    throw;
  }
}
template sampling::Report plan(const Curve&, const sampling::DeviceRequest&);
template sampling::Report plan(const Surface&, const sampling::DeviceRequest&);

void rethrowDeviceError() {
  try {
    throw;
  } catch (const vk::VulkanError& e) {
    const char* hint = "device='cpu' avoids the GPU";
    if (e.result() == VK_ERROR_OUT_OF_DEVICE_MEMORY || e.result() == VK_ERROR_OUT_OF_HOST_MEMORY) {
      hint = "out of GPU memory: try a smaller chunk_points, or device='cpu'";
    }
    throw sampling::DeviceError(std::string(e.what()) + "; " + hint, false);
  }
}

template <>
void Handle<Curve>::checkQueries(std::span<const sampling::CurveQuery> queries) const {
  const auto [u0, u1] = model_->parameterRange();
  const SpanRange s = model_->spans();
  for (size_t i = 0; i < queries.size(); ++i) {
    const auto& q = queries[i];
    if (q.global) {
      if (!(q.u >= u0 && q.u <= u1)) {
        throw sampling::QueryRangeError(i, "u = " + number(q.u) + " is outside the parameter range [" + number(u0) +
                                               ", " + number(u1) + "]");
      }
    } else if (q.span < s.first || q.span > s.last || !(q.t >= 0.0 && q.t <= 1.0)) {
      throw sampling::QueryRangeError(i, "(span " + std::to_string(q.span) + ", t = " + number(q.t) +
                                             ") is outside spans " + std::to_string(s.first) + ".." +
                                             std::to_string(s.last) + ", t in [0, 1]");
    }
  }
}

template <>
void Handle<Surface>::checkQueries(std::span<const sampling::SurfaceQuery> queries) const {
  const auto [u0, u1] = model_->parameterRangeU();
  const auto [v0, v1] = model_->parameterRangeV();
  const PatchRange p = model_->patches();
  for (size_t i = 0; i < queries.size(); ++i) {
    const auto& q = queries[i];
    if (q.global) {
      if (!(q.u >= u0 && q.u <= u1 && q.v >= v0 && q.v <= v1)) {
        throw sampling::QueryRangeError(i, "(U, V) = (" + number(q.u) + ", " + number(q.v) +
                                               ") is outside the parameter ranges [" + number(u0) + ", " + number(u1) +
                                               "] x [" + number(v0) + ", " + number(v1) + "]");
      }
    } else if (q.i < p.u.first || q.i > p.u.last || q.j < p.v.first || q.j > p.v.last ||
               !(q.u >= 0.0 && q.u <= 1.0 && q.v >= 0.0 && q.v <= 1.0)) {
      throw sampling::QueryRangeError(i, "(patch " + std::to_string(q.i) + ", " + std::to_string(q.j) + ", uv " +
                                             number(q.u) + ", " + number(q.v) + ") is outside patches " +
                                             std::to_string(p.u.first) + ".." + std::to_string(p.u.last) + " x " +
                                             std::to_string(p.v.first) + ".." + std::to_string(p.v.last) +
                                             ", uv in [0, 1]^2");
    }
  }
}


// Local and global queries go to evaluateList / evaluateListAt and are put back in order.
template <>
std::vector<CurvePoint> Handle<Curve>::gpuPoints(Resident& res, std::span<const sampling::CurveQuery> queries,
                                                 FieldMask fields) {
  std::vector<gpu::CurveSample> local;
  std::vector<double> global;
  for (const auto& q : queries) q.global ? global.push_back(q.u) : local.push_back({q.span, q.t});
  std::vector<CurvePoint> atLocal, atGlobal, out(queries.size());
  if (!local.empty()) atLocal = res.evaluator->evaluateList(*res.mirror, local, fields);
  if (!global.empty()) atGlobal = res.evaluator->evaluateListAt(*res.mirror, global, fields);
  for (size_t i = 0, l = 0, g = 0; i < queries.size(); ++i) out[i] = queries[i].global ? atGlobal[g++] : atLocal[l++];
  return out;
}
template <>
std::vector<SurfacePoint> Handle<Surface>::gpuPoints(Resident& res, std::span<const sampling::SurfaceQuery> queries,
                                                     FieldMask fields) {
  std::vector<gpu::SurfaceSample> local;
  std::vector<std::pair<double, double>> global;
  for (const auto& q : queries) q.global ? global.push_back({q.u, q.v}) : local.push_back({q.i, q.j, q.u, q.v});
  std::vector<SurfacePoint> atLocal, atGlobal, out(queries.size());
  if (!local.empty()) atLocal = res.evaluator->evaluateList(*res.mirror, local, fields);
  if (!global.empty()) atGlobal = res.evaluator->evaluateListAt(*res.mirror, global, fields);
  for (size_t i = 0, l = 0, g = 0; i < queries.size(); ++i) out[i] = queries[i].global ? atGlobal[g++] : atLocal[l++];
  return out;
}

}  // namespace shapespline::python
