// `sample PART/part.json --grid N -o CLOUD`: every converted face of a part that `shapespline
// import` wrote, each trimmed by its loops, into one point cloud whose records carry the face's id
// (docs/cad.md "Sampling a part"). The count of every face's kept samples is known before any is
// sampled (io::samplesInsideByItem), so the one file's header is written first and memory stays bounded.
#include <shapespline/cli/cmd_sample.h>
#include <shapespline/cli/common.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/part_manifest.h>
#include <shapespline/io/shard_info.h>
#include <shapespline/io/trimmed_points.h>
#include <shapespline/jobs/shard_files.h>
#include <shapespline/jobs/shard_record.h>
#include <shapespline/sampling/session.h>

#include <algorithm>
#include <optional>

namespace shapespline::cli {
namespace {

struct PartFace {
  int id = 0;
  std::filesystem::path model;
  std::optional<Surface> surface;
  io::SampleLayout layout;
};

// A face's model file; its errors also name the manifest's key that names the file.
io::Model loadPartFace(const std::filesystem::path& file, const std::string& key) {
  try {
    return loadModel(file.string());
  } catch (const ModelError& e) {
    throw ModelError(key + " (" + io::shortText(file.filename().string()) + "): " + e.field(), e.value(), e.rule());
  }
}

}  // namespace

bool samplePartInto(const SampleArgs& args, const PartJob& job, io::OutputSet& outputs, std::string& summary,
                    sampling::Session* shared) {
  if (!io::trimmedPointFormat(job.format))
    throw InputError("-o", args.out,
                     "a part is written as a mesh (.ply, .obj, .stl, .glb or .gltf without --grid) or as one point "
                     "cloud (.npy, .f32, .f64, .csv or .ply)");
  requireTrimmedShardFormat(args, job.format);
  const std::filesystem::path manifestPath(args.model);
  const io::PartManifest manifest = io::readPartManifest(manifestPath);
  outputs.reads(manifestPath, "MODEL");

  // Every face is read, built and counted first: the shard's cut balances the records of the whole
  // part, and a shard's job fingerprint covers every face (hashed only for a shard).
  const bool sharded = !args.shard.empty();
  std::vector<PartFace> faces;
  std::vector<uint64_t> keptByItem;  // the part's items, face after face
  std::vector<std::pair<int, std::string>> faceJobs;
  uint64_t gridPoints = 0;
  for (const io::PartFaceEntry& entry : manifest.faces) {
    if (!entry.model) continue;
    PartFace& face = faces.emplace_back();
    face.id = entry.id;
    face.model = *entry.model;
    io::Model model = loadPartFace(face.model, entry.field + ".model");
    auto* surfaceModel = std::get_if<SurfaceModel>(&model);
    if (!surfaceModel || surfaceModel->trim.empty())
      throw InputError("MODEL", face.model.string(), entry.field + " is not a trimmed surface (a face written by import)");
    outputs.reads(face.model, "MODEL's face");
    face.surface.emplace(Surface::create(std::move(*surfaceModel)));
    io::SampleLayout& layout = face.layout;
    layout.surface = true;
    layout.samplesU = job.samplesU;
    layout.samplesV = job.samplesV;
    layout.fields = job.fields;
    layout.precision = job.precision;
    layout.source = face.model.string();
    io::setSurfaceItems(face.surface->model(), layout);
    layout.itemCount = layout.totalItems;
    const TrimLoops& trim = face.surface->model().trim;
    const std::vector<uint64_t> kept = io::samplesInsideByItem(layout, trim);
    keptByItem.insert(keptByItem.end(), kept.begin(), kept.end());
    gridPoints += layout.pointCount();
    if (sharded)
      faceJobs.emplace_back(face.id, io::trimmedJobFingerprint(io::jobFingerprint(*face.surface, layout, job.format), trim));
  }
  if (faces.empty()) throw InputError("MODEL", args.model, "the part has no converted face to sample");

  // This shard's run of the part's items (all of them unsharded), cut into each face's own range.
  io::TrimmedShard shard = io::balancedTrimmedShard(keptByItem, job.shardK, job.shardN);
  if (sharded) shard.job = io::partJobFingerprint(faceJobs);
  shard.index = job.shardK;
  shard.count = job.shardN;
  uint64_t faceStart = 0, points = 0;
  for (PartFace& face : faces) {
    io::SampleLayout& layout = face.layout;
    const uint64_t from = std::clamp(shard.firstItem, faceStart, faceStart + layout.totalItems);
    const uint64_t to = std::clamp(shard.firstItem + shard.items, faceStart, faceStart + layout.totalItems);
    layout.firstItem = from - faceStart;
    layout.itemCount = to - from;
    points += layout.pointCount();
    faceStart += layout.totalItems;
  }

  io::AtomicFile& out = outputs.add(args.out, "-o");
  io::AtomicFile* sidecar = nullptr;
  if (io::hasLayoutSidecar(job.format)) sidecar = &outputs.add(args.out + ".json", "-o");
  io::AtomicFile* record = sharded ? &outputs.add(jobs::shardRecordPath(args.out), "-o") : nullptr;
  std::optional<sampling::Session> own;
  sampling::Session& session = shared ? *shared : own.emplace();
  const sampling::Report report = session.plan(*faces.front().surface, job.request);
  printNotices(report, args.quiet);
  const std::string manifestSha256 = io::sha256OfFile(manifestPath);

  // The shard record: the part's job and items, its records, the manifest as the model (the rest of
  // the metadata is the first face's, whose grid and precisions the whole part shares).
  jobs::ShardRecord want;
  if (record) {
    io::SampleLayout first = faces.front().layout;
    first.metadata = io::jobMetadataOf(*faces.front().surface, manifestPath.string(), manifestSha256,
                                       report.device, report.computedPrecision, job.storedPrecision, job.samplesU,
                                       job.samplesV);
    first.metadata.modelFile = args.model;
    want = jobs::trimmedShardRecordOf(first, job.format, shard, points);
    if (jobs::shardAlreadyDone(want, job.format, {args.out, sidecar ? sidecar->target().string() : "", "sidecar"},
                               args.quiet))
      return false;
  }

  io::TrimmedPointWriter writer(job.format, out, sidecar);
  if (record) writer.setShard(shard);
  const nlohmann::json part = {{"manifest", manifestPath.filename().string()},
                               {"manifest_sha256", manifestSha256},
                               {"faces", faces.size()},
                               {"faces_skipped_at_import", manifest.skipped},
                               {"device", report.device}};
  writer.beginPart(faces.front().layout, shard.records, gridPoints, part);
  sampling::GridOptions options;
  options.threads = args.threads;
  options.chunkPoints = static_cast<size_t>(args.chunkPoints);
  options.slice = job.check;
  for (const PartFace& face : faces) {
    if (face.layout.itemCount == 0) continue;
    writer.nextFace(face.layout, face.surface->model().trim, face.id);
    GridSpec grid;
    grid.samplesU = job.samplesU;
    grid.samplesV = job.samplesV;
    grid.firstItem = face.layout.firstItem;
    grid.itemCount = face.layout.itemCount;
    session.sampleGrid(*face.surface, job.request, grid, job.fields, [&](const GridChunk& c) { writer.consume(c); },
                       options);
  }
  writer.finish();
  if (record) {
    out.flushToTemp();
    if (sidecar) sidecar->flushToTemp();
    jobs::writeShardRecord(*record, want, out, sidecar, "sidecar");
  }
  summary = "wrote " + args.out + " (" + std::to_string(faces.size()) + " faces, " +
            (record ? "items " + std::to_string(shard.firstItem) + ".." + std::to_string(shard.firstItem + shard.items) +
                          " of " + std::to_string(shard.totalItems) + ", "
                    : std::string()) +
            std::to_string(shard.records) + " points inside their trim loops" +
            (sidecar ? ", layout in " + sidecar->target().string() : "") + ")";
  return true;
}

}  // namespace shapespline::cli
