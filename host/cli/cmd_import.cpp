// `shapespline import PART.(step|stp|iges|igs) -o DIR`: a CAD part as bspline models, one per face
// (with its trimming loops) and per edge, and DIR/part.json (docs/cad.md). Built with Open CASCADE
// when the build found it; otherwise the command says how to install it (exit 3).
#include <shapespline/cli/common.h>

#ifdef SHAPESPLINE_HAS_CAD
#include <shapespline/cad/part_import.h>
#endif

#include <cstdio>
#include <memory>

namespace shapespline::cli {
namespace {

struct ImportArgs {
  std::string part, out;
  double trimTolerance = 1e-5;
};

void runImport(const ImportArgs& a) {
#ifdef SHAPESPLINE_HAS_CAD
  if (!(a.trimTolerance > 0.0 && a.trimTolerance <= 0.01))
    throw InputError("--trim-tolerance", std::to_string(a.trimTolerance), "must lie in (0, 0.01]");
  cad::ImportOptions options;
  options.trimTolerance = a.trimTolerance;
  cad::ImportSummary s;
  try {
    s = cad::importPart(a.part, a.out, options);
  } catch (const cad::CadError& e) {
    throw InputError("PART", e.file(), e.entity() + ": " + e.reason());
  }
  // A face or edge OCCT could not convert does not stop the import (part.json lists it); each is
  // named here so that it is not missed.
  for (const std::string& why : s.skipped)
    std::fprintf(stderr, "shapespline: warning: %s: %s (not converted; listed in part.json)\n", a.part.c_str(), why.c_str());
  std::printf("imported %s (%s, %s): %d faces, %d edges, %d shells into %s/", a.part.c_str(), s.format.c_str(),
              s.units.c_str(), s.faces, s.edges, s.shells, a.out.c_str());
  if (s.facesSkipped + s.edgesSkipped > 0)
    std::printf(" (%d faces and %d edges not converted: see part.json)", s.facesSkipped, s.edgesSkipped);
  std::printf("\n");
#else
  (void)a;
  throw RuntimeError("import", "",
                     "this shapespline was built without Open CASCADE: install it (apt-get install "
                     "libocct-data-exchange-dev, or bash scripts/setup.sh) and rebuild");
#endif
}

}  // namespace

void registerImport(CLI::App& app) {
  auto a = std::make_shared<ImportArgs>();
  CLI::App* sub = app.add_subcommand("import", "Import a STEP or IGES part: one bspline model per face (trimmed) and edge, and part.json.");
  sub->add_option("PART", a->part, "a .step/.stp or .iges/.igs file")->required();
  sub->add_option("-o,--output", a->out, "folder for face_NNNN.json, edge_NNNN.json and part.json")->required();
  sub->add_option("--trim-tolerance", a->trimTolerance,
                  "largest deviation of a trim polyline from the face's edges, as a fraction of the face's parameter "
                  "domain (default 1e-5)");
  sub->footer(kExitCodeHelp);
  sub->callback([a] { runImport(*a); });
}

}  // namespace shapespline::cli
