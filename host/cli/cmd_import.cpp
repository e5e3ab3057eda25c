// `shapespline import PART.(step|stp|iges|igs) -o DIR`: a CAD part as bspline models, one per face
// (with its trimming loops) and per edge, and DIR/part.json (docs/cad.md). When the build found
// Open CASCADE, the reading and converting half runs in the plugin libshapespline-occt.so, loaded
// here on demand (cad/part_plugin.h); otherwise the command says how to install it (exit 3).
#include <shapespline/cli/common.h>

#ifdef SHAPESPLINE_HAS_CAD
#include <shapespline/cad/part_plugin.h>

#include <dlfcn.h>
#endif

#include <cstdio>
#include <filesystem>
#include <memory>
#include <new>

namespace shapespline::cli {
namespace {

#ifdef SHAPESPLINE_HAS_CAD
// The plugin's entry, loaded once and never unloaded (OCCT keeps process-wide tables).
cad::ConvertPartFn loadConvertPart() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path bin = fs::read_symlink("/proc/self/exe", ec).parent_path();
  std::string tried;
  for (const fs::path& dir : {bin, bin / SHAPESPLINE_PLUGIN_DIR_FROM_BIN}) {
    const fs::path file = (dir / cad::kPluginFile).lexically_normal();
    if (!fs::exists(file, ec)) {
      tried += (tried.empty() ? "" : ", ") + file.string();
      continue;
    }
    void* plugin = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!plugin) throw RuntimeError("import", file.string(), std::string("cannot load the plugin: ") + ::dlerror());
    void* entry = ::dlsym(plugin, cad::kConvertPartSymbol);
    if (!entry)
      throw RuntimeError("import", file.string(),
                         std::string("the plugin has no ") + cad::kConvertPartSymbol + " (from another build?)");
    return reinterpret_cast<cad::ConvertPartFn>(entry);
  }
  throw RuntimeError("import", tried,
                     std::string("Open CASCADE's importer ") + cad::kPluginFile +
                         " is not in any folder this shapespline looks in: reinstall shapespline, or rebuild it");
}

// cad::convertPart through the plugin, its failures raised as this command's errors.
cad::ConvertedPart convertPart(const std::string& part, const cad::ImportOptions& options) {
  static const cad::ConvertPartFn convert = loadConvertPart();
  cad::ConvertedPart out;
  cad::PluginFailure failure;
  convert(part.c_str(), options, out, failure);
  using Kind = cad::PluginFailure::Kind;
  switch (failure.kind) {
    case Kind::None: return out;
    case Kind::Cad: throw InputError("PART", failure.file, failure.entity + ": " + failure.message);
    case Kind::BadInput: throw std::invalid_argument(failure.message);
    case Kind::OutOfMemory: throw std::bad_alloc();
    case Kind::Runtime: break;
  }
  throw std::runtime_error(failure.message);
}
#endif

struct ImportArgs {
  std::string part, out;
  double trimTolerance = 1e-5;
  bool quiet = false;
};

void runImport(const ImportArgs& a) {
#ifdef SHAPESPLINE_HAS_CAD
  if (!(a.trimTolerance > 0.0 && a.trimTolerance <= 0.01))
    throw InputError("--trim-tolerance", std::to_string(a.trimTolerance), "must lie in (0, 0.01]");
  cad::ImportOptions options;
  options.trimTolerance = a.trimTolerance;
  const cad::ConvertedPart converted = convertPart(a.part, options);
  cad::writePart(converted, a.part, a.out);
  const cad::ImportSummary& s = converted.summary;
  // A face or edge OCCT could not convert does not stop the import (part.json lists it); each is
  // named here so that it is not missed, unless asked to be quiet.
  if (a.quiet) return;
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
  addQuietFlag(sub, a->quiet,
                "no summary and no warnings (faces and edges that did not convert stay listed in part.json)");
  sub->footer(kExitCodeHelp);
  sub->callback([a] { runImport(*a); });
}

}  // namespace shapespline::cli
