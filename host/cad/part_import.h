#pragma once
// `shapespline import`: a STEP or IGES part, read by Open CASCADE, as shapespline models
// (docs/cad.md). Every face becomes a `bspline` surface model (with weights where it is rational)
// restricted to the face's parameter bounds, its trimming loops under `trim`; every edge a `bspline`
// curve model; part.json lists faces, edges, shells, units and the source file's SHA-256. Faces and
// edges that cannot be converted are listed in part.json with the reason. No OCCT type appears here.
#include <shapespline/io/output_set.h>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace shapespline::cad {

struct ImportOptions {
  // Largest deviation of a trim polyline from the face's edges, in the B-spline's parameters, as a
  // fraction of the larger side of the face's parameter domain (docs/cad.md "Tolerances").
  double trimTolerance = 1e-5;
  // Part files larger than this are refused before OCCT reads them (OCCT holds the whole model).
  std::uint64_t maxFileBytes = std::uint64_t{1} << 30;
};

struct ImportSummary {
  int faces = 0, facesSkipped = 0, edges = 0, edgesSkipped = 0, shells = 0;
  std::string format, units;
  std::vector<std::string> skipped;  // "face 3: <reason>", as part.json lists them
};

// A part that cannot be imported: `file` the part, `entity` what in it ("(file)", "(part)",
// "face 3"), `reason` the rule. Exit 2.
class CadError : public std::invalid_argument {
 public:
  CadError(std::string file, std::string entity, std::string reason)
      : std::invalid_argument(file + ": " + entity + ": " + reason),
        file_(std::move(file)),
        entity_(std::move(entity)),
        reason_(std::move(reason)) {}
  const std::string& file() const { return file_; }
  const std::string& entity() const { return entity_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_, entity_, reason_;
};

// A part read and converted in memory: the text of every file importPart writes (face_NNNN.json,
// edge_NNNN.json, part.json last) and the summary.
struct ConvertedPart {
  std::vector<std::pair<std::string, std::string>> files;  // file name, text
  ImportSummary summary;
};

// The Open CASCADE half of the import: reads `part` and converts it, writing nothing. Throws
// CadError for a part that cannot be imported, std::invalid_argument for bad options.
ConvertedPart convertPart(const std::filesystem::path& part, const ImportOptions& options = {});

// The writing half, without Open CASCADE (the CLI runs convertPart in a plugin, cad/part_plugin.h,
// and writes here): the files into `outDir` as one output set (io::OutputSet: all of them or none).
inline void writePart(const ConvertedPart& converted, const std::filesystem::path& part,
                      const std::filesystem::path& outDir) {
  std::filesystem::create_directories(outDir);
  io::OutputSet outputs;
  outputs.reads(part, "PART");
  for (const auto& [name, text] : converted.files) outputs.add(outDir / name, "-o").write(text);
  outputs.commit();
}

// Reads `part` and writes DIR/face_NNNN.json, DIR/edge_NNNN.json and DIR/part.json as one output
// set: convertPart, then writePart. The part is read and converted in memory before any output is
// opened, so a failure (or a crash inside OCCT) leaves nothing behind.
ImportSummary importPart(const std::filesystem::path& part, const std::filesystem::path& outDir,
                         const ImportOptions& options = {});

}  // namespace shapespline::cad
