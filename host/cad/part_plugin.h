#pragma once
// The boundary between the CLI and libshapespline-occt.so, the plugin that holds the Open CASCADE
// half of `import` (cad::convertPart). The CLI loads it with dlopen when `import` runs, so that no
// other command loads OCCT's 18 libraries: they cost every process start about 0.055 s in Release
// and 0.035 s under ASan (shapespline --version, docs/performance.md). No OCCT type appears here,
// and no exception crosses the boundary: a failure comes back as plain data for the CLI to raise
// as its own error.
#include <shapespline/cad/part_import.h>

#include <string>

namespace shapespline::cad {

struct PluginFailure {
  enum class Kind { None, Cad, BadInput, OutOfMemory, Runtime };
  Kind kind = Kind::None;
  std::string file, entity;  // Cad: CadError::file() and entity()
  std::string message;       // Cad: CadError::reason(); otherwise what()
};

// convertPart(part, options) into `out`, or `failure` set.
using ConvertPartFn = void (*)(const char* part, const ImportOptions& options, ConvertedPart& out,
                               PluginFailure& failure);

// The plugin's file name, where the CLI looks for it: beside the executable (a build tree), then in
// SHAPESPLINE_PLUGIN_DIR_FROM_BIN relative to it (an install: CMAKE_INSTALL_LIBDIR/shapespline).
inline constexpr const char* kPluginFile = "libshapespline-occt.so";
// Versioned: a plugin from another build of a different layout is refused by name.
inline constexpr const char* kConvertPartSymbol = "shapespline_convert_part_v1";

}  // namespace shapespline::cad
