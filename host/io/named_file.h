#pragma once
// The one rule for every file that a model or a part manifest names by name (a `.npy` array, a
// part's face or edge model; docs/format.md "Files a model names"): the name is relative to the
// folder of the file that names it and must stay inside that folder. Refused: an empty name, an
// absolute name, a name whose `..` leads out of the folder, a symbolic link (anywhere on the way)
// that leads out of it, and a file that does not exist. Links that stay inside are followed.
// Nothing of the named file is read here, so no error can quote its bytes.
#include <filesystem>
#include <string>

namespace shapespline::io {

struct NamedFileRule {
  // Where the name is resolved: the folder of the naming file ("" is the working directory).
  std::filesystem::path folder;
  // Which file names it, for messages ("the model file", "part.json").
  std::string namer = "the model file";
  // The caller let names lead anywhere (`sample --allow-outside-arrays`); `allowHint` tells how.
  bool allowOutside = false;
  std::string allowHint;
};

// The path of the file `name` (the value at `key` of the naming file). Throws ModelError(key, name,
// rule) when the name breaks the rule: "an absolute path is outside the folder of part.json".
std::filesystem::path resolveNamedFile(const NamedFileRule& rule, const std::string& name, const std::string& key);

}  // namespace shapespline::io
