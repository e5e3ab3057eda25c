#include <shapespline/core/model.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/named_file.h>
#include <shapespline/io/part_manifest.h>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <optional>

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

PartManifest readPartManifest(const std::filesystem::path& path) {
  PartManifest m;
  m.path = path;
  const std::string where = " in " + shortText(path.string(), 200);
  const nlohmann::json j = parseJsonText(readInputFile(path, "MODEL"), "MODEL");
  if (!j.is_object() || !j.contains("faces") || !j["faces"].is_array())
    throw ModelError("faces", "", "a part manifest needs a \"faces\" array" + where);
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
    const nlohmann::json& model = entry["model"];
    if (model.is_null()) {
      ++m.skipped;  // not converted at import; part.json says why
      continue;
    }
    if (!model.is_string()) throw ModelError(face.field + ".model", shortValue(model), "must be a file name" + where);
    face.model = resolveNamedFile(rule, model.get<std::string>(), face.field + ".model");
  }
  return m;
}

}  // namespace shapespline::io
