// CAD faces against Open CASCADE (issue 32): every face of the filleted box (tests/cad/test_parts)
// imported through STEP, evaluated with point, du and dv on 256 x 256 parameters per face by
//   * OCCT's Geom_BSplineSurface::D1 in a loop (1 thread, and 2 threads splitting the rows),
//   * shapespline's CPU fp64 list evaluation of the same parameters (sampling::evaluateOnCpu): every
//     field (second derivatives and normal too), and the lean list kernel (core/list_eval.h: point,
//     du and dv alone, 1 thread) on the list in its grid order (rows of one u: intervals and u bases
//     reused) and shuffled (every lookup fresh),
//   * shapespline's CPU fp64 grid sampler (1 and 2 threads) and Vulkan fp32 grid, at
//     ceil(256 / knot intervals) samples per interval and direction (what `sample` runs),
// best of REPS wall-clock repetitions after one untimed run, in one process. The shapespline list
// is checked against OCCT's D1 first. Prints a table and writes --json FILE.
#include <shapespline/sampling/session.h>

#include "../../tests/cad/test_parts.h"
#include "bench_run.h"

#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/part_import.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/model_json.h>

#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <unistd.h>

namespace {

using namespace shapespline;
namespace fs = std::filesystem;

constexpr int kGrid = 256;

struct Face {
  Surface surface;
  Handle(Geom_BSplineSurface) occt;
  double a0, a1, b0, b1;
  std::vector<sampling::SurfaceQuery> queries;  // the 256 x 256 parameters
  std::vector<sampling::SurfaceQuery> shuffled;  // the same, in a random order
};

using bench::bestSeconds;

void occtRows(const Face& f, int firstRow, int lastRow, std::vector<double>& out) {
  gp_Pnt p;
  gp_Vec du, dv;
  for (int i = firstRow; i < lastRow; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const sampling::SurfaceQuery& q = f.queries[static_cast<size_t>(i) * kGrid + j];
      f.occt->D1(q.u, q.v, p, du, dv);
      double* o = &out[(static_cast<size_t>(i) * kGrid + j) * 9];
      o[0] = p.X(), o[1] = p.Y(), o[2] = p.Z(), o[3] = du.X(), o[4] = du.Y(), o[5] = du.Z();
      o[6] = dv.X(), o[7] = dv.Y(), o[8] = dv.Z();
    }
}

}  // namespace

int main(int argc, char** argv) {
  int reps = 5;
  std::string jsonPath;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reps") && i + 1 < argc) reps = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--json") && i + 1 < argc) jsonPath = argv[++i];
  }
  const fs::path dir = fs::temp_directory_path() / ("shapespline_cad_bench_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  test::writeStep(test::filletedBox(), dir / "box.step");
  cad::importPart(dir / "box.step", dir / "box");
  const cad::PartShape part = cad::readPart(dir / "box.step", std::uint64_t{1} << 30);
  TopTools_IndexedMapOfShape shapes;
  TopExp::MapShapes(part.shape, TopAbs_FACE, shapes);
  std::ifstream manifestFile(dir / "box" / "part.json");
  const nlohmann::json manifest = nlohmann::json::parse(manifestFile);
  std::vector<Face> faces;
  for (const auto& entry : manifest.at("faces")) {
    if (entry.at("model").is_null()) continue;
    SurfaceModel model = std::get<SurfaceModel>(io::loadModelFile(dir / "box" / entry.at("model").get<std::string>()));
    const cad::ConvertedFace occt = cad::convertFace(TopoDS::Face(shapes(entry.at("id").get<int>())), 1e-5);
    Face f{Surface::create(std::move(model)), occt.bspline, 0, 0, 0, 0, {}, {}};
    f.occt->Bounds(f.a0, f.a1, f.b0, f.b1);
    for (int i = 0; i < kGrid; ++i)
      for (int j = 0; j < kGrid; ++j)
        f.queries.push_back({true, 0, 0, f.a0 + (f.a1 - f.a0) * i / (kGrid - 1), f.b0 + (f.b1 - f.b0) * j / (kGrid - 1)});
    f.shuffled = f.queries;
    std::shuffle(f.shuffled.begin(), f.shuffled.end(), std::mt19937(7));
    faces.push_back(std::move(f));
  }
  fs::remove_all(dir);
  const double points = static_cast<double>(faces.size()) * kGrid * kGrid;

  // Cross-check: shapespline's list against OCCT's D1, relative to each face's size.
  sampling::Report cpuReport;
  double worst = 0.0;
  bool leanDiffers = false;
  std::vector<double> occtOut(static_cast<size_t>(kGrid) * kGrid * 9);
  for (const Face& f : faces) {
    occtRows(f, 0, kGrid, occtOut);
    const auto ours = sampling::evaluateOnCpu(f.surface, cpuReport, f.queries);
    double size = 0.0;
    for (size_t k = 0; k < ours.size(); ++k) size = std::max(size, glm::length(ours[k].point - ours[0].point));
    for (size_t k = 0; k < ours.size(); ++k) {
      const double* o = &occtOut[k * 9];
      worst = std::max(worst, glm::length(ours[k].point - glm::dvec3(o[0], o[1], o[2])) / std::max(size, 1e-300));
    }
    // The lean list gives the full list's bits (tests/core/list_eval_test.cpp checks every family).
    const auto lean = sampling::evaluateOnCpu(f.surface, cpuReport, f.queries, ListFields::FirstDerivatives);
    for (size_t k = 0; k < ours.size(); ++k)
      if (std::memcmp(&lean[k].point, &ours[k].point, sizeof(glm::dvec3)) ||
          std::memcmp(&lean[k].du, &ours[k].du, sizeof(glm::dvec3)) ||
          std::memcmp(&lean[k].dv, &ours[k].dv, sizeof(glm::dvec3)))
        leanDiffers = true;
  }

  struct Row {
    std::string name;
    double seconds, mpts;
  };
  std::vector<Row> rows;
  auto add = [&](const std::string& name, double pointCount, const std::function<void()>& run) {
    const double s = bestSeconds(reps, run);
    rows.push_back({name, s, pointCount / s / 1e6});
    std::fprintf(stderr, "  %-52s %8.4f s %8.2f Mpts/s\n", name.c_str(), s, pointCount / s / 1e6);
  };
  add("OCCT Geom_BSplineSurface::D1, 1 thread", points, [&] {
    for (const Face& f : faces) occtRows(f, 0, kGrid, occtOut);
  });
  std::vector<double> occtOut2(occtOut.size());
  add("OCCT Geom_BSplineSurface::D1, 2 threads", points, [&] {
    for (const Face& f : faces) {
      std::thread half([&] { occtRows(f, 0, kGrid / 2, occtOut); });
      occtRows(f, kGrid / 2, kGrid, occtOut2);
      half.join();
    }
  });
  add("shapespline CPU fp64, list of the same parameters", points, [&] {
    for (const Face& f : faces) (void)sampling::evaluateOnCpu(f.surface, cpuReport, f.queries);
  });
  add("shapespline CPU fp64 lean list (point, du, dv), 1 thread", points, [&] {
    for (const Face& f : faces) (void)sampling::evaluateOnCpu(f.surface, cpuReport, f.queries, ListFields::FirstDerivatives);
  });
  add("shapespline CPU fp64 lean list, shuffled order, 1 thread", points, [&] {
    for (const Face& f : faces) (void)sampling::evaluateOnCpu(f.surface, cpuReport, f.shuffled, ListFields::FirstDerivatives);
  });
  // Grids: the same density per face, as samples per knot interval.
  sampling::Session session;
  const FieldMask fields = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv);
  double gridPoints = 0.0;
  std::vector<GridSpec> grids;
  for (const Face& f : faces) {
    const PatchRange r = f.surface.patches();
    const int intervalsU = r.u.last - r.u.first + 1, intervalsV = r.v.last - r.v.first + 1;
    GridSpec g;
    g.samplesU = std::max(2, (kGrid + intervalsU - 1) / intervalsU);
    g.samplesV = std::max(2, (kGrid + intervalsV - 1) / intervalsV);
    grids.push_back(g);
    gridPoints += static_cast<double>(g.samplesU) * g.samplesV * intervalsU * intervalsV;
  }
  auto sampleAll = [&](sampling::DeviceKind kind, shapespline::Precision precision, int threads) {
    sampling::GridOptions options;
    options.threads = threads;
    for (size_t k = 0; k < faces.size(); ++k)
      session.sampleGrid(faces[k].surface, {kind, precision, true, true}, grids[k], fields, [](const GridChunk&) {}, options);
  };
  add("shapespline CPU fp64 grid, 1 thread", gridPoints, [&] { sampleAll(sampling::DeviceKind::Cpu, shapespline::Precision::Double, 1); });
  add("shapespline CPU fp64 grid, 2 threads", gridPoints, [&] { sampleAll(sampling::DeviceKind::Cpu, shapespline::Precision::Double, 2); });
  std::string device = "none";
  try {
    sampleAll(sampling::DeviceKind::Vulkan, shapespline::Precision::Float, 0);
    device = session.plan(faces[0].surface, {sampling::DeviceKind::Vulkan, shapespline::Precision::Float, true, true}).device;
    add("shapespline Vulkan fp32 grid (" + device + ")", gridPoints,
        [&] { sampleAll(sampling::DeviceKind::Vulkan, shapespline::Precision::Float, 0); });
  } catch (const std::exception& e) {
    std::fprintf(stderr, "  Vulkan: skipped (%s)\n", e.what());
  }

  const double occt1 = rows[0].mpts;
  std::printf("| faces of the filleted box (%zu), point + du + dv | Mpts/s | / OCCT 1 thread |\n|---|---:|---:|\n",
              faces.size());
  for (const Row& r : rows) std::printf("| %s | %.2f | %.2f |\n", r.name.c_str(), r.mpts, r.mpts / occt1);
  std::printf("shapespline list vs OCCT D1: max |point difference| / face size = %.2e\n", worst);
  std::printf("lean list vs full list: %s\n", leanDiffers ? "DIFFERENT BITS" : "the same bits");
  if (!jsonPath.empty()) {
    nlohmann::json j = {{"workload", {{"part", "filleted box 40 x 30 x 20, radius 3 (tests/cad/test_parts.cpp)"},
                                      {"faces", faces.size()},
                                      {"parameters_per_face", kGrid * kGrid},
                                      {"grid_points", gridPoints},
                                      {"fields", {"point", "du", "dv"}}}},
                        {"statistic", "best of " + std::to_string(reps) + " wall-clock repetitions after one untimed run"},
                        {"nproc", std::thread::hardware_concurrency()},
                        {"vulkan_device", device},
                        {"max_point_difference_over_face_size", worst},
                        {"lean_list_same_bits_as_full_list", !leanDiffers},
                        {"results", nlohmann::json::array()}};
    for (const Row& r : rows)
      j["results"].push_back({{"peer", r.name}, {"seconds", r.seconds}, {"mpts_per_s", r.mpts}, {"ratio_to_occt_1_thread", r.mpts / occt1}});
    std::ofstream(jsonPath) << j.dump(2) << "\n";
  }
  return worst <= 1e-12 && !leanDiffers ? 0 : 1;
}
