// `shapespline project POINTS --onto MODEL|part.json -o OUT`: the closest point on a surface, a
// part or a curve of every point of a cloud (docs/cli.md "project", docs/math.md "Closest points"),
// a block of points at a time, on every core, in fp64 on the CPU, or with the search on a Vulkan
// device (`--device vulkan`: part/gpu_closest_points.h; a curve stays on the CPU); `--report`
// prints the deviation statistics. `--shard K/N|auto` projects the K-th of N equal runs of the cloud's points and writes
// its record OUT.shard.json; `merge` joins the shards into the unsharded job's bytes.
#include <shapespline/cli/common.h>
#include <shapespline/cli/part_mesh_options.h>
#include <shapespline/core/value_text.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/file_extension.h>
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/part_manifest.h>
#include <shapespline/io/point_cloud.h>
#include <shapespline/io/projection_writer.h>
#include <shapespline/io/shard_info.h>
#include <shapespline/jobs/shard_files.h>
#include <shapespline/jobs/shard_record.h>
#include <shapespline/part/closest_points.h>
#include <shapespline/part/deviation_stats.h>
#include <shapespline/part/gpu_closest_points.h>
#include <shapespline/part/part_model.h>
#include <shapespline/sampling/session.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>

namespace shapespline::cli {

namespace {

// Points projected per block: the memory a job holds whatever the cloud's size.
constexpr std::size_t kProjectBlockPoints = std::size_t{1} << 18;

struct ProjectArgs {
  std::string points, onto, out, shard, shardCount;
  std::string device = "cpu", precision = "double";
  bool requireDevice = false;
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

const char* targetName(io::ProjectionTarget kind) {
  return kind == io::ProjectionTarget::Part ? "part" : kind == io::ProjectionTarget::Curve ? "curve" : "surface";
}

// The SHA-256 of up to kEndBytes at the start and at the end of a file: a cloud of billions of
// points is told apart from another of the same size without reading it whole in every shard.
constexpr std::size_t kEndBytes = std::size_t{1} << 20;
std::string endsSha256(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::uint64_t size = std::filesystem::file_size(path);
  std::string bytes(static_cast<std::size_t>(std::min<std::uint64_t>(size, 2 * kEndBytes)), '\0');
  const std::size_t head = std::min<std::size_t>(bytes.size(), kEndBytes);
  in.read(bytes.data(), static_cast<std::streamsize>(head));
  in.seekg(static_cast<std::streamoff>(size - (bytes.size() - head)));
  in.read(bytes.data() + head, static_cast<std::streamsize>(bytes.size() - head));
  if (!in) throw InputError("POINTS", path, "cannot be read");
  return io::sha256Of(bytes);
}

// Every shard of one projection job has this fingerprint: what is projected (the cloud's size,
// count and ends), onto what (the bytes of the model, or of part.json and every face file), how
// (the path, CPU or Vulkan and its precision, and the tolerance) and into which format.
std::string projectionJob(const ProjectArgs& a, const Target& t, std::uint64_t points, const std::string& path) {
  std::string text = "shapespline project\ntarget " + std::string(targetName(t.kind)) + "\npath " + path + "\nformat " +
                     io::lowercaseExtension(a.out) + "\ntolerance " +
                     (a.tolerance ? shortestText(*a.tolerance) : std::string("exact")) + "\npoints " +
                     std::to_string(points) + " bytes " + std::to_string(std::filesystem::file_size(a.points)) +
                     " ends " + endsSha256(a.points) + "\nonto " + io::sha256OfFile(a.onto) + "\n";
  if (t.part)
    for (const part::PartFace& face : t.part->faces) text += "face " + io::sha256OfFile(face.model) + "\n";
  return io::sha256Of(text).substr(0, 16);
}

void runProject(const ProjectArgs& given) {
  requireThreadCount(given.threads);
  if (given.tolerance && !(std::isfinite(*given.tolerance) && *given.tolerance > 0.0))
    throw InputError("--tolerance", shortestText(*given.tolerance), "expected a finite distance > 0 in the model's units");
  // --shard auto and a shard pattern in -o first (jobs/shard_files.h): the rest sees K/N and a path.
  const jobs::ShardOutput shardOut = jobs::resolveShardOutput(given.out, given.shard, given.shardCount);
  ProjectArgs a = given;
  a.out = shardOut.out;
  const bool sharded = !shardOut.shard.empty();
  io::projectionFormat(a.out, "-o");  // a bad extension is refused before any work

  const auto start = std::chrono::steady_clock::now();
  io::OutputSet outputs;
  outputs.reads(a.points, "POINTS");
  Target target;
  loadTarget(a.onto, outputs, target);
  // The search's device: the CPU (the default, exact in fp64), or Vulkan where the request can use
  // it; a curve is projected on the CPU.
  const sampling::DeviceRequest request = parseDeviceRequest(a.device, a.precision, a.requireDevice);
  sampling::Session session;
  sampling::Report plan = session.planDevice(request);
  if (plan.gpu && target.kind == io::ProjectionTarget::Curve) {
    if (a.requireDevice) throw sampling::DeviceError("closest points on a curve run on the CPU only", true);
    plan = {};
    plan.fallbacks.push_back("closest points on a curve run on the CPU");
  }
  if (!plan.gpu) plan.outputPrecision = plan.computedPrecision;  // the feet are written in fp64 either way
  printNotices(plan, a.quiet);
  const std::string path = plan.gpu ? "vulkan " + std::string(plan.computedPrecision == Precision::Double ? "fp64" : "fp32")
                                    : "cpu";
  io::PointCloudReader cloud(a.points, "POINTS");
  // Shard K of N: the points floor((K-1) P / N) .. floor(K P / N).
  const std::uint64_t total = cloud.count(), k = std::uint64_t(shardOut.index), n = std::uint64_t(shardOut.count);
  const std::uint64_t first = io::shardBound(total, k - 1, n), count = io::shardBound(total, k, n) - first;
  io::AtomicFile& out = outputs.add(a.out, "-o");
  io::AtomicFile* record = sharded ? &outputs.add(jobs::shardRecordPath(a.out), "-o") : nullptr;
  jobs::ShardRecord want;
  if (record) {
    want.job = projectionJob(a, target, total, path);
    want.projection = targetName(target.kind);
    want.surface = target.kind != io::ProjectionTarget::Curve;
    want.format = io::lowercaseExtension(a.out).substr(1);
    want.shardIndex = shardOut.index;
    want.shardCount = shardOut.count;
    want.firstItem = first;
    want.itemCount = want.points = want.vertices = count;
    want.totalItems = total;
    if (jobs::shardAlreadyDone(want, io::outputFormatFromPath(a.out, "-o"), {a.out, "", ""}, a.quiet)) return;
  }
  cloud.skip(first);
  const std::unique_ptr<io::ProjectionWriter> writer = io::makeProjectionWriter(out, a.out, "-o", target.kind, count);

  const part::ClosestPoints closest(*target.tree, a.tolerance.value_or(0.0));
  std::optional<part::GpuClosestPoints> gpu;
  if (plan.gpu) gpu.emplace(closest, session.vulkanContext(), plan.computedPrecision);
  const bool signedDistance = target.kind != io::ProjectionTarget::Curve;
  part::DeviationStats stats;
  std::uint64_t redone = 0;  // GPU searches past the kernel's budget, done again on the CPU
  std::vector<glm::dvec3> block;
  std::vector<part::FootPoint> feet;
  std::vector<io::ProjectionRecord> records;
  for (std::uint64_t left = count; left > 0 && cloud.next(block, std::min<std::uint64_t>(left, kProjectBlockPoints));
       left -= block.size()) {
    feet.resize(block.size());
    if (gpu) {
      gpu->of(block, feet, signedDistance, a.threads);
      redone += gpu->redone();
    } else {
      closest.of(block, feet, signedDistance, a.threads);
    }
    records.resize(block.size());
    for (std::size_t k = 0; k < block.size(); ++k) {
      const part::FootPoint& f = feet[k];
      records[k] = {block[k], f.point, f.normal, f.face, f.u, f.v, f.distance, f.signedDistance};
      stats.add(f.face, f.distance);
    }
    writer->write(records);
  }
  if (record) {
    out.flushToTemp();
    jobs::writeShardRecord(*record, want, out, nullptr, "");
  }
  outputs.commit();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!a.quiet) {
    const part::DeviationStats::Summary all = stats.overall();
    const std::string part = sharded ? " (shard " + shardOut.shard +
                                           ", points " + std::to_string(first) + ".." + std::to_string(first + count) +
                                           " of " + std::to_string(total) + ")"
                                     : "";
    std::string how = "cpu fp64";
    if (plan.gpu) {
      how = plan.device + ", " + (plan.computedPrecision == Precision::Double ? "fp64" : "fp32");
      if (redone > 0) how += ", " + std::to_string(redone) + " searched again on the CPU";
    }
    std::printf("projected %llu points%s onto %s in %.3f s (%s); distance max %.6g, mean %.6g\n",
                static_cast<unsigned long long>(all.count), part.c_str(), target.what.c_str(), seconds, how.c_str(),
                all.max, all.mean);
  }
  if (a.report) std::fputs(stats.text(target.kind == io::ProjectionTarget::Part).c_str(), stdout);
}

}  // namespace

void registerProject(CLI::App& app) {
  auto args = std::make_shared<ProjectArgs>();
  CLI::App* sub = app.add_subcommand(
      "project", "Closest points: each point of a cloud onto a surface, a part or a curve (fp64 CPU, or Vulkan).");
  sub->add_option("POINTS", args->points, "the cloud: .npy (N, 3), .ply, .csv, .f32 or .f64")->required();
  sub->add_option("--onto", args->onto, "a model file (surface or curve) or a part's part.json")->required();
  sub->add_option("-o,--output", args->out, "the feet: .npy, .f64, .csv or .ply (docs/cli.md \"project\")")->required();
  sub->add_flag("--report", args->report, "print the deviation statistics (overall and per face)");
  sub->add_option("--tolerance", args->tolerance,
                  "accept a foot within this distance (model units, > 0) of the nearest: faster near the surface; "
                  "default exact");
  sub->add_option("--threads", args->threads, "threads (0 = one per CPU this process may use)");
  sub->add_option("--device", args->device,
                  "cpu (default: exact, fp64), vulkan or auto: the search on the GPU, each foot finished on the "
                  "CPU, falling back to the CPU with a notice (a curve always runs on the CPU)");
  sub->add_option("--precision", args->precision, "the GPU search's float or double (default double)");
  sub->add_flag("--require-device", args->requireDevice,
                "with --device auto or vulkan: fail (exit 3) instead of falling back to the CPU");
  addShardOptions(sub, args->shard, args->shardCount, "project the K-th (1-based) of N equal runs of the cloud's points");
  addQuietFlag(sub, args->quiet, "no summary line");
  sub->callback([args] { runProject(*args); });
}

}  // namespace shapespline::cli
