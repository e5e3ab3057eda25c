#include "project.h"

#include "convert.h"
#include "handle.h"

#include <shapespline/part/closest_points.h>
#include <shapespline/part/gpu_closest_points.h>
#include <shapespline/sampling/session.h>

#include <pybind11/numpy.h>

#include <cmath>
#include <string>
#include <vector>

namespace shapespline::python {

namespace py = pybind11;

py::dict projectPoints(const part::ProjectionTree& tree, py::handle points, int threads, std::optional<double> tolerance,
                       bool part, const std::string& device, const std::string& precision, bool require) {
  const sampling::DeviceRequest request = deviceRequest(device, precision, require);
  if (tolerance && !(std::isfinite(*tolerance) && *tolerance > 0.0))
    argumentError("tolerance", "must be a finite distance > 0 in the model's units (None: exact)", std::to_string(*tolerance));
  const DArray a = asArray(points, "points");
  if (a.ndim() != 2 || a.shape(1) != 3) argumentError("points", "expected an (n, 3) array");
  if (a.shape(0) == 0) argumentError("points", "the cloud has no points");
  if (threads < 0) argumentError("threads", "must be >= 0 (0 = one per CPU)", std::to_string(threads));
  const size_t n = static_cast<size_t>(a.shape(0));
  std::vector<glm::dvec3> queries(n);
  const auto view = a.unchecked<2>();
  for (size_t k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(view(k, c)))
        argumentError("points[" + std::to_string(k) + "]", "every coordinate must be finite", std::to_string(view(k, c)));
    queries[k] = {view(k, 0), view(k, 1), view(k, 2)};
  }
  const bool curve = tree.curve() != nullptr;
  std::vector<part::FootPoint> feet(n);
  {
    py::gil_scoped_release release;
    const part::ClosestPoints closest(tree, tolerance.value_or(0.0));
    const sampling::Report plan = curve ? sampling::Report{} : session().planDevice(request);
    if (curve && request.device != sampling::DeviceKind::Cpu && request.require)
      throw sampling::DeviceError("closest points on a curve run on the CPU only", true);
    if (plan.gpu)
      part::GpuClosestPoints(closest, session().vulkanContext(), plan.computedPrecision).of(queries, feet, !curve, threads);
    else
      closest.of(queries, feet, !curve, threads);
  }
  py::array_t<double> foot({n, size_t{3}}), distance(n);
  py::array_t<double> uv = curve ? py::array_t<double>(n) : py::array_t<double>({n, size_t{2}});
  double* f = foot.mutable_data();
  double* d = distance.mutable_data();
  double* p = uv.mutable_data();
  for (size_t k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) f[3 * k + c] = feet[k].point[c];
    d[k] = feet[k].distance;
    if (curve) {
      p[k] = feet[k].u;
    } else {
      p[2 * k] = feet[k].u, p[2 * k + 1] = feet[k].v;
    }
  }
  py::dict out;
  out["point"] = foot;
  out[curve ? "t" : "uv"] = uv;
  out["distance"] = distance;
  if (curve) return out;
  py::array_t<double> signedDistance(n), normal({n, size_t{3}});
  py::array_t<std::int32_t> faces(n);
  for (size_t k = 0; k < n; ++k) {
    signedDistance.mutable_data()[k] = feet[k].signedDistance;
    for (int c = 0; c < 3; ++c) normal.mutable_data()[3 * k + c] = feet[k].normal[c];
    faces.mutable_data()[k] = feet[k].face;
  }
  out["signed_distance"] = signedDistance;
  out["normal"] = normal;
  if (part) out["face_ids"] = faces;
  return out;
}

}  // namespace shapespline::python
