#include <shapespline/cli/part_mesh_options.h>

#include <shapespline/cli/common.h>
#include <shapespline/core/surface.h>
#include <shapespline/core/value_text.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/part_manifest.h>
#include <shapespline/part/face_triangulation.h>

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <numbers>

namespace shapespline::cli {
namespace {

// A positive finite number from an option's text.
double positiveOption(const std::string& text, const std::string& option, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || !(v > 0.0))
    throw InputError(option, text, "must be a finite number > 0 (" + what + ")");
  return v;
}

}  // namespace

void addPartMeshOptions(CLI::App* sub, PartMeshArgs& args, const std::string& relativeDefault) {
  sub->add_option("--deflection", args.deflection,
                  "a part's or trimmed face's mesh: largest distance from the surfaces, in model units");
  sub->add_option("--relative-deflection", args.relativeDeflection,
                  "the same as a fraction of the part's diagonal (default " + relativeDefault + ")");
  sub->add_option("--angle", args.angle, "a trimmed mesh's largest turn across a triangle or edge, radians (default 0.5)");
  sub->add_option("--max-triangles", args.maxTriangles,
                  "a trimmed mesh needing more triangles is refused (default 50000000)");
}

PartMeshSettings partMeshSettings(const PartMeshArgs& args, const part::Part& part, double defaultRelative,
                                  const std::string& model) {
  if (!args.deflection.empty() && !args.relativeDeflection.empty())
    throw InputError("--deflection", args.deflection,
                     "give --deflection (absolute) or --relative-deflection (of the part's diagonal), not both");
  PartMeshSettings s;
  part::MeshOptions& o = s.options;
  o.angle = args.angle.empty() ? 0.5 : positiveOption(args.angle, "--angle", "radians, below pi");
  if (o.angle >= std::numbers::pi) throw InputError("--angle", args.angle, "must be below pi (radians)");
  o.maxTriangles = args.maxTriangles;
  if (o.maxTriangles <= 0) throw InputError("--max-triangles", std::to_string(args.maxTriangles), "must be > 0");
  if (!args.deflection.empty()) {
    o.deflection = positiveOption(args.deflection, "--deflection", "model units");
    return s;
  }
  s.relative = args.relativeDeflection.empty()
                   ? defaultRelative
                   : positiveOption(args.relativeDeflection, "--relative-deflection", "of the diagonal");
  o.deflection = *s.relative * part::partDiagonal(part);
  if (!(o.deflection > 0.0) || !std::isfinite(o.deflection))
    throw InputError("MODEL", model, "the part has no extent to take a relative deflection of");
  return s;
}

part::Part loadPartManifest(const std::filesystem::path& manifest, io::OutputSet* outputs, const std::string& option) {
  part::Part part = part::loadPart(manifest);
  if (part.faces.empty()) throw InputError(option, manifest.string(), "the part has no converted face");
  if (outputs) {
    outputs->reads(manifest, option);
    for (const part::PartFace& face : part.faces)
      if (face.model != manifest) outputs->reads(face.model, option + "'s face");
  }
  return part;
}

std::optional<part::Part> partToDraw(const std::string& path, io::Model& model) {
  if (io::isPartManifest(path)) return loadPartManifest(path, nullptr);
  model = loadModel(path);
  if (const auto* face = std::get_if<SurfaceModel>(&model); face && !face->trim.empty())
    return part::faceAsPart(path, Surface::create(*face));
  return std::nullopt;
}

part::PartMesh meshOrRefuse(const part::Part& part, const PartMeshSettings& settings, const PartMeshArgs& args,
                            part::FaceEvaluator& evaluator) {
  try {
    return part::meshPart(part, settings.options, evaluator);
  } catch (const part::TriangleBudgetExceeded& e) {
    const bool relative = args.deflection.empty();
    throw InputError(relative ? "--relative-deflection" : "--deflection",
                     relative ? shortestText(settings.relative.value_or(0.0)) : args.deflection,
                     std::string(e.what()) + "; raise the deflection or --max-triangles");
  }
}

}  // namespace shapespline::cli
