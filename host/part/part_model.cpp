#include <shapespline/core/parallel_for.h>
#include <shapespline/core/validate.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/model_json.h>
#include <shapespline/part/part_model.h>

#include <algorithm>
#include <exception>
#include <optional>
#include <unordered_map>
#include <vector>

namespace shapespline::part {

const io::PartEdgeEntry* Part::edge(int id) const {
  // part.json lists edges by id in order, so the id is usually the position plus one.
  if (id >= 1 && static_cast<size_t>(id) <= edges.size() && edges[static_cast<size_t>(id) - 1].id == id)
    return &edges[static_cast<size_t>(id) - 1];
  const auto it = std::find_if(edges.begin(), edges.end(), [&](const io::PartEdgeEntry& e) { return e.id == id; });
  return it == edges.end() ? nullptr : &*it;
}

bool Part::closed() const {
  if (skipped > 0 || faces.empty()) return false;
  std::unordered_map<int, int> uses;
  for (const PartFace& face : faces) {
    if (face.coedges.empty() && !face.surface.model().trim.empty()) return false;  // no edges to match
    for (const auto& loop : face.coedges)
      for (const io::PartCoedge& coedge : loop) ++uses[coedge.edge];
  }
  for (const auto& [id, count] : uses) {
    const io::PartEdgeEntry* entry = edge(id);
    if (count != 2 && !(entry && entry->degenerate)) return false;
  }
  return true;
}

namespace {

// One face of the manifest, read and built; none for a face that was not converted at import.
std::optional<PartFace> loadFace(io::PartFaceEntry& entry) {
  if (!entry.model) return std::nullopt;
  const std::string key = entry.field + ".model";
  io::Model model;
  try {
    model = io::loadModelFile(*entry.model);
  } catch (const ModelError& e) {
    throw ModelError(key + " (" + io::shortText(entry.model->filename().string()) + "): " + e.field(), e.value(),
                     e.rule());
  }
  auto* surface = std::get_if<SurfaceModel>(&model);
  if (!surface || surface->trim.empty())
    throw ModelError(key, io::shortText(entry.model->string()), "is not a trimmed surface (a face written by import)");
  if (!entry.coedges.empty() && entry.coedges.size() != surface->trim.loops.size())
    throw ModelError(entry.field + ".coedges", std::to_string(entry.coedges.size()) + " loops",
                     "must give the coedges of each of the face's " + std::to_string(surface->trim.loops.size()) +
                         " trim loops");
  return PartFace{entry.id,           entry.field, *entry.model, Surface::create(std::move(*surface)), entry.reversed,
                  std::move(entry.coedges), entry.surface};
}

}  // namespace

Part loadPart(const std::filesystem::path& manifestPath) {
  io::PartManifest manifest = io::readPartManifest(manifestPath);
  Part part;
  part.manifest = manifestPath;
  part.edges = std::move(manifest.edges);
  part.shells = std::move(manifest.shells);
  part.skipped = manifest.skipped;
  // The face files are read and built on every core (a part of a thousand faces is tens of MB of
  // JSON), each into its own slot; the first face in the manifest's order that fails is the error.
  std::vector<std::optional<PartFace>> faces(manifest.faces.size());
  std::vector<std::exception_ptr> errors(manifest.faces.size());
  parallelFor(manifest.faces.size(), 0, [&](size_t f) {
    try {
      faces[f] = loadFace(manifest.faces[f]);
    } catch (...) {
      errors[f] = std::current_exception();
    }
  });
  for (size_t f = 0; f < faces.size(); ++f) {
    if (errors[f]) std::rethrow_exception(errors[f]);
    if (faces[f]) part.faces.push_back(std::move(*faces[f]));
  }
  return part;
}

Part faceAsPart(const std::filesystem::path& model, Surface surface) {
  Part part;
  part.manifest = model;
  PartFace face{1, "face", model, std::move(surface), false, {}, {}};
  const auto& loops = face.surface.model().trim.loops;
  for (size_t l = 0; l < loops.size(); ++l) {
    io::PartCoedge coedge{static_cast<int>(l) + 1, 0, {}};
    for (size_t k = 0; k <= loops[l].size(); ++k) coedge.t.push_back(static_cast<double>(k));
    face.coedges.push_back({coedge});
    part.edges.push_back({static_cast<int>(l) + 1, false});
  }
  part.faces.push_back(std::move(face));
  part.shells.push_back({1});
  return part;
}

}  // namespace shapespline::part
