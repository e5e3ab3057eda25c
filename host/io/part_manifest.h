#pragma once
// A part's manifest, DIR/part.json as `shapespline import` writes it (docs/cad.md): the format
// name, and each face's id and model file. Face files are resolved by the named-file rule
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

struct PartFaceEntry {
  int id = 0;
  std::string field;                         // "faces[3]", for messages
  std::optional<std::filesystem::path> model;  // none: not converted at import (part.json says why)
};

struct PartManifest {
  std::filesystem::path path;
  std::vector<PartFaceEntry> faces;
  int skipped = 0;  // faces without a model
};

// Reads and checks the manifest: ModelError naming the key ("faces[3].model") and the manifest, for
// a malformed entry or a face file that breaks the named-file rule.
PartManifest readPartManifest(const std::filesystem::path& path);

}  // namespace shapespline::io
