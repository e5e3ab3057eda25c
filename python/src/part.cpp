// `shapespline.load_part(DIR)`: a part `shapespline import` wrote, its watertight mesh and its
// trimmed point cloud as NumPy arrays (host/part; docs/python.md "Parts", docs/cad.md "Meshing a
// part" and "Sampling a part"). The mesh's surface points go through the module's session on the
// device asked for, or core's fp64 list kernel; the point cloud is each face's grid job, the
// samples outside its trim loops left out, as `sample part.json -o cloud.npy` writes it.
#include "convert.h"
#include "handle.h"
#include "project.h"
#include "surface_args.h"

#include <shapespline/io/sample_writer.h>
#include <shapespline/io/trimmed_points.h>

#include <shapespline/part/face_evaluator.h>
#include <shapespline/part/face_triangulation.h>
#include <shapespline/part/part_mesher.h>
#include <shapespline/part/part_model.h>

#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>

namespace shapespline::python {
namespace {

struct PartHandle {
  std::filesystem::path dir;
  part::Part part;
  // The projection tree, built at the first project() (the part never changes).
  std::once_flag treeBuilt;
  std::unique_ptr<part::ProjectionTree> tree;
};

double positiveArgument(py::object value, const std::string& name, const std::string& unit) {
  const double v = py::cast<double>(value);
  if (!std::isfinite(v) || !(v > 0.0)) argumentError(name, "must be a finite number > 0 (" + unit + ")", py::str(value));
  return v;
}

py::dict meshOf(const PartHandle& h, py::object deflection, py::object relative, double angle, long long maxTriangles,
                const std::string& device, const std::string& precision, bool require, int threads, bool withReport) {
  if (!deflection.is_none() && !relative.is_none())
    argumentError("deflection", "give deflection (model units) or relative_deflection (of the diagonal), not both");
  const double diagonal = part::partDiagonal(h.part);
  part::MeshOptions options;
  options.deflection = deflection.is_none()
                           ? (relative.is_none() ? 1e-3 : positiveArgument(relative, "relative_deflection", "of the diagonal")) *
                                 diagonal
                           : positiveArgument(deflection, "deflection", "model units");
  if (!(options.deflection > 0.0)) argumentError("relative_deflection", "the part has no extent to take a fraction of");
  if (!std::isfinite(angle) || !(angle > 0.0) || angle >= std::numbers::pi)
    argumentError("angle", "must be a finite number in (0, pi) (radians)", std::to_string(angle));
  if (maxTriangles <= 0) argumentError("max_triangles", "must be > 0", std::to_string(maxTriangles));
  if (threads < 0) argumentError("threads", "must be >= 0 (0 = one per CPU)", std::to_string(threads));
  options.angle = angle;
  options.maxTriangles = maxTriangles;
  options.threads = threads;

  const sampling::DeviceRequest request = part::meshDeviceRequest(deviceRequest(device, precision, require));
  const sampling::Report report = plan(h.part.faces.front().surface, request);
  part::PartMesh mesh;
  {
    // Part meshes take turns on the module's session; the CPU path needs no lock.
    static std::mutex deviceTurn;
    py::gil_scoped_release release;
    try {
      if (report.gpu) {
        std::lock_guard turn(deviceTurn);
        part::SessionFaceEvaluator evaluator(session(), request, report.device);
        mesh = part::meshPart(h.part, options, evaluator);
      } else {
        part::CpuFaceEvaluator evaluator;
        mesh = part::meshPart(h.part, options, evaluator);
      }
    } catch (const part::TriangleBudgetExceeded& e) {
      py::gil_scoped_acquire acquire;
      argumentError(deflection.is_none() ? "relative_deflection" : "deflection",
                    std::string(e.what()) + "; raise the deflection or max_triangles");
    }
  }
  const io::TriangleMesh& m = mesh.mesh;
  const auto n = static_cast<py::ssize_t>(m.positions.size()), t = static_cast<py::ssize_t>(m.triangles.size());
  std::vector<double> positions, normals;
  positions.reserve(m.positions.size() * 3);
  normals.reserve(m.normals.size() * 3);
  for (const glm::dvec3& p : m.positions) positions.insert(positions.end(), {p.x, p.y, p.z});
  for (const glm::dvec3& p : m.normals) normals.insert(normals.end(), {p.x, p.y, p.z});
  std::vector<uint32_t> triangles;
  triangles.reserve(m.triangles.size() * 3);
  for (const auto& tri : m.triangles) triangles.insert(triangles.end(), tri.begin(), tri.end());
  std::vector<int32_t> faceIds(m.faceIds.begin(), m.faceIds.end());
  py::dict out;
  out["positions"] = owned(std::move(positions), {n, 3});
  out["normals"] = owned(std::move(normals), {n, 3});
  out["triangles"] = owned(std::move(triangles), {t, 3});
  out["face_ids"] = owned(std::move(faceIds), {t});
  out["open_edges"] = mesh.boundaryEdges;
  out["non_manifold_edges"] = mesh.nonManifoldEdges;
  out["deflection"] = options.deflection;
  out["device"] = report.gpu ? report.device : std::string("cpu");
  if (withReport) out["report"] = py::cast(report);
  return out;
}

// Every face's grid, only the samples inside its trim loops: their (U, V), face id and fields.
py::object sampleOf(const PartHandle& h, py::object grid, py::object fields, const std::string& device,
                    const std::string& precision, bool require, bool withReport) {
  GridSpec spec = parseSurfaceGrid(grid);
  const std::vector<std::pair<std::string, Field>> wanted = surfaceFieldsOf(parseSurfaceFields(fields));
  FieldMask mask = 0;
  for (const auto& [name, field] : wanted) mask |= fieldBit(field);
  sampling::DeviceRequest request = deviceRequest(device, precision, require);
  request.grid = true;
  // Each face's items, and the samples each keeps: the arrays are sized before anything is sampled.
  std::vector<io::SampleLayout> layouts(h.part.faces.size());
  uint64_t total = 0, gridPoints = 0;
  for (size_t f = 0; f < h.part.faces.size(); ++f) {
    io::SampleLayout& layout = layouts[f];
    layout.surface = true;
    layout.samplesU = spec.samplesU;
    layout.samplesV = spec.samplesV;
    io::setSurfaceItems(h.part.faces[f].surface.model(), layout);
    layout.itemCount = layout.totalItems;
    for (uint64_t kept : io::samplesInsideByItem(layout, h.part.faces[f].surface.model().trim)) total += kept;
    gridPoints += layout.pointCount();
  }
  if (gridPoints > (uint64_t{1} << 40) / 24) argumentError("grid", "the part's grids are too large for arrays in memory");
  const auto n = static_cast<py::ssize_t>(total);
  const bool dbl = request.precision == Precision::Double;
  py::array_t<double> uv({n, py::ssize_t(2)});
  py::array_t<int32_t> faceIds({n});
  std::vector<std::pair<Field, void*>> planes;
  py::dict out;
  out["uv"] = uv;
  out["face_ids"] = faceIds;
  for (const auto& [name, field] : wanted) {
    py::array a = dbl ? py::array(py::array_t<double>({n, py::ssize_t(3)})) : py::array(py::array_t<float>({n, py::ssize_t(3)}));
    planes.emplace_back(field, a.mutable_data());
    out[name.c_str()] = a;
  }
  double* uvOut = uv.mutable_data();
  int32_t* faceOut = faceIds.mutable_data();
  sampling::Report report;
  {
    py::gil_scoped_release release;
    report = plan(h.part.faces.front().surface, request);
    uint64_t next = 0;
    for (size_t f = 0; f < h.part.faces.size(); ++f) {
      const part::PartFace& face = h.part.faces[f];
      const io::SampleLayout& layout = layouts[f];
      const TrimClassifier inside(face.surface.model().trim);
      GridSpec g = spec;
      g.firstItem = 0;
      g.itemCount = layout.totalItems;
      // Chunks come in item order, so the records keep the grid's order, face after face.
      session().sampleGrid(face.surface, request, g, mask, [&](const GridChunk& c) {
        for (size_t p = 0; p < c.pointCount(); ++p) {
          const size_t in = c.pointInItem(p), sv = static_cast<size_t>(layout.samplesV);
          const auto [u, v] = layout.parameter(c.itemOf(p), static_cast<int>(in / sv), static_cast<int>(in % sv));
          if (!inside.inside({u, v})) continue;
          if (next == total) throw std::logic_error("Part.sample: more samples inside than counted");
          uvOut[2 * next] = u;
          uvOut[2 * next + 1] = v;
          faceOut[next] = face.id;
          for (const auto& [field, dst] : planes)
            for (int k = 0; k < 3; ++k) {
              const double x = c.coord(field, p, k);
              if (dbl) static_cast<double*>(dst)[3 * next + size_t(k)] = x;
              else static_cast<float*>(dst)[3 * next + size_t(k)] = static_cast<float>(x);
            }
          ++next;
        }
      });
    }
    if (next != total) throw std::logic_error("Part.sample: fewer samples inside than counted");
  }
  if (withReport) return py::make_tuple(out, py::cast(report));
  return out;
}

}  // namespace

void bindPart(py::module_& m) {
  py::class_<PartHandle, std::shared_ptr<PartHandle>>(
      m, "Part", "A part `shapespline import` wrote (DIR/part.json): its faces, edges and shells, and its mesh.")
      .def_property_readonly("faces", [](const PartHandle& h) {
        std::vector<int> ids;
        for (const auto& f : h.part.faces) ids.push_back(f.id);
        return ids;
      }, "The ids of the faces that imported, in the manifest's order.")
      .def_property_readonly("edges", [](const PartHandle& h) { return h.part.edges.size(); }, "How many edges the part has.")
      .def_property_readonly("skipped", [](const PartHandle& h) { return h.part.skipped; },
                             "How many faces did not convert at import (part.json says why).")
      .def_property_readonly("diagonal", [](const PartHandle& h) { return part::partDiagonal(h.part); },
                             "The diagonal of the box around every face's control points (relative deflections are of it).")
      .def("mesh", &meshOf, py::kw_only(), py::arg("deflection") = py::none(), py::arg("relative_deflection") = py::none(),
           py::arg("angle") = 0.5, py::arg("max_triangles") = part::kDefaultTriangleBudget, py::arg("device") = "auto",
           py::arg("precision") = "double", py::arg("require") = false, py::arg("threads") = 0,
           py::arg("with_report") = false,
           "The part's watertight mesh (docs/cad.md 'Meshing a part'): a dict of positions (N, 3) float64, normals "
           "(N, 3), triangles (M, 3) uint32, face_ids (M,) int32, open_edges, non_manifold_edges, deflection and "
           "device. deflection in model units, or relative_deflection of the diagonal (default 1e-3); angle in "
           "radians; a mesh needing more than max_triangles raises ValueError.")
      .def("sample", &sampleOf, py::arg("grid") = py::none(), py::kw_only(), py::arg("fields") = py::none(),
           py::arg("device") = "auto", py::arg("precision") = "double", py::arg("require") = false,
           py::arg("report") = false,
           "The part's point cloud (docs/cad.md 'Sampling a part'): each face's grid (grid=N or (Su, Sv) samples per "
           "patch, default 16) with only the samples inside its trim loops, face after face in the manifest's "
           "order: a dict of uv (K, 2) float64 (the face's knot parameters), face_ids (K,) int32 and each field "
           "(K, 3) ('point' by default; float32 with precision='float'). report=True: (dict, Report).")
      .def(
          "project",
          [](PartHandle& h, py::handle points, int threads, std::optional<double> tolerance, const std::string& device,
             const std::string& precision, bool require) {
            std::call_once(h.treeBuilt, [&] { h.tree = std::make_unique<part::ProjectionTree>(part::ProjectionTree::ofPart(h.part)); });
            return projectPoints(*h.tree, points, threads, tolerance, true, device, precision, require);
          },
          py::arg("points"), py::kw_only(), py::arg("threads") = 0, py::arg("tolerance") = py::none(),
          py::arg("device") = "cpu", py::arg("precision") = "double", py::arg("require") = false,
          "Closest points (docs/math.md §15): for each row of points (n, 3), the nearest point of the part's faces "
          "inside their trim loops: a dict of point (n, 3), uv (n, 2), face_ids (n,) int32, distance (n,), "
          "signed_distance (n,) (outside positive on a closed part) and normal (n, 3); fp64 on the CPU by default, "
          "device='auto' or 'vulkan': the search on the GPU in precision, each foot finished on the CPU.")
      .def("__repr__", [](const PartHandle& h) {
        return "<shapespline.Part " + h.dir.string() + ": " + std::to_string(h.part.faces.size()) + " faces, " +
               std::to_string(h.part.edges.size()) + " edges>";
      });
  m.def(
      "load_part",
      [](const std::string& dir) {
        std::filesystem::path path(dir);
        if (std::filesystem::is_directory(path)) path /= "part.json";
        auto h = std::make_shared<PartHandle>();
        h->dir = path.parent_path();
        h->part = part::loadPart(path);
        if (h->part.faces.empty()) argumentError("dir", "the part has no converted faces", dir);
        return h;
      },
      py::arg("dir"), "A part `shapespline import` wrote: DIR (or DIR/part.json).");
}

}  // namespace shapespline::python
