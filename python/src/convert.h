#pragma once
// Conversions between Python objects and the library's types, shared by the binding files.
#include <shapespline/core/model.h>
#include <shapespline/core/sample_grid.h>
#include <shapespline/sampling/report.h>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace shapespline::python {

namespace py = pybind11;

// A bad argument of a Python call (not a model field): ValueError "NAME: RULE (got VALUE)".
[[noreturn]] void argumentError(const std::string& name, const std::string& rule, const std::string& value = "");

// A value as a C-order array of doubles (converted if need be); ValueError naming `name` when it
// is not numbers.
using DArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
DArray asArray(py::handle h, const char* name);

// A Python value (dict, list, tuple, number, bool, str, None, NumPy array or scalar) as JSON, for
// the model parser. `path` names the value in errors (ModelError, as the JSON reader's paths).
nlohmann::json toJson(py::handle value, const std::string& path, int depth = 0);
// JSON (a model written by io::toJson) as Python objects (dict, list, float, ...).
py::object fromJson(const nlohmann::json& j);

Precision parsePrecision(const std::string& s);
sampling::DeviceRequest deviceRequest(const std::string& device, const std::string& precision, bool require);

// A NumPy array that owns `data` (moved into a capsule, no copy) with the given shape.
template <class T>
py::array_t<T> owned(std::vector<T>&& data, std::vector<py::ssize_t> shape) {
  auto* heap = new std::vector<T>(std::move(data));
  py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, heap->data(), owner);
}

// A fresh C-contiguous array of `shape` (uninitialised), and its data pointer.
template <class T>
py::array_t<T> empty(std::vector<py::ssize_t> shape) {
  return py::array_t<T>(shape);
}

// n points as an (n, 3) array of the precision's dtype (float32 rounds once).
py::array points3(const std::vector<glm::dvec3>& pts, Precision precision);

// A 1-D float64 array from any sequence or array; `name` for errors.
std::vector<double> doubles(py::handle h, const std::string& name);
// (n, 3) or (n, 2) coordinates (2-D rows get z = 0); returns n points.
std::vector<glm::dvec3> pointRows(py::handle h, const std::string& name, int* dims = nullptr);
glm::dvec3 onePoint(py::handle h, const std::string& name, int dims);

}  // namespace shapespline::python
