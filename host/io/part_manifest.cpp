#include <shapespline/core/model.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/named_file.h>
#include <shapespline/io/part_manifest.h>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <unordered_set>

namespace shapespline::io {

bool isPartManifest(const std::filesystem::path& path) {
  if (path.extension() != ".json") return false;
  // Opened as every input is (a FIFO never blocks; a directory or device is no manifest: the model
  // loader then says why). Blocks overlap by the name's length, so a name cut by a block boundary
  // is still found.
  std::optional<InputFd> file;
  try {
    file.emplace(path, "MODEL");
  } catch (const std::exception&) {
    return false;
  }
  const size_t nameLength = std::strlen(kPartFormat);
  std::string block(size_t{1} << 20, '\0');
  size_t kept = 0;
  bool found = false;
  while (!found) {
    const ssize_t n = ::read(file->get(), block.data() + kept, block.size() - kept);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    const size_t have = kept + static_cast<size_t>(n);
    found = std::string_view(block.data(), have).find(kPartFormat) != std::string_view::npos;
    kept = std::min(have, nameLength - 1);
    std::memmove(block.data(), block.data() + have - kept, kept);
  }
  if (!found) return false;
  const nlohmann::json j = parseJsonText(readInputFile(path, "MODEL"), "MODEL");
  return j.is_object() && j.contains("format") && j["format"] == kPartFormat;
}

namespace {

// An id as part.json writes them: a non-negative integer that fits an int.
bool isId(const nlohmann::json& v) {
  return v.is_number_integer() && v.get<std::int64_t>() >= 0 && v.get<std::int64_t>() <= std::numeric_limits<int>::max();
}

std::vector<PartEdgeEntry> readEdges(const nlohmann::json& j, const std::string& where,
                                     std::unordered_set<int>& ids) {
  std::vector<PartEdgeEntry> edges;
  if (!j.contains("edges")) return edges;  // a hand-made manifest of faces only
  const nlohmann::json& list = j["edges"];
  if (!list.is_array()) throw ModelError("edges", shortValue(list), "must be an array" + where);
  edges.reserve(list.size());
  for (size_t i = 0; i < list.size(); ++i) {
    const nlohmann::json& entry = list[i];
    const std::string field = "edges[" + std::to_string(i) + "]";
    if (!entry.is_object() || !entry.contains("id") || !isId(entry["id"]))
      throw ModelError(field, shortValue(entry), "an edge needs a non-negative integer \"id\"" + where);
    PartEdgeEntry& edge = edges.emplace_back();
    edge.id = entry["id"].get<int>();
    if (!ids.insert(edge.id).second)
      throw ModelError(field + ".id", std::to_string(edge.id), "is the id of an earlier edge" + where);
    if (const auto d = entry.find("degenerate"); d != entry.end()) {
      if (!d->is_boolean()) throw ModelError(field + ".degenerate", shortValue(*d), "must be true or false" + where);
      edge.degenerate = d->get<bool>();
    }
  }
  return edges;
}

std::vector<std::vector<PartCoedge>> readCoedges(const nlohmann::json& list, const std::string& field,
                                                 const std::unordered_set<int>& edgeIds, const std::string& where) {
  if (!list.is_array()) throw ModelError(field, shortValue(list), "must be an array of loops" + where);
  std::vector<std::vector<PartCoedge>> loops(list.size());
  for (size_t l = 0; l < list.size(); ++l) {
    const nlohmann::json& loop = list[l];
    const std::string loopField = field + "[" + std::to_string(l) + "]";
    if (!loop.is_array() || loop.empty())
      throw ModelError(loopField, shortValue(loop), "a loop's coedges are a non-empty array" + where);
    loops[l].reserve(loop.size());
    for (size_t c = 0; c < loop.size(); ++c) {
      const nlohmann::json& entry = loop[c];
      const std::string at = loopField + "[" + std::to_string(c) + "]";
      if (!entry.is_object() || !entry.contains("edge") || !entry.contains("start") || !entry.contains("t"))
        throw ModelError(at, shortValue(entry), "a coedge is {\"edge\", \"start\", \"t\"}" + where);
      PartCoedge& coedge = loops[l].emplace_back();
      const nlohmann::json& edge = entry["edge"];
      if (!isId(edge) || !edgeIds.count(edge.get<int>()))
        throw ModelError(at + ".edge", shortValue(edge), "is not an edge id of the part" + where);
      coedge.edge = edge.get<int>();
      const nlohmann::json& start = entry["start"];
      if (!isId(start)) throw ModelError(at + ".start", shortValue(start), "must be a non-negative integer" + where);
      coedge.start = start.get<int>();
      const nlohmann::json& t = entry["t"];
      if (!t.is_array() || t.size() < 2)
        throw ModelError(at + ".t", shortValue(t), "a coedge's parameters are an array of at least 2 numbers" + where);
      coedge.t.reserve(t.size());
      for (size_t k = 0; k < t.size(); ++k) {
        if (!t[k].is_number() || !std::isfinite(t[k].get<double>()))
          throw ModelError(at + ".t[" + std::to_string(k) + "]", shortValue(t[k]), "must be a finite number" + where);
        coedge.t.push_back(t[k].get<double>());
      }
    }
  }
  return loops;
}

std::vector<std::vector<int>> readShells(const nlohmann::json& j, const std::unordered_set<int>& faceIds,
                                         const std::string& where) {
  std::vector<std::vector<int>> shells;
  if (!j.contains("shells")) return shells;
  const nlohmann::json& list = j["shells"];
  if (!list.is_array()) throw ModelError("shells", shortValue(list), "must be an array" + where);
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string field = "shells[" + std::to_string(i) + "]";
    const nlohmann::json& entry = list[i];
    if (!entry.is_object() || !entry.contains("faces") || !entry["faces"].is_array())
      throw ModelError(field, shortValue(entry), "a shell needs a \"faces\" array" + where);
    std::vector<int>& shell = shells.emplace_back();
    const nlohmann::json& faces = entry["faces"];
    shell.reserve(faces.size());
    for (size_t k = 0; k < faces.size(); ++k) {
      const nlohmann::json& id = faces[k];
      if (!isId(id) || !faceIds.count(id.get<int>()))
        throw ModelError(field + ".faces[" + std::to_string(k) + "]", shortValue(id), "is not a face id of the part" + where);
      shell.push_back(id.get<int>());
    }
  }
  return shells;
}

}  // namespace

PartManifest readPartManifest(const std::filesystem::path& path) {
  PartManifest m;
  m.path = path;
  const std::string where = " in " + shortText(path.string(), 200);
  const nlohmann::json j = parseJsonText(readInputFile(path, "MODEL"), "MODEL");
  if (!j.is_object() || !j.contains("faces") || !j["faces"].is_array())
    throw ModelError("faces", "", "a part manifest needs a \"faces\" array" + where);
  std::unordered_set<int> edgeIds, faceIds;
  m.edges = readEdges(j, where, edgeIds);
  NamedFileRule rule;
  rule.folder = path.parent_path();
  rule.namer = shortText(path.string(), 200);
  for (size_t i = 0; i < j["faces"].size(); ++i) {
    const nlohmann::json& entry = j["faces"][i];
    PartFaceEntry& face = m.faces.emplace_back();
    face.field = "faces[" + std::to_string(i) + "]";
    if (!entry.is_object() || !entry.contains("id") || !entry["id"].is_number_integer() || !entry.contains("model"))
      throw ModelError(face.field, shortValue(entry), "a face needs an integer \"id\" and a \"model\"" + where);
    const nlohmann::json& id = entry["id"];
    // Face ids are written as numbers in fp32 records too: exact up to 2^24.
    if (id.get<std::int64_t>() < 0 || id.get<std::int64_t>() > (std::int64_t{1} << 24))
      throw ModelError(face.field + ".id", shortValue(id), "a face id is an integer from 0 to 2^24" + where);
    face.id = id.get<int>();
    faceIds.insert(face.id);
    const nlohmann::json& model = entry["model"];
    if (model.is_null()) {
      ++m.skipped;  // not converted at import; part.json says why
      continue;
    }
    if (!model.is_string()) throw ModelError(face.field + ".model", shortValue(model), "must be a file name" + where);
    face.model = resolveNamedFile(rule, model.get<std::string>(), face.field + ".model");
    if (const auto r = entry.find("reversed"); r != entry.end()) {
      if (!r->is_boolean()) throw ModelError(face.field + ".reversed", shortValue(*r), "must be true or false" + where);
      face.reversed = r->get<bool>();
    }
    if (const auto t = entry.find("surface"); t != entry.end()) {
      if (!t->is_string()) throw ModelError(face.field + ".surface", shortValue(*t), "must be a string" + where);
      face.surface = t->get<std::string>();
    }
    if (const auto c = entry.find("coedges"); c != entry.end())  // absent before coedges were written
      face.coedges = readCoedges(*c, face.field + ".coedges", edgeIds, where);
  }
  m.shells = readShells(j, faceIds, where);
  return m;
}

}  // namespace shapespline::io
