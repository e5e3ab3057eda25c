#pragma once
// A part's manifest, DIR/part.json as `shapespline import` writes it (docs/cad.md): the format
// name, each face's id, model file, orientation and coedges, the edges and the shells. Face files are resolved by the named-file rule
// (io/named_file.h): inside the manifest's folder, or the manifest is refused.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace shapespline::io {

inline constexpr const char* kPartFormat = "shapespline-part";

// Whether `path` is a part manifest: a .json file whose top-level "format" is kPartFormat. The file
// is scanned for the name in blocks first (a model file may be 32 MiB of JSON, and the key may come
// after megabytes of faces and edges), and parsed only when the name occurs.
bool isPartManifest(const std::filesystem::path& path);

// One edge's run of a face's trim loop (docs/cad.md "Coedges"): the loop points start, start + 1,
// ..., start + t.size() - 1, modulo the loop's point count, lie on edge `edge` (an id of
// PartManifest::edges), point start + j at the edge's own parameter t[j].
struct PartCoedge {
  int edge = 0;
  int start = 0;
  std::vector<double> t;  // at least 2, finite
};

struct PartFaceEntry {
  int id = 0;
  std::string field;                         // "faces[3]", for messages
  std::optional<std::filesystem::path> model;  // none: not converted at import (part.json says why)
  bool reversed = false;                       // the face's normal is -(du x dv) of the model
  std::string surface;                         // the OCCT class of the face's own surface; may be empty
  std::vector<std::vector<PartCoedge>> coedges;  // per trim loop; empty in a manifest without them
};

struct PartEdgeEntry {
  int id = 0;
  bool degenerate = false;  // a point (a sphere's pole): no curve model
};

struct PartManifest {
  std::filesystem::path path;
  std::vector<PartFaceEntry> faces;
  std::vector<PartEdgeEntry> edges;       // empty where the manifest lists none
  std::vector<std::vector<int>> shells;   // each shell's face ids
  int skipped = 0;  // faces without a model
};

// Reads and checks the manifest: ModelError naming the key ("faces[3].model",
// "faces[3].coedges[0][2].edge") and the manifest, for a malformed entry, a face file that breaks the
// named-file rule, a coedge on an edge the manifest does not list, or a shell of unknown faces.
// The loop point counts are in the face files: a coedge's start is checked against them by whoever
// reads both.
PartManifest readPartManifest(const std::filesystem::path& path);

}  // namespace shapespline::io
