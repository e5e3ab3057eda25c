// `sample PART/part.json -o part.(ply|obj|stl|glb|gltf)` and `sample FACE.json --trim -o face.glb`:
// the part's (or the face's) watertight mesh at a deflection and an angle (docs/cad.md "Meshing a
// part"), built by host/part on the CPU, its surface points evaluated on the job's device.
#include <shapespline/cli/cmd_sample.h>
#include <shapespline/cli/common.h>
#include <shapespline/cli/exit_codes.h>
#include <shapespline/cli/part_mesh_options.h>
#include <shapespline/core/model.h>
#include <shapespline/core/value_text.h>
#include <shapespline/io/job_metadata.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/triangle_mesh.h>
#include <shapespline/part/face_triangulation.h>
#include <shapespline/part/part_mesher.h>
#include <shapespline/sampling/session.h>

#include <nlohmann/json.hpp>

#include <optional>

namespace shapespline::cli {

bool meshesTrimmed(const SampleArgs& args, io::OutputFormat format, bool part) {
  if (!(part || args.trim) || !io::triangleMeshFormat(format)) return false;
  // A PLY with a grid stays the point cloud it always was; every other mesh format is a mesh.
  const bool grid = !args.grid.empty() || !args.samples.empty();
  if (format == io::OutputFormat::Ply && grid) return false;
  if (grid)
    throw InputError(args.grid.empty() ? "--samples" : "--grid", args.grid.empty() ? args.samples : args.grid,
                     "a trimmed mesh is made to a deflection (--deflection, --relative-deflection), not a grid; a "
                     "grid of a part or trimmed face is a point cloud (.ply, .npy, .f32, .f64, .csv)");
  return true;
}

bool meshPartInto(const SampleArgs& args, io::OutputFormat format, const sampling::DeviceRequest& request,
                  io::OutputSet& outputs, std::string& summary, sampling::Session& session) {
  const auto refuse = [&](bool given, const std::string& option, const std::string& value, const std::string& why) {
    if (given) throw InputError(option, value, why);
  };
  const std::string meshOnly = "does not apply to a trimmed mesh";
  refuse(!args.shard.empty(), "--shard", args.shard, "a part's mesh is one file (shard its point cloud instead)");
  refuse(args.derivatives, "--derivatives", "", meshOnly);
  refuse(!args.fields.empty(), "--fields", args.fields, meshOnly);
  refuse(args.meshLayoutGiven, "--mesh-layout", args.meshLayout, meshOnly);
  refuse(!args.saveModel.empty(), "--save-model", args.saveModel, meshOnly);

  const std::filesystem::path modelPath(args.model);
  std::optional<part::Part> part;
  if (args.trim) {
    io::Model model = loadModel(args.model, args.allowOutsideArrays);
    auto* surface = std::get_if<SurfaceModel>(&model);
    if (!surface || surface->trim.empty())
      throw InputError("--trim", args.model, "the model has no trim loops (the faces `shapespline import` writes have them)");
    part.emplace(part::faceAsPart(modelPath, Surface::create(std::move(*surface))));
    outputs.reads(modelPath, "MODEL");
  } else {
    part.emplace(loadPartManifest(modelPath, &outputs));
  }
  PartMeshSettings settings = partMeshSettings(args.mesh, *part, 1e-3, args.model);
  settings.options.threads = args.threads;

  const sampling::DeviceRequest meshRequest = part::meshDeviceRequest(request);
  const sampling::Report report = session.plan(part->faces.front().surface, meshRequest);
  printNotices(report, args.quiet);
  std::optional<part::CpuFaceEvaluator> cpu;
  std::optional<part::SessionFaceEvaluator> gpu;
  part::FaceEvaluator& evaluator =
      report.gpu ? static_cast<part::FaceEvaluator&>(gpu.emplace(session, meshRequest, report.device)) : cpu.emplace();
  part::PartMesh mesh = meshOrRefuse(*part, settings, args.mesh, evaluator);
  if (!args.normals) mesh.mesh.normals.clear();

  nlohmann::json description = {{"source", modelPath.filename().string()},
                                {"source_sha256", io::sha256OfFile(modelPath)},
                                {"faces", mesh.faces},
                                {"faces_skipped_at_import", part->skipped},
                                {"edges", mesh.edges},
                                {"deflection", settings.options.deflection},
                                {"angle", settings.options.angle},
                                {"triangles", mesh.mesh.triangles.size()},
                                {"vertices", mesh.mesh.positions.size()},
                                {"open_edges", mesh.boundaryEdges},
                                {"non_manifold_edges", mesh.nonManifoldEdges},
                                {"device", evaluator.device()}};
  if (settings.relative) description["relative_deflection"] = *settings.relative;
  io::AtomicFile& out = outputs.add(args.out, "-o");
  io::AtomicFile* bin = format == io::OutputFormat::Gltf ? &outputs.add(io::gltfBufferPath(args.out), "-o") : nullptr;
  try {
    io::writeTriangleMesh(mesh.mesh, format, description, request.precision == Precision::Double, out, bin);
  } catch (const std::invalid_argument& e) {
    throw InputError("-o", args.out, e.what());
  }
  summary = "wrote " + args.out + " (" + std::to_string(mesh.faces) + " faces, " + std::to_string(mesh.edges) +
            " edges, " + std::to_string(mesh.mesh.triangles.size()) + " triangles, " +
            std::to_string(mesh.mesh.positions.size()) + " vertices, " + std::to_string(mesh.boundaryEdges) +
            " open edges, deflection " + shortestText(settings.options.deflection) + ", " + evaluator.device() + ")";
  return true;
}

}  // namespace shapespline::cli
