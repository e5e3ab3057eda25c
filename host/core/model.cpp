#include <shapespline/core/model.h>

namespace shapespline {

static std::string describe(const std::string& field, const std::string& value, const std::string& rule) {
  std::string s = field;
  if (!value.empty()) s += " = " + value;
  s += ": " + rule;
  return s;
}

ModelError::ModelError(std::string field, std::string value, std::string rule)
    : std::invalid_argument(describe(field, value, rule)),
      field_(std::move(field)), value_(std::move(value)), rule_(std::move(rule)) {}

}  // namespace shapespline
