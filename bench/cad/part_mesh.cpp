// Part meshes against Open CASCADE's BRepMesh_IncrementalMesh (issue 54): the bench's own parts
// (tests/cad/test_parts: a filleted box, a drilled plate, a free-form face) or any STEP/IGES files
// given, meshed at the same deflection D (a fraction of the part's diagonal) and angle by
//   * BRepMesh (InParallel) on the shape as the reader gives it,
//   * shapespline's part mesher (host/part) on the imported part, its points from the CPU fp64 path
//     and from a Vulkan device (first call, then warm; and a re-mesh at D / 2, the renderer's case),
// best of REPS wall-clock runs after one untimed run, in one process. Each mesh is welded (BRepMesh's
// face triangulations by their nodes' positions, as users weld them) and reports its triangles,
// open edges and the largest distance from the exact surface at triangle centroids and edge
// midpoints, projected with GeomAPI_ProjectPointOnSurf (every triangle up to 4,000 per part, then
// evenly spread). Also the file's read (OCCT), `import` and loading the imported part, and the end to
// end (import + load + mesh against OCCT's read + BRepMesh). Prints a table
// and writes --json FILE. Usage: shapespline_part_mesh_bench [--relative D] [--angle A] [--reps N]
// [--json FILE] [--no-gpu] [PART.step ...]
#include <shapespline/part/face_evaluator.h>
#include <shapespline/part/part_mesher.h>
#include <shapespline/part/part_model.h>
#include <shapespline/sampling/session.h>

#include "bench_parts.h"
#include "bench_run.h"

#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/part_import.h>

#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <span>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

namespace {

using namespace shapespline;
namespace fs = std::filesystem;

using bench::seconds;

struct Triangle {
  std::array<glm::dvec3, 3> corners;
  int face;  // 1-based, TopExp::MapShapes order (the ids `import` gives)
};

struct MeshFigures {
  double seconds = 0.0;
  size_t triangles = 0;
  size_t openEdges = 0;
  double deviation = 0.0;  // largest measured distance, in units of D
};

// Open edges after welding the triangles' corners by position (cells of `weld`).
size_t openEdgesAfterWelding(const std::vector<Triangle>& triangles, double weld) {
  std::map<std::array<int64_t, 3>, uint32_t> ids;
  const auto id = [&](glm::dvec3 p) {
    const glm::dvec3 c = glm::round(p / weld);
    return ids.try_emplace({int64_t(c.x), int64_t(c.y), int64_t(c.z)}, uint32_t(ids.size())).first->second;
  };
  std::map<std::pair<uint32_t, uint32_t>, int> uses;
  for (const Triangle& t : triangles) {
    const uint32_t v[3] = {id(t.corners[0]), id(t.corners[1]), id(t.corners[2])};
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(v[k], v[(k + 1) % 3])];
  }
  size_t open = 0;
  for (const auto& [edge, n] : uses) open += n == 1;
  return open;
}

// The largest distance of centroids and edge midpoints from their face's OCCT surface.
double largestDeviation(const std::vector<Triangle>& triangles, const TopTools_IndexedMapOfShape& faces) {
  const size_t step = std::max<size_t>(1, triangles.size() / 4000);
  double worst = 0.0;
  for (size_t k = 0; k < triangles.size(); k += step) {
    const Triangle& t = triangles[k];
    const Handle(Geom_Surface) surface = BRep_Tool::Surface(TopoDS::Face(faces(t.face)));
    const auto& [a, b, c] = t.corners;
    for (const glm::dvec3 q : {(a + b + c) / 3.0, (a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0}) {
      GeomAPI_ProjectPointOnSurf projection(gp_Pnt(q.x, q.y, q.z), surface);
      if (projection.NbPoints() > 0) worst = std::max(worst, projection.LowerDistance());
    }
  }
  return worst;
}

std::vector<Triangle> brepMeshTriangles(const TopTools_IndexedMapOfShape& faces) {
  std::vector<Triangle> out;
  for (int f = 1; f <= faces.Extent(); ++f) {
    const TopoDS_Face& face = TopoDS::Face(faces(f));
    TopLoc_Location location;
    const Handle(Poly_Triangulation) mesh = BRep_Tool::Triangulation(face, location);
    if (mesh.IsNull()) continue;
    const gp_Trsf placement = location.Transformation();
    for (int t = 1; t <= mesh->NbTriangles(); ++t) {
      int n[3];
      mesh->Triangle(t).Get(n[0], n[1], n[2]);
      Triangle tri{{}, f};
      for (int k = 0; k < 3; ++k) {
        const gp_Pnt p = mesh->Node(n[k]).Transformed(placement);
        tri.corners[size_t(k)] = {p.X(), p.Y(), p.Z()};
      }
      out.push_back(tri);
    }
  }
  return out;
}

std::vector<Triangle> partMeshTriangles(const part::PartMesh& mesh) {
  std::vector<Triangle> out;
  out.reserve(mesh.mesh.triangles.size());
  for (size_t k = 0; k < mesh.mesh.triangles.size(); ++k) {
    const auto& t = mesh.mesh.triangles[k];
    out.push_back({{mesh.mesh.positions[t[0]], mesh.mesh.positions[t[1]], mesh.mesh.positions[t[2]]}, mesh.mesh.faceIds[k]});
  }
  return out;
}

// Counts the lists an evaluator is given (the device's calls) and their points.
class CountingEvaluator final : public part::FaceEvaluator {
 public:
  explicit CountingEvaluator(part::FaceEvaluator& inner) : inner_(inner) {}
  void evaluate(const Surface& face, std::span<const glm::dvec2> uv, std::span<SurfaceFirst> out) override {
    ++lists;
    points += uv.size();
    inner_.evaluate(face, uv, out);
  }
  std::string device() const override { return inner_.device(); }
  std::atomic<size_t> lists{0}, points{0};

 private:
  part::FaceEvaluator& inner_;
};

struct Options {
  double relative = 1e-3, angle = 0.5;
  int reps = 3;
  bool gpu = true;
  std::string json;
  std::vector<fs::path> parts;
};

nlohmann::json figuresJson(const MeshFigures& m) {
  return {{"seconds", m.seconds}, {"triangles", m.triangles}, {"open_edges", m.openEdges}, {"deviation_of_d", m.deviation}};
}

void printRow(const std::string& what, const MeshFigures& m, double peer) {
  std::printf("  %-28s %9.4f s  %8.2fx  %8zu triangles  %6zu open edges  deviation %.3f D\n", what.c_str(), m.seconds,
              peer / m.seconds, m.triangles, m.openEdges, m.deviation);
}

nlohmann::json benchPart(const std::string& name, const fs::path& file, const Options& o, const fs::path& scratch) {
  nlohmann::json row = {{"part", name}, {"file", file.string()}};
  cad::PartShape shape;
  row["occt_read_seconds"] = seconds([&] { shape = cad::readPart(file, std::uint64_t{1} << 32); });
  const fs::path dir = scratch / name;
  fs::remove_all(dir);
  row["import_seconds"] = seconds([&] { cad::importPart(file, dir); });
  std::optional<part::Part> loaded;
  row["load_seconds"] = seconds([&] { loaded.emplace(part::loadPart(dir / "part.json")); });
  const part::Part& p = *loaded;
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape.shape, TopAbs_FACE, faces);
  const double diagonal = part::partDiagonal(p), d = o.relative * diagonal;
  row.update({{"faces", faces.Extent()}, {"diagonal", diagonal}, {"deflection", d}, {"angle", o.angle}});
  const double weld = 1e-9 * diagonal;

  MeshFigures occt;
  occt.seconds = bench::bestSeconds(o.reps, [&] {
    BRepTools::Clean(shape.shape);
    BRepMesh_IncrementalMesh(shape.shape, d, false, o.angle, true);
  });
  const std::vector<Triangle> occtTriangles = brepMeshTriangles(faces);
  occt.triangles = occtTriangles.size();
  occt.openEdges = openEdgesAfterWelding(occtTriangles, weld);
  occt.deviation = largestDeviation(occtTriangles, faces) / d;

  part::MeshOptions options;
  options.deflection = d;
  options.angle = o.angle;
  options.threads = 0;
  const auto figures = [&](const part::PartMesh& mesh, double time) {
    MeshFigures m;
    m.seconds = time;
    const std::vector<Triangle> triangles = partMeshTriangles(mesh);
    m.triangles = triangles.size();
    m.openEdges = openEdgesAfterWelding(triangles, weld);
    m.deviation = largestDeviation(triangles, faces) / d;
    return m;
  };
  part::CpuFaceEvaluator cpu;
  part::PartMesh cpuMesh;
  const MeshFigures ours = figures(cpuMesh, bench::bestSeconds(o.reps, [&] { cpuMesh = part::meshPart(p, options, cpu); }));

  std::printf("%s: %d faces, D = %.4g (%.0e of the diagonal %.4g), angle %.2f; read %.3f s, import %.3f s, load %.3f s\n",
              name.c_str(), faces.Extent(), d, o.relative, diagonal, o.angle, row["occt_read_seconds"].get<double>(),
              row["import_seconds"].get<double>(), row["load_seconds"].get<double>());
  printRow("BRepMesh (InParallel)", occt, occt.seconds);
  printRow("shapespline CPU fp64", ours, occt.seconds);
  row["brepmesh"] = figuresJson(occt);
  row["shapespline_cpu"] = figuresJson(ours);
  // A user's STEP file to a mesh: import, load and mesh, against OCCT's read and BRepMesh.
  const double ourEndToEnd = row["import_seconds"].get<double>() + row["load_seconds"].get<double>() + ours.seconds;
  const double occtEndToEnd = row["occt_read_seconds"].get<double>() + occt.seconds;
  row["end_to_end_seconds"] = ourEndToEnd;
  row["occt_end_to_end_seconds"] = occtEndToEnd;
  std::printf("  %-28s %9.4f s  %8.2fx  (OCCT read + BRepMesh: %.4f s)\n", "end to end: import+load+mesh", ourEndToEnd,
              occtEndToEnd / ourEndToEnd, occtEndToEnd);

  if (o.gpu) {
    sampling::Session session;
    const sampling::DeviceRequest request{sampling::DeviceKind::Vulkan, shapespline::Precision::Double, false};
    const sampling::Report report = session.plan(p.faces.front().surface, request);
    if (report.gpu) {
      part::SessionFaceEvaluator device(session, request, report.device);
      part::PartMesh gpuMesh;
      CountingEvaluator counted(device);
      const double first = seconds([&] { gpuMesh = part::meshPart(p, options, counted); });
      const MeshFigures warm = figures(gpuMesh, bench::bestSeconds(o.reps, [&] { gpuMesh = part::meshPart(p, options, device); }));
      part::MeshOptions finer = options;
      finer.deflection = d / 2;
      const double remesh = bench::bestSeconds(o.reps, [&] { part::meshPart(p, finer, device); });
      const double occtRemesh = bench::bestSeconds(o.reps, [&] {
        BRepTools::Clean(shape.shape);
        BRepMesh_IncrementalMesh(shape.shape, d / 2, false, o.angle, true);
      });
      MeshFigures firstCall = warm;
      firstCall.seconds = first;
      printRow("Vulkan fp64, first call", firstCall, occt.seconds);
      printRow("Vulkan fp64, warm", warm, occt.seconds);
      std::printf("  %-28s %9.4f s  %8.2fx  (BRepMesh at D/2: %.4f s)\n", "Vulkan warm, re-mesh at D/2", remesh,
                  occtRemesh / remesh, occtRemesh);
      std::printf("  %zu lists of %.0f points on average per mesh: %.2f ms a list, warm\n", counted.lists.load(),
                  double(counted.points.load()) / double(counted.lists.load()), 1e3 * warm.seconds / double(counted.lists.load()));
      std::printf("  device: %s; same topology as the CPU: %s\n", report.device.c_str(),
                  gpuMesh.mesh.triangles == cpuMesh.mesh.triangles ? "yes" : "no");
      row["vulkan"] = figuresJson(warm);
      row["vulkan"]["first_call_seconds"] = first;
      row["vulkan"]["remesh_half_d_seconds"] = remesh;
      row["brepmesh"]["half_d_seconds"] = occtRemesh;
      row["vulkan"]["device"] = report.device;
      row["vulkan"]["lists_per_mesh"] = counted.lists.load();
      row["vulkan"]["same_topology_as_cpu"] = gpuMesh.mesh.triangles == cpuMesh.mesh.triangles;
    } else {
      std::printf("  Vulkan: no device (%s)\n", report.fallbacks.empty() ? "" : report.fallbacks.front().c_str());
    }
  }
  return row;
}

Options parse(int argc, char** argv) {
  Options o;
  o.parts = bench::parseArguments(argc, argv, [&](const std::string& a, const bench::OptionValue& value) {
    if (a == "--relative") o.relative = std::stod(value());
    else if (a == "--angle") o.angle = std::stod(value());
    else if (a == "--reps") o.reps = std::stoi(value());
    else if (a == "--json") o.json = value();
    else if (a == "--no-gpu") o.gpu = false;
    else return false;
    return true;
  });
  if (!(o.relative > 0.0) || !(o.angle > 0.0) || o.reps < 1) throw std::invalid_argument("bad --relative, --angle or --reps");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    cad::initOcctControllers();
    std::printf("part meshes at %.0e of the diagonal, angle %.2f, best of %d, %u threads\n", o.relative, o.angle, o.reps,
                std::thread::hardware_concurrency());
    bench::benchEachPart("shapespline_part_mesh_bench", o.parts, o.json, [&](const std::string& name, const fs::path& file,
                                                       const fs::path& scratch) { return benchPart(name, file, o, scratch); });
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shapespline_part_mesh_bench: %s\n", e.what());
    return 1;
  }
}
