#pragma once
// Where the part mesher's surface points come from: lists of (U, V) on one face, evaluated for the
// point and first partials. The CPU evaluator is core's list kernel in fp64 (the reference); the
// session evaluator sends the same lists through a sampling::Session, so a Vulkan device evaluates
// them (the list kernels of `*_eval.comp`) while the triangulation stays on the CPU.
#include <shapespline/core/surface.h>
#include <shapespline/sampling/session.h>

#include <glm/vec2.hpp>

#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <unordered_map>

namespace shapespline::part {

class FaceEvaluator {
 public:
  virtual ~FaceEvaluator() = default;
  // out[k] at uv[k] (same sizes); parameters outside the face's domain are clamped into it (trim
  // points may lie up to the trim tolerance outside).
  virtual void evaluate(const Surface& face, std::span<const glm::dvec2> uv, std::span<SurfaceFirst> out) = 0;
  // The device, for reports ("cpu fp64", or the Vulkan device's name and precision).
  virtual std::string device() const = 0;
};

// Thread-safe: several faces may be evaluated at once.
class CpuFaceEvaluator final : public FaceEvaluator {
 public:
  void evaluate(const Surface& face, std::span<const glm::dvec2> uv, std::span<SurfaceFirst> out) override;
  std::string device() const override { return "cpu fp64"; }
};

// Through a session on the device `request` names; one list at a time (the session is not
// thread-safe), so callers on several threads take turns. Each face it is asked about stays on
// the device (sampling::Session::ResidentSurface, found by the face's address): its net is uploaded
// once, and each list is one evaluation. Keep one evaluator per part, while the part lives; a
// part meshed again through the same evaluator (at another deflection) uploads nothing.
class SessionFaceEvaluator final : public FaceEvaluator {
 public:
  SessionFaceEvaluator(sampling::Session& session, sampling::DeviceRequest request, std::string device)
      : session_(session), request_(std::move(request)), device_(std::move(device)) {}
  void evaluate(const Surface& face, std::span<const glm::dvec2> uv, std::span<SurfaceFirst> out) override;
  std::string device() const override { return device_; }

 private:
  sampling::Session& session_;
  sampling::DeviceRequest request_;
  std::string device_;
  std::mutex mutex_;
  std::unordered_map<const Surface*, std::unique_ptr<sampling::Session::ResidentSurface>> resident_;
};

// The device a part mesh runs on for `request`: `auto` is the CPU, because the mesher asks for many
// small lists (a few per face and round) and on a device each costs a submission that outweighs
// its evaluation (bench/cad/part_mesh.cpp: a 1,018-face part in 0.08 s on the CPU, 5 s on
// lavapipe); `vulkan` and `cpu` are as asked.
sampling::DeviceRequest meshDeviceRequest(sampling::DeviceRequest request);

// uv clamped into the face's parameter ranges, as global list queries.
std::vector<SurfaceQuery> clampedQueries(const Surface& face, std::span<const glm::dvec2> uv);

}  // namespace shapespline::part
