#pragma once
// A CAD part as `shapespline import` wrote it (docs/cad.md): every converted face a built Surface
// with its trim loops, whether its outward normal is reversed, and the coedges of each loop (which
// edge each run of loop points lies on, at which of the edge's parameters); the edges (degenerate
// ones are points: a sphere's pole); the shells. The data the mesher and the other part tools read;
// nothing here evaluates.
#include <shapespline/core/surface.h>
#include <shapespline/io/part_manifest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace shapespline::part {

struct PartFace {
  int id = 0;
  std::string field;  // "faces[3]", for messages
  std::filesystem::path model;
  Surface surface;
  bool reversed = false;
  std::vector<std::vector<io::PartCoedge>> coedges;  // per trim loop, in the loop's order
  std::string surfaceClass;  // the OCCT class of the face's own surface (part.json's `surface`); may be empty
};

struct Part {
  std::filesystem::path manifest;
  std::vector<PartFace> faces;           // the converted faces, in part.json's order
  std::vector<io::PartEdgeEntry> edges;  // as part.json lists them
  std::vector<std::vector<int>> shells;  // face ids
  int skipped = 0;                       // faces not converted at import

  // The entry of edge `id`, nullptr when the part has none.
  const io::PartEdgeEntry* edge(int id) const;
  // True when the faces close: none was skipped at import and every edge a coedge names (a point
  // edge aside) is named by exactly two coedges, so the part bounds a solid and has an outside.
  bool closed() const;
};

// Reads the manifest and builds every converted face. ModelError naming the manifest's key
// ("faces[3].model: ...") for a face file that is not a trimmed surface or breaks a model rule.
Part loadPart(const std::filesystem::path& manifest);

// A trimmed face on its own (`sample FACE.json --trim -o face.glb`): a part of one face whose every
// trim loop is one closed edge of its own, its points at t = 0, 1, 2, ... (loop l is edge l + 1).
Part faceAsPart(const std::filesystem::path& model, Surface surface);

}  // namespace shapespline::part
