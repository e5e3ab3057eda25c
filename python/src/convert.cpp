#include "convert.h"

#include <cmath>
#include <limits>

namespace shapespline::python {

DArray asArray(py::handle h, const char* name) {
  DArray a;
  try {
    a = DArray::ensure(h);
  } catch (const py::error_already_set&) {
  }
  if (!a) argumentError(name, "expected an array of numbers", py::str(py::repr(h)));
  return a;
}

void argumentError(const std::string& name, const std::string& rule, const std::string& value) {
  throw py::value_error(name + ": " + rule + (value.empty() ? "" : " (got " + value + ")"));
}

namespace {

std::string shortRepr(py::handle h) {
  std::string s = py::str(py::repr(h));
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

}  // namespace

nlohmann::json toJson(py::handle h, const std::string& path, int depth) {
  const std::string where = path.empty() ? "(document)" : path;
  if (depth > 64) throw ModelError(where, "", "nesting deeper than 64 levels");
  if (h.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(h)) return h.cast<bool>();
  if (py::isinstance<py::int_>(h)) {
    try {
      return h.cast<long long>();
    } catch (const py::cast_error&) {
      return py::float_(py::reinterpret_borrow<py::object>(h)).cast<double>();
    }
  }
  if (py::isinstance<py::float_>(h)) return h.cast<double>();
  if (py::isinstance<py::str>(h)) return h.cast<std::string>();
  if (py::isinstance<py::dict>(h)) {
    nlohmann::json o = nlohmann::json::object();
    for (auto item : py::reinterpret_borrow<py::dict>(h)) {
      if (!py::isinstance<py::str>(item.first)) {
        throw ModelError(where, shortRepr(item.first), "keys must be strings");
      }
      const std::string key = item.first.cast<std::string>();
      o[key] = toJson(item.second, path.empty() ? key : path + "." + key, depth + 1);
    }
    return o;
  }
  if (py::isinstance<py::list>(h) || py::isinstance<py::tuple>(h)) {
    nlohmann::json a = nlohmann::json::array();
    size_t i = 0;
    for (auto item : py::reinterpret_borrow<py::iterable>(h)) {
      a.push_back(toJson(item, where + "[" + std::to_string(i++) + "]", depth + 1));
    }
    return a;
  }
  if (py::hasattr(h, "tolist") && py::hasattr(h, "dtype")) {  // NumPy arrays and scalars
    const std::string kind = py::str(h.attr("dtype").attr("kind"));
    if (kind != "f" && kind != "i" && kind != "u" && kind != "b") {
      throw ModelError(where, shortRepr(h), "a NumPy value here must be numeric (dtype kind " + kind + ")");
    }
    return toJson(h.attr("tolist")(), path, depth);
  }
  throw ModelError(where, shortRepr(h), "expected a number, bool, string, list, tuple, dict or NumPy array");
}

py::object fromJson(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null:
      return py::none();
    case nlohmann::json::value_t::boolean:
      return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer:
      return py::int_(j.get<long long>());
    case nlohmann::json::value_t::number_unsigned:
      return py::int_(j.get<unsigned long long>());
    case nlohmann::json::value_t::number_float:
      return py::float_(j.get<double>());
    case nlohmann::json::value_t::string:
      return py::str(j.get<std::string>());
    case nlohmann::json::value_t::array: {
      py::list l;
      for (const auto& e : j) l.append(fromJson(e));
      return l;
    }
    case nlohmann::json::value_t::object: {
      py::dict d;
      for (auto it = j.begin(); it != j.end(); ++it) d[py::str(it.key())] = fromJson(it.value());
      return d;
    }
    default:
      return py::none();
  }
}

Precision parsePrecision(const std::string& s) {
  if (s == "double" || s == "float64" || s == "fp64") return Precision::Double;
  if (s == "float" || s == "float32" || s == "fp32") return Precision::Float;
  argumentError("precision", "expected 'double' or 'float'", "'" + s + "'");
}

sampling::DeviceRequest deviceRequest(const std::string& device, const std::string& precision, bool require) {
  sampling::DeviceRequest r;
  if (device == "auto") {
    r.device = sampling::DeviceKind::Auto;
  } else if (device == "vulkan" || device == "gpu") {
    r.device = sampling::DeviceKind::Vulkan;
  } else if (device == "cpu") {
    r.device = sampling::DeviceKind::Cpu;
  } else {
    argumentError("device", "expected 'auto', 'vulkan' or 'cpu'", "'" + device + "'");
  }
  r.precision = parsePrecision(precision);
  r.require = require;
  return r;
}

py::array points3(const std::vector<glm::dvec3>& pts, Precision precision) {
  const auto n = static_cast<py::ssize_t>(pts.size());
  if (precision == Precision::Float) {
    std::vector<float> v(pts.size() * 3);
    for (size_t i = 0; i < pts.size(); ++i)
      for (int c = 0; c < 3; ++c) v[i * 3 + c] = static_cast<float>(pts[i][c]);
    return owned(std::move(v), {n, 3});
  }
  std::vector<double> v(pts.size() * 3);
  for (size_t i = 0; i < pts.size(); ++i)
    for (int c = 0; c < 3; ++c) v[i * 3 + c] = pts[i][c];
  return owned(std::move(v), {n, 3});
}

std::vector<double> doubles(py::handle h, const std::string& name) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  } catch (const py::error_already_set&) {
  }
  if (!a) argumentError(name, "expected a sequence of numbers", shortRepr(h));
  if (a.ndim() > 1) argumentError(name, "expected a scalar or a 1-D sequence of numbers", shortRepr(h));
  const double* p = a.data();
  std::vector<double> v(p, p + a.size());
  for (size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) argumentError(name + "[" + std::to_string(i) + "]", "must be finite", shortRepr(h));
  }
  return v;
}

std::vector<glm::dvec3> pointRows(py::handle h, const std::string& name, int* dims) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  } catch (const py::error_already_set&) {
  }
  if (!a) argumentError(name, "expected an (n, 2) or (n, 3) array of numbers", shortRepr(h));
  if (a.ndim() == 1 && (a.shape(0) == 2 || a.shape(0) == 3)) a = a.reshape({py::ssize_t(1), a.shape(0)});
  if (a.ndim() != 2 || (a.shape(1) != 2 && a.shape(1) != 3)) {
    argumentError(name, "expected an (n, 2) or (n, 3) array", shortRepr(h));
  }
  const int d = static_cast<int>(a.shape(1));
  if (dims) *dims = d;
  std::vector<glm::dvec3> out(static_cast<size_t>(a.shape(0)), glm::dvec3(0.0));
  const double* p = a.data();
  for (size_t i = 0; i < out.size(); ++i) {
    for (int c = 0; c < d; ++c) {
      const double v = p[i * d + c];
      if (!std::isfinite(v)) {
        argumentError(name + "[" + std::to_string(i) + "][" + std::to_string(c) + "]", "must be finite",
                      std::to_string(v));
      }
      out[i][c] = v;
    }
  }
  return out;
}

glm::dvec3 onePoint(py::handle h, const std::string& name, int dims) {
  int d = 0;
  const std::vector<glm::dvec3> p = pointRows(h, name, &d);
  if (p.size() != 1 || d != dims) {
    argumentError(name, "expected one point of " + std::to_string(dims) + " coordinates", shortRepr(h));
  }
  return p[0];
}

}  // namespace shapespline::python
