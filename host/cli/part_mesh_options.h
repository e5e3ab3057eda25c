#pragma once
// What `sample`, `render` and `view` share about a part's (or a trimmed face's) mesh: the options
// as given (--deflection, --relative-deflection, --angle, --max-triangles), checked into
// part::MeshOptions, the part read from its manifest or from one face with trim loops, and the
// mesher's budget refusal as the InputError of the option that asked for it.
#include <shapespline/io/model_json.h>
#include <shapespline/part/face_evaluator.h>
#include <shapespline/part/part_mesher.h>
#include <shapespline/part/part_model.h>

#include <filesystem>
#include <optional>
#include <string>

namespace CLI {
class App;
}
namespace shapespline::io {
class OutputSet;
}

namespace shapespline::cli {

struct PartMeshArgs {
  std::string deflection, relativeDeflection, angle;  // as given ("" = not given)
  long long maxTriangles = part::kDefaultTriangleBudget;
};

// Adds the four options; `relativeDefault` says what the command uses when neither deflection is given.
void addPartMeshOptions(CLI::App* sub, PartMeshArgs& args, const std::string& relativeDefault);

// The options' values checked (InputError naming the option): a deflection relative to `part`'s
// diagonal unless an absolute one is given; `defaultRelative` when neither is.
struct PartMeshSettings {
  part::MeshOptions options;
  std::optional<double> relative;  // the fraction of the diagonal, unless --deflection gave it
};
PartMeshSettings partMeshSettings(const PartMeshArgs& args, const part::Part& part, double defaultRelative,
                                  const std::string& model);

// The part of a manifest (`import`), each file it reads added to `outputs` when given; InputError
// naming `option` (the argument that named the manifest) when no face of it was converted.
part::Part loadPartManifest(const std::filesystem::path& manifest, io::OutputSet* outputs,
                            const std::string& option = "MODEL");

// What `render` and `view` draw as a part's mesh: a part's manifest, or a face model with trim
// loops (a part of one face). Any other model is read into `model` (InputError as loadModel), and
// then there is no part.
std::optional<part::Part> partToDraw(const std::string& path, io::Model& model);

// part::meshPart, with the budget's refusal an InputError naming the deflection option.
part::PartMesh meshOrRefuse(const part::Part& part, const PartMeshSettings& settings, const PartMeshArgs& args,
                            part::FaceEvaluator& evaluator);

}  // namespace shapespline::cli
