// Closest points against Open CASCADE's GeomAPI_ProjectPointOnSurf (issue 55): the bench's own parts
// (tests/cad/test_parts: a drilled plate of planes and cylinders, a filleted box, a free-form
// B-spline face) or any STEP/IGES files given. N points are taken on the faces (at random
// parameters inside each face's trim loops, spread over the faces by their count), and N more moved
// off them along the normal by up to 2% of the diagonal. Timed on the same points, best of REPS:
//   * OCCT: per face, Init once (the face's surface and parameter bounds) and Perform per point, the
//     faces split between as many threads as the machine has (OCCT is told each point's face: its
//     easiest case);
//   * shapespline's part::ClosestPoints on the whole part (every face a candidate), CPU fp64, the
//     same threads; its tree built once (timed apart).
// Also counted: the points where OCCT's nearest point (LowerDistance, or no answer) is farther than
// shapespline's by more than 1e-9 of the diagonal, among those whose shapespline foot is on the
// point's own face (a point of the surface OCCT searched, so OCCT missed its own minimum). Prints a table; writes --json FILE.
// Usage: shapespline_project_bench [--points N] [--reps N] [--json FILE] [PART.step ...]
#include <shapespline/core/parallel_for.h>
#include <shapespline/core/trim_classifier.h>
#include <shapespline/part/closest_points.h>
#include <shapespline/part/part_model.h>

#include "bench_parts.h"
#include "bench_run.h"

#include <shapespline/cad/occt_part.h>
#include <shapespline/cad/part_import.h>

#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <random>
#include <thread>
#include <unistd.h>

namespace {

using namespace shapespline;
namespace fs = std::filesystem;

struct Options {
  int points = 20000, reps = 3;
  std::string json;
  std::vector<fs::path> parts;
};

struct Cloud {
  std::vector<glm::dvec3> points;
  std::vector<int> face;  // index into Part::faces
};

// `count` points on the faces, inside their loops, each face's share proportional to 1 (every
// face gets points), and the same moved along the normal by up to `offset`.
Cloud cloudOn(const part::Part& p, int count, double offset, uint32_t seed) {
  std::mt19937_64 rng(seed);
  Cloud c;
  const int perFace = std::max(1, count / static_cast<int>(p.faces.size()));
  for (size_t f = 0; f < p.faces.size(); ++f) {
    const Surface& s = p.faces[f].surface;
    const auto [u0, u1] = s.parameterRangeU();
    const auto [v0, v1] = s.parameterRangeV();
    std::uniform_real_distribution<double> U(u0, u1), V(v0, v1), off(-offset, offset);
    std::optional<TrimClassifier> inside;
    if (!s.model().trim.empty()) inside.emplace(s.model().trim);
    for (int k = 0, tries = 0; k < perFace && tries < 100 * perFace; ++tries) {
      const glm::dvec2 uv(U(rng), V(rng));
      if (inside && !inside->inside(uv)) continue;
      const SurfacePoint sp = s.evaluateAt(uv.x, uv.y);
      c.points.push_back(sp.point + (offset > 0.0 ? off(rng) : 0.0) * sp.normal);
      c.face.push_back(static_cast<int>(f));
      ++k;
    }
  }
  return c;
}

struct Figures {
  double occtSeconds = 0.0, oursSeconds = 0.0;
  size_t points = 0, occtFarther = 0, occtNoAnswer = 0;
  double worstOcctGap = 0.0;
};

Figures compare(const part::Part& p, const TopTools_IndexedMapOfShape& faces, const part::ClosestPoints& closest,
                const Cloud& cloud, int reps, double diagonal) {
  Figures fig;
  fig.points = cloud.points.size();
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  // OCCT: points grouped by face; Init once per face, Perform per point.
  std::vector<std::vector<size_t>> byFace(p.faces.size());
  for (size_t k = 0; k < cloud.points.size(); ++k) byFace[cloud.face[k]].push_back(k);
  std::vector<double> occtDistance(cloud.points.size(), -1.0);
  fig.occtSeconds = bench::bestSeconds(reps, [&] {
    parallelFor(p.faces.size(), static_cast<int>(threads), [&](size_t f) {
      if (byFace[f].empty()) return;
      const TopoDS_Face& face = TopoDS::Face(faces(p.faces[f].id));
      double u0, u1, v0, v1;
      BRepTools::UVBounds(face, u0, u1, v0, v1);
      GeomAPI_ProjectPointOnSurf projector;
      projector.Init(BRep_Tool::Surface(face), u0, u1, v0, v1);
      for (const size_t k : byFace[f]) {
        const glm::dvec3& q = cloud.points[k];
        projector.Perform(gp_Pnt(q.x, q.y, q.z));
        occtDistance[k] = projector.IsDone() && projector.NbPoints() > 0 ? projector.LowerDistance() : -1.0;
      }
    });
  });
  std::vector<part::FootPoint> feet(cloud.points.size());
  fig.oursSeconds = bench::bestSeconds(reps, [&] { closest.of(cloud.points, feet, true, static_cast<int>(threads)); });
  for (size_t k = 0; k < feet.size(); ++k) {
    if (occtDistance[k] < 0.0) {
      ++fig.occtNoAnswer;
      continue;
    }
    // Only where shapespline's foot is on the point's own face: elsewhere another face is nearer,
    // which OCCT, told the face, is not asked about.
    if (feet[k].face != p.faces[cloud.face[k]].id) continue;
    const double gap = occtDistance[k] - feet[k].distance;
    fig.worstOcctGap = std::max(fig.worstOcctGap, gap);
    if (gap > 1e-9 * diagonal) ++fig.occtFarther;
  }
  return fig;
}

nlohmann::json benchPart(const std::string& name, const fs::path& file, const Options& o, const fs::path& scratch) {
  cad::PartShape shape = cad::readPart(file, std::uint64_t{1} << 32);
  const fs::path dir = scratch / name;
  fs::remove_all(dir);
  cad::importPart(file, dir);
  const part::Part p = part::loadPart(dir / "part.json");
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape.shape, TopAbs_FACE, faces);
  std::optional<part::ProjectionTree> tree;
  const double build = bench::seconds([&] { tree.emplace(part::ProjectionTree::ofPart(p)); });
  const part::ClosestPoints closest(*tree);
  const double diagonal = tree->diagonal();
  std::printf("%s: %zu faces, diagonal %.4g; tree %zu cells, %zu trim pieces, built in %.3f s\n", name.c_str(),
              p.faces.size(), diagonal, tree->cells().size(), tree->runs().size(), build);
  nlohmann::json row = {{"part", name}, {"faces", p.faces.size()}, {"diagonal", diagonal}, {"tree_seconds", build}};
  for (const auto& [kind, offset] : {std::pair{"on", 0.0}, std::pair{"off", 0.02 * diagonal}}) {
    const Cloud cloud = cloudOn(p, o.points, offset, kind[1] == 'n' ? 1 : 2);
    const Figures f = compare(p, faces, closest, cloud, o.reps, diagonal);
    const double occtRate = f.points / f.occtSeconds, ourRate = f.points / f.oursSeconds;
    std::printf("  %-3s %7zu points: OCCT %10.0f points/s, shapespline %10.0f points/s = %7.1fx; OCCT farther on %zu "
                "(worst %.3g), no answer on %zu\n",
                kind, f.points, occtRate, ourRate, ourRate / occtRate, f.occtFarther, f.worstOcctGap, f.occtNoAnswer);
    row[kind] = {{"points", f.points},           {"occt_points_per_second", occtRate},
                 {"points_per_second", ourRate}, {"ratio", ourRate / occtRate},
                 {"occt_farther", f.occtFarther}, {"occt_worst_gap", f.worstOcctGap},
                 {"occt_no_answer", f.occtNoAnswer}};
  }
  return row;
}

Options parse(int argc, char** argv) {
  Options o;
  o.parts = bench::parseArguments(argc, argv, [&](const std::string& a, const bench::OptionValue& value) {
    if (a == "--points") o.points = std::stoi(value());
    else if (a == "--reps") o.reps = std::stoi(value());
    else if (a == "--json") o.json = value();
    else return false;
    return true;
  });
  if (o.points < 1 || o.reps < 1) throw std::invalid_argument("bad --points or --reps");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    cad::initOcctControllers();
    std::printf("closest points: %d on the faces and %d off (up to 2%% of the diagonal), best of %d, %u threads\n",
                o.points, o.points, o.reps, std::thread::hardware_concurrency());
    bench::benchEachPart("shapespline_project_bench", o.parts, o.json, [&](const std::string& name, const fs::path& file,
                                                       const fs::path& scratch) { return benchPart(name, file, o, scratch); });
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shapespline_project_bench: %s\n", e.what());
    return 1;
  }
}
