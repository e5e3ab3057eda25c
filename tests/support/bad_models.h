#pragma once
// A catalog of model files that must be rejected (docs/format.md, docs/math.md §11), each with the JSON-path
// field the error must name. Shared by the io tests (parser) and the CLI tests (exit codes, messages).
#include <string>
#include <vector>

namespace shapespline::test {

struct BadModel {
  std::string name;       // unique, usable as a test name: [A-Za-z0-9_]
  std::string json_text;  // the complete file content (may be malformed JSON)
  std::string field;      // ModelError::field() expected, e.g. "alpha[3]" or "(document)"
};

const std::vector<BadModel>& badModelCatalog();

}  // namespace shapespline::test
