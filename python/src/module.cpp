// The `shapespline` Python module (pybind11): models, sampling through the sampling layer, list
// evaluation, resident GPU models with parameter setters, tessellation, errors as exceptions.
// Basis tables, GB tools and B-spline extension: tools.cpp. Reference: docs/python.md.
#include "chunks.h"
#include "convert.h"
#include "handle.h"
#include "project.h"
#include "surface_args.h"

#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/huge_pages.h>
#include <shapespline/core/tess_patches.h>
#include <shapespline/core/tess_topology.h>
#include <shapespline/gpu/tessellator.h>
#include <shapespline/io/model_json.h>
#include <shapespline/sampling/devices.h>
#include <shapespline/shaders/tess_layout.h>
#include <shapespline/version.h>
#include <shapespline/vk/submit.h>

#include <glm/geometric.hpp>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>

namespace shapespline::python {

void bindTools(py::module_& m, py::class_<CurveHandle, std::shared_ptr<CurveHandle>>& curve,
               py::class_<SurfaceHandle, std::shared_ptr<SurfaceHandle>>& surface);
void bindPart(py::module_& m);

namespace {

using CurveClass = py::class_<CurveHandle, std::shared_ptr<CurveHandle>>;
using SurfaceClass = py::class_<SurfaceHandle, std::shared_ptr<SurfaceHandle>>;

// ---- Fields ------------------------------------------------------------------------------------

struct FieldName {
  const char* name;
  Field field;
};
constexpr FieldName kCurveFields[] = {{"point", Field::Point}, {"d1", Field::D1}, {"d2", Field::D2}};
constexpr FieldName kSurfaceFields[] = {{"point", Field::Point}, {"du", Field::Du},   {"dv", Field::Dv},
                                        {"duu", Field::Duu},     {"duv", Field::Duv}, {"dvv", Field::Dvv},
                                        {"normal", Field::Normal}};

template <class Model>
std::span<const FieldName> fieldNames() {
  if constexpr (std::is_same_v<Model, Curve>) {
    return kCurveFields;
  } else {
    return kSurfaceFields;
  }
}

template <class Model>
FieldMask parseFields(py::object fields) {
  const auto names = fieldNames<Model>();
  std::vector<std::string> list;
  if (fields.is_none()) {
    list = {"point"};
  } else if (py::isinstance<py::str>(fields)) {
    list = {fields.cast<std::string>()};
  } else {
    try {
      list = fields.cast<std::vector<std::string>>();
    } catch (const py::cast_error&) {
      argumentError("fields", "expected a field name or a sequence of field names", py::str(py::repr(fields)));
    }
  }
  FieldMask mask = 0;
  for (const auto& s : list) {
    if (s == "all") {
      for (const auto& f : names) mask |= fieldBit(f.field);
      continue;
    }
    bool found = false;
    for (const auto& f : names) {
      if (s == f.name) mask |= fieldBit(f.field), found = true;
    }
    if (!found) {
      std::string allowed;
      for (const auto& f : names) allowed += std::string(allowed.empty() ? "" : ", ") + f.name;
      argumentError("fields", "unknown field; expected " + allowed + " or 'all'", "'" + s + "'");
    }
  }
  if (!mask) argumentError("fields", "at least one field is needed");
  return mask;
}

// ---- Models from Python ------------------------------------------------------------------------

// A NumPy array of numbers (at least 1-D) under one of the array keys goes to the parser as it is
// (io::ModelArrays::given: the rules and messages of a .npy array), not as JSON numbers: a 2048^2
// net took 9 s and 15x its size through JSON. Anything else is left to the JSON path (false).
constexpr const char* kArrayKeys[] = {"points", "alpha", "weights"};
bool giveArray(py::handle value, const char* key, nlohmann::json& doc, io::ModelArrays& arrays) {
  if (!py::isinstance<py::array>(value)) return false;
  const auto a = py::reinterpret_borrow<py::array>(value);
  const char kind = a.dtype().kind();
  if (a.ndim() == 0 || (kind != 'f' && kind != 'i' && kind != 'u')) return false;
  const auto c = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!c) throw py::error_already_set();
  io::NpyArray given;
  for (py::ssize_t d = 0; d < c.ndim(); ++d) given.shape.push_back(uint64_t(c.shape(d)));
  if (std::string_view(key) == "points" && c.shape(c.ndim() - 1) == 3 && c.size() > 0) {
    // As the .npy reader does (io::NpyLayout::Points): one block, with room for a surface's net.
    reserveHuge(given.points, io::pointCapacity(given.shape));
    given.points.resize(size_t(c.size()) / 3);
    std::copy(c.data(), c.data() + c.size(), &given.points.data()->x);
  } else {
    reserveHuge(given.values, size_t(c.size()));
    given.values.assign(c.data(), c.data() + c.size());
  }
  arrays.given[key] = std::move(given);
  doc[key] = {{"array", key}};
  return true;
}

io::Model parseDict(py::handle d) {
  if (!py::isinstance<py::dict>(d)) argumentError("model", "expected a dict with the keys of a model file");
  const auto dict = py::reinterpret_borrow<py::dict>(d);
  py::dict rest;  // the keys that go through JSON
  for (auto item : dict) rest[item.first] = item.second;
  nlohmann::json doc;
  io::ModelArrays arrays;
  std::vector<const char*> given;
  for (const char* key : kArrayKeys)
    if (dict.contains(key) && giveArray(dict[key], key, doc, arrays)) {
      PyDict_DelItemString(rest.ptr(), key);
      given.push_back(key);
    }
  nlohmann::json json = toJson(rest, "");
  for (const char* key : given) json[key] = doc[key];
  return io::parseModel(json, &arrays);
}

io::Model loadPath(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    PyErr_SetString(PyExc_FileNotFoundError, ("no such model file: '" + path + "'").c_str());
    throw py::error_already_set();
  }
  py::gil_scoped_release release;
  return io::loadModelFile(path);
}

py::object wrap(io::Model m) {
  if (auto* c = std::get_if<CurveModel>(&m)) return py::cast(std::make_shared<CurveHandle>(Curve::create(std::move(*c))));
  return py::cast(std::make_shared<SurfaceHandle>(Surface::create(std::get<SurfaceModel>(std::move(m)))));
}

// Keyword constructor: the keys of the model file format, checked by the same parser (NumPy arrays
// of points, alpha and weights handed over in `arrays`).
nlohmann::json keywordModel(const char* kind, py::object points, const std::string& construction, py::object degree,
                            py::object order, py::object lambda, py::object mu, py::object alpha, py::object closed,
                            py::object knots, py::object weights, io::ModelArrays& arrays) {
  nlohmann::json j = {{"kind", kind}, {"construction", construction}};
  auto put = [&](const char* key, py::object v) {
    if (!v.is_none()) j[key] = toJson(v, key);
  };
  auto putArray = [&](const char* key, py::object v) {
    if (!giveArray(v, key, j, arrays)) put(key, v);
  };
  putArray("points", points);
  put("degree", degree);
  put("order", order);
  put("lambda", lambda);
  put("mu", mu);
  putArray("alpha", alpha);
  if (!closed.is_none()) {
    if (std::string(kind) == "surface" && py::isinstance<py::bool_>(closed)) {
      const bool b = closed.cast<bool>();
      j["closed"] = {b, b};
    } else {
      put("closed", closed);
    }
  }
  put("knots", knots);
  putArray("weights", weights);
  return j;
}

// ---- Sampling ----------------------------------------------------------------------------------

template <class Model>
size_t gridItems(const Model& m) {
  if constexpr (std::is_same_v<Model, Curve>) {
    return curveGridItems(m).size();
  } else {
    return surfaceGridItems(m).size();
  }
}

template <class Model>
GridSpec parseGrid(py::object grid, py::object samples) {
  if (!grid.is_none() && !samples.is_none()) argumentError("grid", "give grid or samples, not both");
  const bool surface = std::is_same_v<Model, Surface>;
  py::object g = grid.is_none() ? samples : grid;
  const char* name = grid.is_none() ? "samples" : "grid";
  GridSpec spec;
  if (g.is_none()) {
    spec.samplesU = surface ? 16 : 64;
    spec.samplesV = surface ? 16 : 1;
    return spec;
  }
  auto count = [&](py::handle h) {
    long long v = 0;
    try {
      if (py::isinstance<py::float_>(h) || py::isinstance<py::bool_>(h)) throw py::cast_error();
      v = h.cast<long long>();
    } catch (const py::cast_error&) {
      argumentError(name, "expected an integer sample count", py::str(py::repr(h)));
    }
    if (v < 2 || v > (1ll << 30)) argumentError(name, "each sample count must be in [2, 2^30]", std::to_string(v));
    return static_cast<int>(v);
  };
  if (py::isinstance<py::int_>(g) || py::hasattr(g, "__index__")) {
    spec.samplesU = count(g);
    spec.samplesV = surface ? spec.samplesU : 1;
    return spec;
  }
  if (!surface) argumentError(name, "a curve takes one integer: samples per span", py::str(py::repr(g)));
  py::sequence seq;
  try {
    seq = g.cast<py::sequence>();
  } catch (const py::cast_error&) {
    argumentError(name, "expected an integer or a pair (Su, Sv)", py::str(py::repr(g)));
  }
  if (py::len(seq) != 2) argumentError(name, "expected an integer or a pair (Su, Sv)", py::str(py::repr(g)));
  spec.samplesU = count(seq[0]);
  spec.samplesV = count(seq[1]);
  return spec;
}

template <class T>
void copyPlane(const GridChunk& c, Field f, T* dst, size_t first = 0, size_t count = SIZE_MAX) {
  const size_t begin = first * 3, end = std::min(c.pointCount(), first + std::min(count, c.pointCount())) * 3;
  const void* src = c.planes[size_t(f)];
  if (c.precision == Precision::Double) {
    const auto* s = static_cast<const double*>(src);
    for (size_t i = begin; i < end; ++i) dst[i] = static_cast<T>(s[i]);
  } else {
    const auto* s = static_cast<const float*>(src);
    for (size_t i = begin; i < end; ++i) dst[i] = static_cast<T>(s[i]);
  }
}

py::object reportObject(const sampling::Report& r) { return py::cast(r); }

// The items of the job: [first_item, first_item + count).
template <class Model>
GridSpec jobGrid(Handle<Model>& h, GridSpec spec, long long firstItem, long long itemCount) {
  const size_t total = gridItems(*h.model());
  if (firstItem < 0 || static_cast<size_t>(firstItem) >= total) {
    argumentError("first_item", "must be in [0, " + std::to_string(total) + ")", std::to_string(firstItem));
  }
  if (itemCount < 0 || static_cast<size_t>(firstItem + itemCount) > total) {
    argumentError("item_count", "first_item + item_count must not exceed " + std::to_string(total) + " items",
                  std::to_string(itemCount));
  }
  spec.firstItem = static_cast<size_t>(firstItem);
  spec.itemCount = itemCount == 0 ? total - spec.firstItem : static_cast<size_t>(itemCount);
  return spec;
}

template <class Model>
std::vector<py::ssize_t> itemShape(const GridSpec& g) {
  if constexpr (std::is_same_v<Model, Curve>) {
    return {py::ssize_t(g.itemCount), py::ssize_t(g.samplesU), 3};
  } else {
    return {py::ssize_t(g.itemCount), py::ssize_t(g.samplesU), py::ssize_t(g.samplesV), 3};
  }
}

// The result arrays of a grid job, allocated once and written straight from each chunk (the GIL
// released). `run(slice, jobPlanes)` runs the job, through a handle's resident model or the
// session, and returns its report.
template <class Model, class Run>
py::dict sampleIntoArrays(const GridSpec& g, FieldMask mask, Precision precision, sampling::Report& report, Run&& run) {
  const size_t points = g.itemCount * g.pointsPerItem();
  if (points > (size_t{1} << 40) / 24) argumentError("grid", "the job is too large for arrays in memory; use sample_chunks");
  py::dict out;
  std::array<void*, kFieldCount> dst{};
  const bool dbl = precision == Precision::Double;
  for (const auto& f : fieldNames<Model>()) {
    if (!(mask & fieldBit(f.field))) continue;
    py::array a = dbl ? py::array(py::array_t<double>(itemShape<Model>(g))) : py::array(py::array_t<float>(itemShape<Model>(g)));
    dst[size_t(f.field)] = a.mutable_data();
    out[f.name] = a;
  }
  py::gil_scoped_release release;
  const size_t ppi = g.pointsPerItem();
  // fp64 on the CPU: the sampler's workers write the arrays themselves. Otherwise the copy into
  // the arrays is order-free: a slice consumer, run by the CPU sampler's workers as they finish
  // their rows (while the values are in their caches) or on each GPU chunk.
  std::array<double*, kFieldCount> jobPlanes{};
  if (dbl)
    for (int f = 0; f < kFieldCount; ++f) jobPlanes[size_t(f)] = static_cast<double*>(dst[size_t(f)]);
  const SliceConsumer copy = [&](const GridChunk& c, size_t first, size_t count) {
    const size_t offset = ((c.firstItem - g.firstItem) * ppi + c.firstItemPoint()) * 3;
    for (int f = 0; f < kFieldCount; ++f) {
      if (!dst[size_t(f)] || !c.planes[size_t(f)]) continue;
      if (dbl && c.planes[size_t(f)] == static_cast<double*>(dst[size_t(f)]) + offset) continue;  // written there
      if (dbl) {
        copyPlane(c, Field(f), static_cast<double*>(dst[size_t(f)]) + offset, first, count);
      } else {
        copyPlane(c, Field(f), static_cast<float*>(dst[size_t(f)]) + offset, first, count);
      }
    }
  };
  report = run(copy, jobPlanes);
  return out;
}

template <class Model>
py::object sample(Handle<Model>& h, py::object grid, py::object samples, py::object fields, const std::string& device,
                  const std::string& precision, bool require, long long firstItem, long long itemCount,
                  long long chunkPoints, bool withReport) {
  const FieldMask mask = parseFields<Model>(fields);
  sampling::DeviceRequest request = deviceRequest(device, precision, require);
  request.grid = true;
  if (chunkPoints < 0) argumentError("chunk_points", "must be >= 0", std::to_string(chunkPoints));
  const GridSpec g = jobGrid(h, parseGrid<Model>(grid, samples), firstItem, itemCount);
  sampling::Report report;
  py::dict out = sampleIntoArrays<Model>(g, mask, request.precision, report,
                                         [&](const SliceConsumer& copy, const std::array<double*, kFieldCount>& planes) {
    return h.sampleGrid(request, g, mask, [](const GridChunk&) {}, static_cast<size_t>(chunkPoints), copy, planes);
  });
  if (withReport) return py::make_tuple(out, reportObject(report));
  return out;
}

template <class Model>
std::shared_ptr<ChunkStream> sampleChunks(Handle<Model>& h, py::object grid, py::object samples, py::object fields,
                                          const std::string& device, const std::string& precision, bool require,
                                          long long firstItem, long long itemCount, long long chunkPoints,
                                          long long queue) {
  const FieldMask mask = parseFields<Model>(fields);
  const sampling::DeviceRequest request = deviceRequest(device, precision, require);
  if (chunkPoints < 0) argumentError("chunk_points", "must be >= 0", std::to_string(chunkPoints));
  if (queue < 1 || queue > 64) argumentError("queue", "must be in [1, 64]", std::to_string(queue));
  const GridSpec g = jobGrid(h, parseGrid<Model>(grid, samples), firstItem, itemCount);
  const auto held = h.model();
  const Model& snapshot = *held;
  {
    py::gil_scoped_release release;
    python::plan(snapshot, request);  // device errors here, on the caller's thread
  }
  sampling::GridOptions options;
  options.chunkPoints = chunkPoints > 0 ? static_cast<size_t>(chunkPoints) : 0;  // 0: the Session's default per device
  auto job = [snapshot = std::move(snapshot), request, g, mask, options](const ChunkConsumer& consumer) {
    return session().sampleGrid(snapshot, request, g, mask, consumer, options);
  };
  return std::make_shared<ChunkStream>(std::move(job), g, mask, request.precision, static_cast<size_t>(queue),
                                       std::is_same_v<Model, Surface>);
}

template <class Model>
py::object chunkDict(ChunkData&& d, FieldMask mask, Precision precision) {
  py::dict out;
  out["first_item"] = d.firstItem;
  out["item_count"] = d.itemCount;
  out["first_row"] = d.firstRow;
  out["row_count"] = d.rowCount;
  out["first_point"] = d.firstPoint;
  const auto n = static_cast<py::ssize_t>(d.points);
  for (const auto& f : fieldNames<Model>()) {
    if (!(mask & fieldBit(f.field))) continue;
    const size_t i = size_t(f.field);
    if (precision == Precision::Double) {
      out[f.name] = owned(std::move(d.f64[i]), {n, 3});
    } else {
      out[f.name] = owned(std::move(d.f32[i]), {n, 3});
    }
  }
  return out;
}

// ---- Many models ---------------------------------------------------------------------------------

// One model of sample_many, sampled whole through the module's Session: its device and evaluators
// (compiled pipelines) serve every model, and no resident mirror is built for a model sampled once.
template <class Model>
py::object sampleSnapshot(const Model& model, py::object grid, py::object fields, const sampling::DeviceRequest& request,
                          bool withReport) {
  const FieldMask mask = parseFields<Model>(fields);
  GridSpec g = parseGrid<Model>(grid, py::none());
  g.itemCount = gridItems(model);
  {
    py::gil_scoped_release release;
    python::plan(model, request);  // creates the session's context once; DeviceError when required
  }
  sampling::Report report;
  py::dict out = sampleIntoArrays<Model>(g, mask, request.precision, report,
                                         [&](const SliceConsumer& copy, const std::array<double*, kFieldCount>& planes) {
    sampling::GridOptions o;
    o.slice = copy;
    o.jobPlanes = planes;
    return session().sampleGrid(model, request, g, mask, [](const GridChunk&) {}, o);
  });
  if (withReport) return py::make_tuple(out, reportObject(report));
  return out;
}

py::object sampleModelData(io::Model m, py::object grid, py::object fields, const sampling::DeviceRequest& request,
                           bool withReport) {
  if (auto* c = std::get_if<CurveModel>(&m)) {
    const Curve curve = [&] {
      py::gil_scoped_release release;
      return Curve::create(std::move(*c));
    }();
    return sampleSnapshot(curve, grid, fields, request, withReport);
  }
  const Surface surface = [&] {
    py::gil_scoped_release release;
    return Surface::create(std::get<SurfaceModel>(std::move(m)));
  }();
  return sampleSnapshot(surface, grid, fields, request, withReport);
}

// A Curve, a Surface, a model dict, or a model file's path (str or os.PathLike).
py::object sampleAnyModel(py::object item, py::object grid, py::object fields, const sampling::DeviceRequest& request,
                          bool withReport) {
  if (py::isinstance<CurveHandle>(item)) {
    return sampleSnapshot(*item.cast<CurveHandle&>().model(), grid, fields, request, withReport);
  }
  if (py::isinstance<SurfaceHandle>(item)) {
    return sampleSnapshot(*item.cast<SurfaceHandle&>().model(), grid, fields, request, withReport);
  }
  if (py::isinstance<py::dict>(item)) return sampleModelData(parseDict(item.cast<py::dict>()), grid, fields, request, withReport);
  if (py::isinstance<py::str>(item) || py::hasattr(item, "__fspath__")) {
    const std::string path = py::str(py::module_::import("os").attr("fspath")(item));
    return sampleModelData(loadPath(path), grid, fields, request, withReport);
  }
  PyErr_SetString(PyExc_TypeError, ("a model must be a Curve, a Surface, a dict or a path (got " +
                                    std::string(py::str(py::type::of(item).attr("__name__"))) + ")").c_str());
  throw py::error_already_set();
}

// sample_many: each model in turn; a failing model's exception names it (a note "models[k]"), and
// is raised (errors="raise") or put in its place in the list (errors="keep") while the others are
// still sampled.
py::list sampleMany(py::sequence models, py::object grid, py::object fields, const std::string& device,
                    const std::string& precision, bool require, const std::string& errors, bool withReport) {
  if (errors != "raise" && errors != "keep") argumentError("errors", "must be 'raise' or 'keep'", errors);
  sampling::DeviceRequest request = deviceRequest(device, precision, require);
  request.grid = true;
  // Called as a Python function, so that every C++ exception arrives translated (ModelError,
  // DeviceError, ...) as the exception object the caller would see.
  py::cpp_function one([&](py::object item) { return sampleAnyModel(item, grid, fields, request, withReport); });
  py::list out;
  const size_t n = py::len(models);
  for (size_t k = 0; k < n; ++k) {
    try {
      out.append(one(models[k]));
    } catch (py::error_already_set& e) {
      const std::string note = "sample_many: models[" + std::to_string(k) + "]";
      if (py::hasattr(e.value(), "add_note")) e.value().attr("add_note")(note);
      if (errors == "raise") throw;
      out.append(e.value());
    }
  }
  return out;
}

// ---- Lists -------------------------------------------------------------------------------------

template <class Model, class Point>
py::dict pointDict(const std::vector<Point>& pts, Precision precision, FieldMask fields = ~FieldMask{0}) {
  py::dict out;
  std::vector<glm::dvec3> v(pts.size());
  auto put = [&](const char* name, glm::dvec3 Point::*member) {
    bool asked = false;
    for (const auto& f : kCurveFields) asked |= !std::strcmp(f.name, name) && (fields & fieldBit(f.field));
    for (const auto& f : kSurfaceFields) asked |= !std::strcmp(f.name, name) && (fields & fieldBit(f.field));
    if (!asked) return;
    for (size_t i = 0; i < pts.size(); ++i) v[i] = pts[i].*member;
    out[name] = points3(v, precision);
  };
  if constexpr (std::is_same_v<Model, Curve>) {
    put("point", &CurvePoint::point);
    put("d1", &CurvePoint::d1);
    put("d2", &CurvePoint::d2);
  } else {
    put("point", &SurfacePoint::point);
    put("du", &SurfacePoint::du);
    put("dv", &SurfacePoint::dv);
    put("duu", &SurfacePoint::duu);
    put("duv", &SurfacePoint::duv);
    put("dvv", &SurfacePoint::dvv);
    put("normal", &SurfacePoint::normal);
  }
  return out;
}


py::object curveEvaluate(CurveHandle& h, py::object params, py::object span, py::object t, const std::string& device,
                         const std::string& precision, bool require, bool withReport, py::object fields) {
  const FieldMask mask = fields.is_none() ? shapespline::kCurveFields : parseFields<Curve>(fields) | fieldBit(Field::Point);
  const sampling::DeviceRequest request = deviceRequest(device, precision, require);
  std::vector<sampling::CurveQuery> q;
  if (!params.is_none()) {
    if (!span.is_none() || !t.is_none()) argumentError("params", "give params (global u) or span and t, not both");
    const DArray u = asArray(params, "params");
    if (u.ndim() > 1) argumentError("params", "expected a scalar or a 1-D array of global parameters u");
    for (py::ssize_t i = 0; i < u.size(); ++i) q.push_back({true, 0, 0.0, u.data()[i]});
  } else {
    if (span.is_none() || t.is_none()) argumentError("params", "give params (global u), or span and t");
    const DArray s = asArray(span, "span"), tt = asArray(t, "t");
    if (s.ndim() > 1 || tt.ndim() > 1) argumentError("span", "span and t must be scalars or 1-D arrays");
    const py::ssize_t n = std::max(s.size(), tt.size());
    if ((s.size() != n && s.size() != 1) || (tt.size() != n && tt.size() != 1)) {
      argumentError("t", "span and t must have the same length (or one of them a scalar)");
    }
    for (py::ssize_t i = 0; i < n; ++i) {
      const double sp = s.data()[s.size() == 1 ? 0 : i];
      if (sp != std::floor(sp) || std::abs(sp) > 1e9) argumentError("span[" + std::to_string(i) + "]", "must be an integer");
      q.push_back({false, static_cast<int>(sp), tt.data()[tt.size() == 1 ? 0 : i], 0.0});
    }
  }
  sampling::ListResult<CurvePoint> r;
  {
    py::gil_scoped_release release;
    r = h.evaluate(request, q, mask);
  }
  py::dict out = pointDict<Curve>(r.points, request.precision, mask);
  if (withReport) return py::make_tuple(out, reportObject(r.report));
  return out;
}

py::object surfaceEvaluate(SurfaceHandle& h, py::object params, py::object patch, py::object uv,
                           const std::string& device, const std::string& precision, bool require, bool withReport,
                           py::object fields) {
  const FieldMask mask =
      fields.is_none() ? shapespline::kSurfaceFields : parseFields<Surface>(fields) | fieldBit(Field::Point);
  const sampling::DeviceRequest request = deviceRequest(device, precision, require);
  std::vector<sampling::SurfaceQuery> q;
  auto pairs = [](py::object o, const char* name) {
    DArray a = asArray(o, name);
    if (a.ndim() == 1 && a.size() == 2) a = a.reshape({py::ssize_t(1), py::ssize_t(2)});
    if (a.ndim() != 2 || a.shape(1) != 2) argumentError(name, "expected an (n, 2) array");
    return a;
  };
  if (!params.is_none()) {
    if (!patch.is_none() || !uv.is_none()) argumentError("params", "give params (global U, V) or patch and uv, not both");
    const DArray a = pairs(params, "params");
    for (py::ssize_t i = 0; i < a.shape(0); ++i) q.push_back({true, 0, 0, a.at(i, 0), a.at(i, 1)});
  } else {
    if (patch.is_none() || uv.is_none()) argumentError("params", "give params (global U, V), or patch and uv");
    const DArray p = pairs(patch, "patch"), l = pairs(uv, "uv");
    if (p.shape(0) != l.shape(0)) argumentError("uv", "patch and uv must have the same number of rows");
    for (py::ssize_t i = 0; i < p.shape(0); ++i) {
      for (int c = 0; c < 2; ++c) {
        const double v = p.at(i, c);
        if (v != std::floor(v) || std::abs(v) > 1e9) argumentError("patch[" + std::to_string(i) + "]", "must be integers");
      }
      q.push_back({false, static_cast<int>(p.at(i, 0)), static_cast<int>(p.at(i, 1)), l.at(i, 0), l.at(i, 1)});
    }
  }
  sampling::ListResult<SurfacePoint> r;
  {
    py::gil_scoped_release release;
    r = h.evaluate(request, q, mask);
  }
  py::dict out = pointDict<Surface>(r.points, request.precision, mask);
  if (withReport) return py::make_tuple(out, reportObject(r.report));
  return out;
}

// ---- Tessellation ------------------------------------------------------------------------------

struct Mesh {
  std::vector<float> vertices;  // 8 per vertex: position, normal, uv (shaders/tess_layout.h TessVertex)
  std::vector<uint32_t> indices;
  sampling::Report report;
};

// The CPU counterpart of gpu::SurfaceTessellator: the same core topology, each vertex's canonical
// sample evaluated in fp64, normals the normalised mean over the patches sharing the vertex.
Mesh tessellateCpu(const Surface& s, int rate) {
  const TessPatches patches(s);
  const TessTopology topo = buildTessTopology(uniformTessRates(s, rate));
  Mesh m;
  m.vertices.resize(size_t(topo.vertexCount) * 8);
  for (uint32_t k = 0; k < topo.vertexCount; ++k) {
    const TessSample& c = topo.samples[k];
    const SurfacePoint p = patches.evaluate(s, c);
    glm::dvec3 n = p.normal;
    for (uint32_t e = 0; e < topo.extraCount[k]; ++e) n += patches.evaluate(s, topo.samples[topo.extraFirst[k] + e]).normal;
    if (topo.extraCount[k] > 0) n = glm::normalize(n);
    float* v = &m.vertices[size_t(k) * 8];
    for (int i = 0; i < 3; ++i) v[i] = float(p.point[i]), v[3 + i] = float(n[i]);
    const auto uv = patches.uv(s, c);
    v[6] = uv[0];
    v[7] = uv[1];
  }
  m.indices = topo.indices;
  return m;
}

py::object tessellate(SurfaceHandle& h, int rate, const std::string& device, const std::string& precision,
                      bool require, bool withReport) {
  const sampling::DeviceRequest request = deviceRequest(device, precision, require);
  if (rate < 1 || rate > 4096) argumentError("rate", "must be in [1, 4096]", std::to_string(rate));
  Mesh mesh;
  {
    py::gil_scoped_release release;
    mesh = h.withDevice(
        request,
        [&](const std::shared_ptr<vk::Context>& ctx, gpu::GpuSurface& mirror, const sampling::Report& r) {
          gpu::SurfaceTessellator tess(ctx, mirror, gpu::SurfaceTessellator::uniformRates(mirror, rate));
          vk::runOneShot(*ctx, [&](VkCommandBuffer cmd) { tess.record(cmd); });
          Mesh m;
          m.vertices.resize(size_t(tess.vertexCount()) * 8);
          tess.vertexBuffer().downloadSpan(std::span<float>(m.vertices));
          if (r.netScaleExponent != 0) {
            for (size_t k = 0; k < tess.vertexCount(); ++k)
              for (int i = 0; i < 3; ++i) {
                float& x = m.vertices[k * 8 + i];
                x = float(std::ldexp(double(x), -r.netScaleExponent));
              }
          }
          m.indices = tess.topology().indices;
          m.report = r;
          return m;
        },
        [&](const Surface& s, const sampling::Report& r) {
          Mesh m = tessellateCpu(s, rate);
          m.report = r;
          return m;
        });
  }
  const auto nv = static_cast<py::ssize_t>(mesh.vertices.size() / 8);
  const auto nt = static_cast<py::ssize_t>(mesh.indices.size() / 3);
  py::tuple result = py::make_tuple(owned(std::move(mesh.vertices), {nv, 8}), owned(std::move(mesh.indices), {nt, 3}));
  if (withReport) return py::make_tuple(result[0], result[1], reportObject(mesh.report));
  return result;
}

// ---- Model properties --------------------------------------------------------------------------

std::string nameOf(Construction c) { return std::string(constructionName(c)); }

py::array modelPoints(const std::vector<glm::dvec3>& pts, int dims) {
  std::vector<double> v;
  v.reserve(pts.size() * size_t(dims));
  for (const auto& p : pts)
    for (int c = 0; c < dims; ++c) v.push_back(p[c]);
  return owned(std::move(v), {py::ssize_t(pts.size()), py::ssize_t(dims)});
}

py::array vecArray(std::vector<double> v) {
  const auto n = static_cast<py::ssize_t>(v.size());
  return owned(std::move(v), {n});
}

py::dict statsDict(const ResidentStats& s) {
  py::dict d;
  d["resident"] = s.resident;
  d["mirrors_built"] = s.mirrorsBuilt;
  d["net_bytes"] = s.upload.netBytes;
  d["net_writes"] = s.upload.netWrites;
  d["param_bytes"] = s.upload.paramBytes;
  d["param_writes"] = s.upload.paramWrites;
  d["vertex_passes"] = s.upload.vertexPasses;
  return d;
}

template <class Model>
void checkLambdaFamily(const Model& m) {
  const Construction c = m.model().family.construction;
  if (c == Construction::GUBP || c == Construction::BSpline) {
    throw ModelError("lambda", "", "'" + nameOf(c) + "' has no lambda (gubp: set_mu)");
  }
}

// Common properties and setters of both classes.
template <class Model, class Class>
void bindCommon(Class& cls) {
  using H = Handle<Model>;
  cls.def_property_readonly("construction", [](const H& h) { return nameOf(h.model()->model().family.construction); },
                            "The construction: extended_bspline, alpha_eb, gb, ubp, gubp or bspline.")
      .def_property_readonly("degree", [](const H& h) { return h.model()->model().family.degree; },
                             "Xu-Wang degree 4..6 (extended_bspline, alpha_eb), else 0.")
      .def_property_readonly("mu", [](const H& h) { return vecArray(h.model()->model().family.mu); },
                             "GUBP half vector mu_0..mu_floor(k/2) (empty for other constructions).")
      .def_property_readonly("alpha", [](const H& h) { return vecArray(h.model()->model().alpha); },
                             "alpha_eb tension per control point (row-major for surfaces); empty otherwise.")
      .def_property_readonly("uses_knot_vector", [](const H& h) { return h.model()->usesKnotVector(); },
                             "True for a bspline with a knot vector (the parameter is the knot parameter).")
      .def_property_readonly("item_count", [](const H& h) { return gridItems(*h.model()); },
                             "Items of a grid job: spans (curves) or patches (surfaces), in sample() order.")
      .def_property(
          "lambda_", [](const H& h) { return h.model()->model().family.lambda; },
          [](H& h, double v) {
            checkLambdaFamily(*h.model());
            h.change([&](auto& d) { d.family.lambda = v; }, [&](auto& mirror, int) { mirror.setLambda(v); });
          },
          "Global shape parameter lambda (setting it re-evaluates without re-uploading the net).")
      .def(
          "set_lambda",
          [](H& h, double v) {
            checkLambdaFamily(*h.model());
            h.change([&](auto& d) { d.family.lambda = v; }, [&](auto& mirror, int) { mirror.setLambda(v); });
          },
          py::arg("lambda_"), "Set lambda (ValueError naming 'lambda' when out of range; nothing changes then).")
      .def(
          "set_mu",
          [](H& h, py::object mu) {
            const std::vector<double> v = doubles(mu, "mu");
            if (h.model()->model().family.construction != Construction::GUBP) throw ModelError("mu", "", "only gubp has mu");
            FamilySpec f;
            h.change([&](auto& d) { d.family.mu = v, f = d.family; }, [&](auto& mirror, int) { mirror.setParameters(f); });
          },
          py::arg("mu"), "Set the GUBP half vector mu_0..mu_floor(k/2).")
      .def(
          "plan",
          [](const H& h, const std::string& device, const std::string& precision, bool require) {
            const auto request = deviceRequest(device, precision, require);
            py::gil_scoped_release release;
            return h.plan(request);
          },
          py::arg("device") = "auto", py::arg("precision") = "double", py::arg("require") = false,
          "The Report a job would get (device, precisions, fallbacks) without running it.")
      .def(
          "upload_stats",
          [](const H& h, const std::string& precision) { return statsDict(h.stats(parsePrecision(precision))); },
          py::arg("precision") = "float",
          "Upload counters of the resident GPU model of one precision: resident, mirrors_built (full net uploads), "
          "net_bytes, net_writes, param_bytes, param_writes, vertex_passes.")
      .def(
          "to_dict", [](const H& h) { return fromJson(io::toJson(H::K::dataOf(*h.model()))); },
          "The model as a dict with the keys of the model file format (docs/format.md).")
      .def(
          "save",
          [](const H& h, const std::string& path) {
            const std::string text = io::toJson(H::K::dataOf(*h.model())).dump(2) + "\n";
            py::module_::import("pathlib").attr("Path")(path).attr("write_text")(text);
          },
          py::arg("path"), "Write the model file (JSON).")
      .def(
          "copy", [](const H& h) { return std::make_shared<H>(*h.model()); },
          "An independent copy (no resident GPU model).")
      .def_property_readonly(
          "alpha_nodes", [](const H& h) { return points3(h.model()->alphaNodes(), Precision::Double); },
          "alpha_eb only: node_j = C_j(0) of the base curve/surface per vertex, (N, 3) (row-major for surfaces).")
      .def_property_readonly(
          "alpha_v", [](const H& h) { return points3(h.model()->alphaV(), Precision::Double); },
          "alpha_eb only: the V point of each vertex, (N, 3).");
}

}  // namespace

GridSpec parseSurfaceGrid(py::object grid) { return parseGrid<Surface>(grid, py::none()); }
FieldMask parseSurfaceFields(py::object fields) { return parseFields<Surface>(fields); }
std::vector<std::pair<std::string, Field>> surfaceFieldsOf(FieldMask mask) {
  std::vector<std::pair<std::string, Field>> out;
  for (const FieldName& f : fieldNames<Surface>())
    if (mask & fieldBit(f.field)) out.emplace_back(f.name, f.field);
  return out;
}

}  // namespace shapespline::python

PYBIND11_MODULE(shapespline, m) {
  using namespace shapespline;
  using namespace shapespline::python;
  m.doc() =
      "Shape-parametric spline curves and surfaces (Xu-Wang extended B-splines, alpha-EB, GB, UBP, GUBP, "
      "B-splines), sampled on a Vulkan GPU or the CPU fp64 path. See docs/python.md.";
  m.attr("__version__") = SHAPESPLINE_VERSION_STRING;
  m.attr("git_commit") = SHAPESPLINE_GIT_COMMIT;
  m.attr("__license__") = SHAPESPLINE_LICENSE;

  // ---- Exceptions ----
  static py::exception<ModelError> modelError(m, "ModelError", PyExc_ValueError);
  modelError.doc() = "A model or parameter that breaks a rule (a ValueError). Attributes: field, value, rule.";
  static py::exception<sampling::DeviceError> deviceError(m, "DeviceError", PyExc_RuntimeError);
  deviceError.doc() = "A Vulkan failure, or a fallback refused by require=True (a RuntimeError). Attribute: fallback_refused.";
  py::register_exception_translator([](std::exception_ptr p) {
    auto raise = [](py::object type, const std::string& what, auto&& attrs) {
      py::object e = type(what);
      attrs(e);
      PyErr_SetObject(type.ptr(), e.ptr());
    };
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ModelError& e) {
      raise(modelError, e.what(), [&](py::object& o) {
        o.attr("field") = e.field();
        o.attr("value") = e.value();
        o.attr("rule") = e.rule();
      });
    } catch (const sampling::DeviceError& e) {
      raise(deviceError, e.what(), [&](py::object& o) { o.attr("fallback_refused") = e.fallbackRefused(); });
    } catch (const vk::VulkanError& e) {
      raise(deviceError, e.what(), [&](py::object& o) { o.attr("fallback_refused") = false; });
    } catch (const sampling::QueryRangeError& e) {
      PyErr_SetString(PyExc_ValueError, ("params[" + std::to_string(e.index()) + "]: " + e.what()).c_str());
    } catch (const std::out_of_range& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  // ---- Report ----
  py::class_<sampling::Report>(m, "Report", "What a job did: the device, the computed and output precision, fallbacks.")
      .def_readonly("device", &sampling::Report::device, "'cpu' or the Vulkan device's name.")
      .def_readonly("gpu", &sampling::Report::gpu, "True when the GPU evaluated the job.")
      .def_property_readonly("computed_precision",
                             [](const sampling::Report& r) { return r.computedPrecision == Precision::Double ? "double" : "float"; })
      .def_property_readonly("output_precision",
                             [](const sampling::Report& r) { return r.outputPrecision == Precision::Double ? "double" : "float"; })
      .def_readonly("fallbacks", &sampling::Report::fallbacks, "Why the GPU was not used, in the order found.")
      .def_readonly("net_scale_exponent", &sampling::Report::netScaleExponent, "The job evaluated 2^k * net (either path) and scaled the results back.")
      .def_readonly("band_rows", &sampling::Report::bandRows,
                    "GPU grid of a net larger than one device buffer: patch rows per band (0: the whole net at once).")
      .def("__repr__", [](const sampling::Report& r) {
        std::string s = "Report(device='" + r.device + "', gpu=" + (r.gpu ? "True" : "False") + ", computed_precision='" +
                        (r.computedPrecision == Precision::Double ? "double" : "float") + "'";
        if (!r.fallbacks.empty()) s += ", fallbacks=" + std::to_string(r.fallbacks.size());
        return s + ")";
      });

  // ---- Chunk iterator ----
  py::class_<ChunkStream, std::shared_ptr<ChunkStream>>(
      m, "ChunkIterator", "Iterator over the chunks of a grid job (sample_chunks); a context manager.")
      .def("__iter__", [](std::shared_ptr<ChunkStream> s) { return s; })
      .def("__next__",
           [](ChunkStream& s) -> py::object {
             std::optional<ChunkData> d;
             {
               py::gil_scoped_release release;
               d = s.next();
             }
             if (!d) throw py::stop_iteration();
             return s.surface() ? chunkDict<Surface>(std::move(*d), s.fields(), s.precision())
                                : chunkDict<Curve>(std::move(*d), s.fields(), s.precision());
           })
      .def("close", [](ChunkStream& s) {
        py::gil_scoped_release release;
        s.close();
      }, "Cancel the job (the producer stops at its next chunk).")
      .def("__enter__", [](std::shared_ptr<ChunkStream> s) { return s; })
      .def("__exit__", [](ChunkStream& s, py::args) {
        py::gil_scoped_release release;
        s.close();
      })
      .def_property_readonly("report", [](const ChunkStream& s) -> py::object {
        auto r = s.report();
        return r ? py::cast(*r) : py::none();
      }, "The job's Report once the last chunk was produced, else None.");

  // ---- Curve ----
  CurveClass curve(m, "Curve", "A curve model (docs/format.md) with its CPU evaluator and, once used on the GPU, a resident GPU model.");
  curve
      .def(py::init([](py::object points, const std::string& construction, py::object degree, py::object order,
                       py::object lambda, py::object mu, py::object alpha, py::object closed, py::object knots,
                       py::object weights) {
             io::ModelArrays arrays;
             io::Model parsed = io::parseModel(
                 keywordModel("curve", points, construction, degree, order, lambda, mu, alpha, closed, knots, weights, arrays),
                 &arrays);
             return std::make_shared<CurveHandle>(Curve::create(std::get<CurveModel>(std::move(parsed))));
           }),
           py::arg("points"), py::kw_only(), py::arg("construction") = "extended_bspline", py::arg("degree") = py::none(),
           py::arg("order") = py::none(), py::arg("lambda_") = py::none(), py::arg("mu") = py::none(),
           py::arg("alpha") = py::none(), py::arg("closed") = py::none(), py::arg("knots") = py::none(),
           py::arg("weights") = py::none(),
           "Curve(points, *, construction, degree, order, lambda_, mu, alpha, closed, knots, weights): points (n, 2) "
           "or (n, 3); the other keywords are the model file's keys (alpha a scalar or one value per point; weights "
           "one positive value per point of a bspline with knots: a rational B-spline).")
      .def_static(
          "from_dict",
          [](py::dict d) {
            io::Model mm = parseDict(d);
            if (!std::holds_alternative<CurveModel>(mm)) throw ModelError("kind", "surface", "expected a curve");
            return std::make_shared<CurveHandle>(Curve::create(std::get<CurveModel>(std::move(mm))));
          },
          py::arg("model"), "A curve from a dict with the keys of a model file.")
      .def_property_readonly("kind", [](const CurveHandle&) { return "curve"; })
      .def_property_readonly("points", [](const CurveHandle& h) {
        const auto held = h.model();
        const Curve& c = *held;
        return modelPoints(c.model().points, c.dimension());
      }, "Control points (n, dimension).")
      .def_property_readonly("dimension", [](const CurveHandle& h) { return h.model()->dimension(); })
      .def_property_readonly("closed", [](const CurveHandle& h) { return h.model()->model().closed; })
      .def_property_readonly("order", [](const CurveHandle& h) { return h.model()->model().family.order; })
      .def_property_readonly("knots", [](const CurveHandle& h) { return vecArray(h.model()->model().knots); })
      .def_property_readonly("weights", [](const CurveHandle& h) { return vecArray(h.model()->model().weights); },
                             "Weights of a rational bspline (empty: not rational).")
      .def_property_readonly("spans", [](const CurveHandle& h) {
        const SpanRange s = h.model()->spans();
        return py::make_tuple(s.first, s.last);
      }, "Valid span indices (first, last), inclusive (knot-vector B-splines: knot interval indices).")
      .def_property_readonly("parameter_range", [](const CurveHandle& h) {
        const auto r = h.model()->parameterRange();
        return py::make_tuple(r.first, r.second);
      }, "(u_min, u_max) of the global parameter.")
      .def(
          "sample", &sample<Curve>, py::arg("grid") = py::none(), py::arg("samples") = py::none(), py::kw_only(),
          py::arg("fields") = py::none(), py::arg("device") = "auto", py::arg("precision") = "double",
          py::arg("require") = false, py::arg("first_item") = 0, py::arg("item_count") = 0, py::arg("chunk_points") = 0,
          py::arg("report") = false,
          "sample(samples=64, *, fields=('point',), device='auto', precision='double', ...) -> dict of arrays "
          "(items, samples, 3): S samples per span, t = s/(S-1).")
      .def(
          "sample_chunks",
          [](CurveHandle& h, py::object grid, py::object samples, py::object fields, const std::string& device,
             const std::string& precision, bool require, long long first, long long count, long long chunk,
             long long queue) {
            return sampleChunks(h, grid, samples, fields, device, precision, require, first, count, chunk, queue);
          },
          py::arg("grid") = py::none(), py::arg("samples") = py::none(), py::kw_only(), py::arg("fields") = py::none(),
          py::arg("device") = "auto", py::arg("precision") = "double", py::arg("require") = false,
          py::arg("first_item") = 0, py::arg("item_count") = 0, py::arg("chunk_points") = 0, py::arg("queue") = 2,
          "Iterator of chunk dicts (first_item, item_count, first_row, row_count, first_point, and an (n, 3) array per "
          "field), produced by a thread in bounded memory.")
      .def(
          "project",
          [](CurveHandle& h, py::handle points, int threads, std::optional<double> tolerance, const std::string& device,
             const std::string& precision, bool require) {
            const std::shared_ptr<const Curve> curve = h.model();
            const part::ProjectionTree tree = part::ProjectionTree::ofCurve(*curve);
            return projectPoints(tree, points, threads, tolerance, false, device, precision, require);
          },
          py::arg("points"), py::kw_only(), py::arg("threads") = 0, py::arg("tolerance") = py::none(),
          py::arg("device") = "cpu", py::arg("precision") = "double", py::arg("require") = false,
          "Closest points (docs/math.md §15): for each row of points (n, 3), the nearest point of the curve: a dict "
          "of point (n, 3), t (n,) and distance (n,), fp64, on the CPU (a GPU device is refused with require=True).")
      .def("evaluate", &curveEvaluate, py::arg("params") = py::none(), py::kw_only(), py::arg("span") = py::none(),
           py::arg("t") = py::none(), py::arg("device") = "auto", py::arg("precision") = "double",
           py::arg("require") = false, py::arg("report") = false, py::arg("fields") = py::none(),
           "evaluate(u) or evaluate(span=..., t=...) -> dict point, d1, d2 of shape (n, 3); derivatives w.r.t. the "
           "global parameter. fields: a name or names (the point is always in); 'point' and 'd1' alone run the "
           "lean list kernel.")
      .def(
          "set_alpha",
          [](CurveHandle& h, py::object value, py::object index) {
            if (h.model()->model().family.construction != Construction::AlphaEB) throw ModelError("alpha", "", "only alpha_eb has alpha");
            if (!index.is_none()) {
              const int i = index.cast<int>();
              const double a = value.cast<double>();
              const int n = int(h.model()->model().points.size());
              if (i < 0 || i >= n) argumentError("index", "must be in [0, " + std::to_string(n) + ")", std::to_string(i));
              h.change([&](CurveModel& d) { d.alpha[size_t(i)] = a; }, [&](gpu::GpuCurve& g, int) { g.setAlpha(i, a); });
              return;
            }
            std::vector<double> v = doubles(value, "alpha");
            const size_t n = h.model()->model().points.size();
            if (v.size() == 1) v.assign(n, v[0]);
            if (v.size() != n) argumentError("alpha", "needs one value per control point (" + std::to_string(n) + ")");
            h.change([&](CurveModel& d) { d.alpha = v; }, [&](gpu::GpuCurve& g, int) { g.setAlphas(v); });
          },
          py::arg("value"), py::arg("index") = py::none(),
          "Set alpha of one vertex (index) or of all (a scalar or one value per point).")
      .def(
          "set_control_point",
          [](CurveHandle& h, int i, py::object p) {
            const auto held = h.model();
            const Curve& c = *held;
            const int n = int(c.model().points.size());
            if (i < 0 || i >= n) argumentError("index", "must be in [0, " + std::to_string(n) + ")", std::to_string(i));
            const glm::dvec3 q = onePoint(p, "point", c.dimension());
            h.change([&](CurveModel& d) { d.points[size_t(i)] = q; },
                     [&](gpu::GpuCurve& g, int k) { g.updateControlPoint(i, {std::ldexp(q.x, k), std::ldexp(q.y, k), std::ldexp(q.z, k)}); });
          },
          py::arg("index"), py::arg("point"), "Move control point `index` (only the changed net entries are rewritten).")
      .def("__repr__", [](const CurveHandle& h) {
        const auto held = h.model();
        const Curve& c = *held;
        return "<shapespline.Curve " + nameOf(c.model().family.construction) + ", " +
               std::to_string(c.model().points.size()) + " points" + (c.model().closed ? ", closed" : "") + ">";
      });
  bindCommon<Curve>(curve);

  // ---- Surface ----
  SurfaceClass surface(m, "Surface", "A surface model (docs/format.md) with its CPU evaluator and, once used on the GPU, a resident GPU model.");
  surface
      .def(py::init([](py::object points, const std::string& construction, py::object degree, py::object order,
                       py::object lambda, py::object mu, py::object alpha, py::object closed, py::object knots,
                       py::object weights) {
             io::ModelArrays arrays;
             io::Model parsed = io::parseModel(
                 keywordModel("surface", points, construction, degree, order, lambda, mu, alpha, closed, knots, weights, arrays),
                 &arrays);
             return std::make_shared<SurfaceHandle>(Surface::create(std::get<SurfaceModel>(std::move(parsed))));
           }),
           py::arg("points"), py::kw_only(), py::arg("construction") = "extended_bspline", py::arg("degree") = py::none(),
           py::arg("order") = py::none(), py::arg("lambda_") = py::none(), py::arg("mu") = py::none(),
           py::arg("alpha") = py::none(), py::arg("closed") = py::none(), py::arg("knots") = py::none(),
           py::arg("weights") = py::none(),
           "Surface(points, *, ...): points (rows, cols, 3); closed a bool or (closed_u, closed_v); alpha a scalar or "
           "(rows, cols); order and knots per direction for bspline; weights (rows, cols) for a rational bspline.")
      .def_static(
          "from_dict",
          [](py::dict d) {
            io::Model mm = parseDict(d);
            if (!std::holds_alternative<SurfaceModel>(mm)) throw ModelError("kind", "curve", "expected a surface");
            return std::make_shared<SurfaceHandle>(Surface::create(std::get<SurfaceModel>(std::move(mm))));
          },
          py::arg("model"), "A surface from a dict with the keys of a model file.")
      .def_property_readonly("kind", [](const SurfaceHandle&) { return "surface"; })
      .def_property_readonly("points", [](const SurfaceHandle& h) {
        const auto held = h.model();
        const Surface& s = *held;
        py::array a = modelPoints(s.controlPoints(), 3);
        return a.attr("reshape")(s.model().rows, s.model().cols, 3);
      }, "Control net (rows, cols, 3).")
      .def_property_readonly("shape", [](const SurfaceHandle& h) {
        const auto held = h.model();
        const SurfaceShape& sm = held->model();
        return py::make_tuple(sm.rows, sm.cols);
      }, "(rows, cols) of the control net.")
      .def_property_readonly("closed", [](const SurfaceHandle& h) {
        const auto held = h.model();
        const SurfaceShape& sm = held->model();
        return py::make_tuple(sm.closedU, sm.closedV);
      })
      .def_property_readonly("order", [](const SurfaceHandle& h) {
        const auto held = h.model();
        const SurfaceShape& sm = held->model();
        return py::make_tuple(sm.family.order, sm.orderV ? sm.orderV : sm.family.order);
      })
      .def_property_readonly("knots", [](const SurfaceHandle& h) {
        const auto held = h.model();
        const SurfaceShape& sm = held->model();
        return py::make_tuple(vecArray(sm.knotsU), vecArray(sm.knotsV));
      })
      .def_property_readonly("patches", [](const SurfaceHandle& h) {
        const PatchRange p = h.model()->patches();
        return py::make_tuple(py::make_tuple(p.u.first, p.u.last), py::make_tuple(p.v.first, p.v.last));
      }, "((first_u, last_u), (first_v, last_v)) valid patch indices, inclusive.")
      .def_property_readonly("parameter_range", [](const SurfaceHandle& h) {
        const auto held = h.model();
        const Surface& s = *held;
        const auto u = s.parameterRangeU(), v = s.parameterRangeV();
        return py::make_tuple(py::make_tuple(u.first, u.second), py::make_tuple(v.first, v.second));
      }, "((U_min, U_max), (V_min, V_max)).")
      .def(
          "sample",
          [](SurfaceHandle& h, py::object grid, py::object samples, py::object fields, const std::string& device,
             const std::string& precision, bool require, long long first, long long count, long long chunk, bool rep) {
            return sample(h, grid, samples, fields, device, precision, require, first, count, chunk, rep);
          },
          py::arg("grid") = py::none(), py::arg("samples") = py::none(), py::kw_only(), py::arg("fields") = py::none(),
          py::arg("device") = "auto", py::arg("precision") = "double", py::arg("require") = false,
          py::arg("first_item") = 0, py::arg("item_count") = 0, py::arg("chunk_points") = 0, py::arg("report") = false,
          "sample(grid=(16, 16), *, fields=('point',), ...) -> dict of arrays (patches, Su, Sv, 3), patches "
          "row-major (u outer), u_a = a/(Su-1), v_b = b/(Sv-1).")
      .def(
          "sample_chunks",
          [](SurfaceHandle& h, py::object grid, py::object samples, py::object fields, const std::string& device,
             const std::string& precision, bool require, long long first, long long count, long long chunk,
             long long queue) {
            auto s = sampleChunks(h, grid, samples, fields, device, precision, require, first, count, chunk, queue);
            py::object o = py::cast(s);
            return o;
          },
          py::arg("grid") = py::none(), py::arg("samples") = py::none(), py::kw_only(), py::arg("fields") = py::none(),
          py::arg("device") = "auto", py::arg("precision") = "double", py::arg("require") = false,
          py::arg("first_item") = 0, py::arg("item_count") = 0, py::arg("chunk_points") = 0, py::arg("queue") = 2,
          "Iterator of chunk dicts, as Curve.sample_chunks.")
      .def("evaluate", &surfaceEvaluate, py::arg("params") = py::none(), py::kw_only(), py::arg("patch") = py::none(),
           py::arg("uv") = py::none(), py::arg("device") = "auto", py::arg("precision") = "double",
           py::arg("require") = false, py::arg("report") = false, py::arg("fields") = py::none(),
           "evaluate((n, 2) global (U, V)) or evaluate(patch=(n, 2), uv=(n, 2)) -> dict point, du, dv, duu, duv, dvv, "
           "normal of shape (n, 3). fields: a name or names (the point is always in); 'point', 'du' and 'dv' alone "
           "run the lean list kernel.")
      .def(
          "project",
          [](SurfaceHandle& h, py::handle points, int threads, std::optional<double> tolerance, const std::string& device,
             const std::string& precision, bool require) {
            const std::shared_ptr<const Surface> surface = h.model();
            const part::ProjectionTree tree = part::ProjectionTree::ofFaces({{surface.get(), 0, false}});
            return projectPoints(tree, points, threads, tolerance, false, device, precision, require);
          },
          py::arg("points"), py::kw_only(), py::arg("threads") = 0, py::arg("tolerance") = py::none(),
          py::arg("device") = "cpu", py::arg("precision") = "double", py::arg("require") = false,
          "Closest points (docs/math.md §15): for each row of points (n, 3), the nearest point of the surface "
          "(inside its trim loops, if it has any): a dict of point (n, 3), uv (n, 2) (global U, V), distance (n,), "
          "signed_distance (n,) (the side of the normal) and normal (n, 3); fp64 on the CPU by default, device='auto' or "
          "'vulkan': the search on the GPU in precision, each foot finished on the CPU.")
      .def("tessellate", &tessellate, py::arg("rate") = 8, py::kw_only(), py::arg("device") = "auto",
           py::arg("precision") = "float", py::arg("require") = false, py::arg("report") = false,
           "Watertight triangle mesh: (vertices (V, 8) float32 [x y z nx ny nz U V], indices (T, 3) uint32).")
      .def(
          "set_alpha",
          [](SurfaceHandle& h, py::object value, py::object index) {
            const auto held = h.model();
            const SurfaceShape& sm = held->model();
            if (sm.family.construction != Construction::AlphaEB) throw ModelError("alpha", "", "only alpha_eb has alpha");
            if (!index.is_none()) {
              const auto ij = index.cast<std::pair<int, int>>();
              const double a = value.cast<double>();
              if (ij.first < 0 || ij.first >= sm.rows || ij.second < 0 || ij.second >= sm.cols) {
                argumentError("index", "must be (i, j) inside the " + std::to_string(sm.rows) + " x " + std::to_string(sm.cols) + " net");
              }
              h.change([&](SurfaceModel& d) { d.alpha[size_t(ij.first) * d.cols + ij.second] = a; },
                       [&](gpu::GpuSurface& g, int) { g.setAlpha(ij.first, ij.second, a); });
              return;
            }
            DArray arr = asArray(value, "alpha");
            std::vector<double> v(arr.data(), arr.data() + arr.size());
            const size_t n = size_t(sm.rows) * sm.cols;
            if (v.size() == 1) v.assign(n, v[0]);
            if (v.size() != n) argumentError("alpha", "needs a scalar or (rows, cols) values");
            h.change([&](SurfaceModel& d) { d.alpha = v; }, [&](gpu::GpuSurface& g, int) { g.setAlphas(v); });
          },
          py::arg("value"), py::arg("index") = py::none(),
          "Set alpha of one vertex (index=(i, j)) or of all (a scalar or a (rows, cols) array).")
      .def(
          "set_control_point",
          [](SurfaceHandle& h, int i, int j, py::object p) {
            const auto held = h.model();
            const SurfaceShape& sm = held->model();
            if (i < 0 || i >= sm.rows || j < 0 || j >= sm.cols) {
              argumentError("index", "must be (i, j) inside the " + std::to_string(sm.rows) + " x " + std::to_string(sm.cols) + " net");
            }
            const glm::dvec3 q = onePoint(p, "point", 3);
            h.change([&](SurfaceModel& d) { d.points[size_t(i) * d.cols + j] = q; },
                     [&](gpu::GpuSurface& g, int k) {
                       g.updateControlPoint(i, j, {std::ldexp(q.x, k), std::ldexp(q.y, k), std::ldexp(q.z, k)});
                     });
          },
          py::arg("i"), py::arg("j"), py::arg("point"), "Move control point (i, j).")
      .def("__repr__", [](const SurfaceHandle& h) {
        const auto held = h.model();
        const SurfaceShape& sm = held->model();
        return "<shapespline.Surface " + nameOf(sm.family.construction) + ", " +
               std::to_string(sm.rows) + " x " + std::to_string(sm.cols) + " points>";
      });
  bindCommon<Surface>(surface);

  // ---- Module functions ----
  m.def("load", [](const std::string& path) { return wrap(loadPath(path)); }, py::arg("path"),
        "A Curve or Surface from a model file (docs/format.md).");
  m.def("from_dict", [](py::dict d) { return wrap(parseDict(d)); }, py::arg("model"),
        "A Curve or Surface from a dict with the keys of a model file.");
  m.def("sample_many", &sampleMany, py::arg("models"), py::arg("grid") = py::none(), py::kw_only(),
        py::arg("fields") = py::none(), py::arg("device") = "auto", py::arg("precision") = "double",
        py::arg("require") = false, py::arg("errors") = "raise", py::arg("report") = false,
        "sample_many(models, grid=None, *, fields, device, precision, require, errors='raise', report=False) -> list "
        "of sample() dicts, one per model (a Curve, Surface, dict or model file path), all through one device and its "
        "compiled pipelines. errors='keep' puts a failing model's exception in its place and samples the others.");
  m.def("devices", [] {
    py::gil_scoped_release release;
    return sampling::describeDevices();
  }, "The Vulkan devices, the one a job would use, fp64 support and limits (as `shapespline info`).");

  bindTools(m, curve, surface);
  bindPart(m);
}
