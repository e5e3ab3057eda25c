// `sample PART/part.json --grid N -o CLOUD`: every converted face of a part that `shapespline
// import` wrote, each trimmed by its loops, into one point cloud whose records carry the face's id
// (docs/cad.md "Sampling a part"). The count of every face's kept samples is known before any is
// sampled (io::samplesInside), so the one file's header is written first and memory stays bounded.
#include <shapespline/cli/cmd_sample.h>
#include <shapespline/cli/common.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/trimmed_points.h>
#include <shapespline/sampling/session.h>

#include <fstream>
#include <optional>

namespace shapespline::cli {
namespace {

constexpr const char* kPartFormat = "shapespline-part";
constexpr size_t kSniffBytes = 64 * 1024;

struct PartFace {
  int id = 0;
  std::filesystem::path model;
  std::optional<Surface> surface;
  io::SampleLayout layout;
};

}  // namespace

bool isPartManifest(const std::string& path) {
  if (std::filesystem::path(path).extension() != ".json") return false;
  // A model file may be 32 MiB of JSON: look for the format's name in its head before parsing.
  std::ifstream in(path, std::ios::binary);
  std::string head(kSniffBytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  if (head.find(kPartFormat) == std::string::npos) return false;
  const nlohmann::json j = readJsonFile(path, "MODEL");
  return j.is_object() && j.value("format", std::string()) == kPartFormat;
}

bool samplePartInto(const SampleArgs& args, const PartJob& job, io::OutputSet& outputs, std::string& summary,
                    sampling::Session* shared) {
  if (!io::trimmedPointFormat(job.format))
    throw InputError("-o", args.out,
                     "a part is written as one point cloud (.npy, .f32, .f64, .csv or .ply); meshes and pictures of "
                     "trimmed faces are refused until a trimmed mesher exists");
  const std::filesystem::path manifestPath(args.model);
  const nlohmann::json manifest = readJsonFile(args.model, "MODEL");
  if (!manifest.contains("faces") || !manifest["faces"].is_array())
    throw InputError("MODEL", args.model, "a part manifest needs a \"faces\" array");
  outputs.reads(manifestPath, "MODEL");

  std::vector<PartFace> faces;
  uint64_t total = 0;
  int skipped = 0;
  for (size_t i = 0; i < manifest["faces"].size(); ++i) {
    const nlohmann::json& entry = manifest["faces"][i];
    const std::string field = "faces[" + std::to_string(i) + "]";
    if (!entry.is_object() || !entry.contains("id") || !entry["id"].is_number_integer() || !entry.contains("model"))
      throw InputError("MODEL", args.model, field + " needs an integer \"id\" and a \"model\"");
    if (entry["model"].is_null()) {
      ++skipped;  // not converted at import; part.json says why
      continue;
    }
    if (!entry["model"].is_string()) throw InputError("MODEL", args.model, field + ".model must be a file name");
    PartFace& face = faces.emplace_back();
    face.id = entry["id"].get<int>();
    face.model = manifestPath.parent_path() / entry["model"].get<std::string>();
    io::Model model = loadModel(face.model.string());
    auto* surfaceModel = std::get_if<SurfaceModel>(&model);
    if (!surfaceModel || surfaceModel->trim.empty())
      throw InputError("MODEL", face.model.string(), field + " is not a trimmed surface (a face written by import)");
    outputs.reads(face.model, "MODEL's face");
    face.surface.emplace(Surface::create(std::move(*surfaceModel)));
    io::SampleLayout& layout = face.layout;
    layout.surface = true;
    layout.samplesU = job.samplesU;
    layout.samplesV = job.samplesV;
    layout.fields = job.fields;
    layout.precision = job.precision;
    layout.source = face.model.string();
    setSurfaceItems(face.surface->model(), layout);
    layout.itemCount = layout.totalItems;
    total += io::samplesInside(layout, face.surface->model().trim);
  }
  if (faces.empty()) throw InputError("MODEL", args.model, "the part has no converted face to sample");

  io::AtomicFile& out = outputs.add(args.out, "-o");
  io::AtomicFile* sidecar = nullptr;
  if (io::hasLayoutSidecar(job.format)) sidecar = &outputs.add(args.out + ".json", "-o");
  std::optional<sampling::Session> own;
  sampling::Session& session = shared ? *shared : own.emplace();
  const sampling::Report report = session.plan(*faces.front().surface, job.request);
  printNotices(report, args.quiet);

  io::TrimmedPointWriter writer(job.format, out, sidecar);
  const nlohmann::json part = {{"manifest", manifestPath.filename().string()},
                               {"manifest_sha256", io::sha256OfFile(manifestPath)},
                               {"faces", faces.size()},
                               {"faces_skipped_at_import", skipped},
                               {"device", report.device}};
  writer.beginPart(faces.front().layout, total, part);
  sampling::GridOptions options;
  options.threads = args.threads;
  options.chunkPoints = static_cast<size_t>(args.chunkPoints);
  options.slice = job.check;
  for (const PartFace& face : faces) {
    writer.nextFace(face.layout, face.surface->model().trim, face.id);
    GridSpec grid;
    grid.samplesU = job.samplesU;
    grid.samplesV = job.samplesV;
    grid.itemCount = face.layout.totalItems;
    session.sampleGrid(*face.surface, job.request, grid, job.fields, [&](const GridChunk& c) { writer.consume(c); },
                       options);
  }
  writer.finish();
  summary = "wrote " + args.out + " (" + std::to_string(faces.size()) + " faces, " + std::to_string(total) +
            " points inside their trim loops" + (sidecar ? ", layout in " + sidecar->target().string() : "") + ")";
  return true;
}

}  // namespace shapespline::cli
