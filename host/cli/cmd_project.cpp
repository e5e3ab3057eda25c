// `shapespline project POINTS --onto MODEL|part.json -o OUT`: the closest point on a surface, a
// part or a curve of every point of a cloud (docs/cli.md "project", docs/math.md "Closest points"),
// a block of points at a time, on every core, in fp64 on the CPU; `--report` prints the deviation
// statistics.
#include <shapespline/cli/common.h>
#include <shapespline/cli/part_mesh_options.h>
#include <shapespline/core/value_text.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/part_manifest.h>
#include <shapespline/io/point_cloud.h>
#include <shapespline/io/projection_writer.h>
#include <shapespline/part/closest_points.h>
#include <shapespline/part/deviation_stats.h>
#include <shapespline/part/part_model.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

namespace shapespline::cli {

namespace {

// Points projected per block: the memory a job holds whatever the cloud's size.
constexpr std::size_t kProjectBlockPoints = std::size_t{1} << 18;

struct ProjectArgs {
  std::string points, onto, out;
  int threads = 0;
  std::optional<double> tolerance;
  bool report = false, quiet = false;
};

// What the points are projected onto, and the tree over it (which keeps pointers into it).
struct Target {
  std::optional<part::Part> part;
  std::optional<Surface> surface;
  std::optional<Curve> curve;
  std::unique_ptr<part::ProjectionTree> tree;
  io::ProjectionTarget kind = io::ProjectionTarget::Surface;
  std::string what;  // for the summary
};

void loadTarget(const std::string& path, io::OutputSet& outputs, Target& t) {
  if (io::isPartManifest(path)) {
    t.part.emplace(loadPartManifest(path, &outputs, "--onto"));
    t.tree = std::make_unique<part::ProjectionTree>(part::ProjectionTree::ofPart(*t.part));
    t.kind = io::ProjectionTarget::Part;
    t.what = std::to_string(t.part->faces.size()) + " faces" + (t.part->closed() ? ", closed" : "");
    return;
  }
  outputs.reads(path, "--onto");
  io::Model model = loadModel(path);
  if (auto* curve = std::get_if<CurveModel>(&model)) {
    t.curve.emplace(Curve::create(std::move(*curve)));
    t.tree = std::make_unique<part::ProjectionTree>(part::ProjectionTree::ofCurve(*t.curve));
    t.kind = io::ProjectionTarget::Curve;
    t.what = "a curve";
    return;
  }
  t.surface.emplace(Surface::create(std::get<SurfaceModel>(std::move(model))));
  t.tree = std::make_unique<part::ProjectionTree>(part::ProjectionTree::ofFaces({{&*t.surface, 0, false}}));
  t.what = t.surface->model().trim.empty() ? "a surface" : "a trimmed surface";
}

void runProject(const ProjectArgs& a) {
  requireThreadCount(a.threads);
  if (a.tolerance && !(std::isfinite(*a.tolerance) && *a.tolerance > 0.0))
    throw InputError("--tolerance", shortestText(*a.tolerance), "expected a finite distance > 0 in the model's units");
  const auto start = std::chrono::steady_clock::now();
  io::OutputSet outputs;
  outputs.reads(a.points, "POINTS");
  Target target;
  loadTarget(a.onto, outputs, target);
  io::PointCloudReader cloud(a.points, "POINTS");
  io::AtomicFile& out = outputs.add(a.out, "-o");
  const std::unique_ptr<io::ProjectionWriter> writer =
      io::makeProjectionWriter(out, a.out, "-o", target.kind, cloud.count());

  const part::ClosestPoints closest(*target.tree, a.tolerance.value_or(0.0));
  const bool signedDistance = target.kind != io::ProjectionTarget::Curve;
  part::DeviationStats stats;
  std::vector<glm::dvec3> block;
  std::vector<part::FootPoint> feet;
  std::vector<io::ProjectionRecord> records;
  while (cloud.next(block, kProjectBlockPoints)) {
    feet.resize(block.size());
    closest.of(block, feet, signedDistance, a.threads);
    records.resize(block.size());
    for (std::size_t k = 0; k < block.size(); ++k) {
      const part::FootPoint& f = feet[k];
      records[k] = {block[k], f.point, f.normal, f.face, f.u, f.v, f.distance, f.signedDistance};
      stats.add(f.face, f.distance);
    }
    writer->write(records);
  }
  outputs.commit();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!a.quiet) {
    const part::DeviationStats::Summary all = stats.overall();
    std::printf("projected %llu points onto %s in %.3f s; distance max %.6g, mean %.6g\n",
                static_cast<unsigned long long>(all.count), target.what.c_str(), seconds, all.max, all.mean);
  }
  if (a.report) std::fputs(stats.text(target.kind == io::ProjectionTarget::Part).c_str(), stdout);
}

}  // namespace

void registerProject(CLI::App& app) {
  auto args = std::make_shared<ProjectArgs>();
  CLI::App* sub = app.add_subcommand(
      "project", "Closest points: each point of a cloud onto a surface, a part or a curve (fp64, CPU).");
  sub->add_option("POINTS", args->points, "the cloud: .npy (N, 3), .ply, .csv, .f32 or .f64")->required();
  sub->add_option("--onto", args->onto, "a model file (surface or curve) or a part's part.json")->required();
  sub->add_option("-o,--output", args->out, "the feet: .npy, .f64, .csv or .ply (docs/cli.md \"project\")")->required();
  sub->add_flag("--report", args->report, "print the deviation statistics (overall and per face)");
  sub->add_option("--tolerance", args->tolerance,
                  "accept a foot within this distance (model units, > 0) of the nearest: faster near the surface; "
                  "default exact");
  sub->add_option("--threads", args->threads, "threads (0 = one per CPU this process may use)");
  addQuietFlag(sub, args->quiet, "no summary line");
  sub->callback([args] { runProject(*args); });
}

}  // namespace shapespline::cli
