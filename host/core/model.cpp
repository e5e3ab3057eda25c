#include <shapespline/core/model.h>

namespace shapespline {

std::string_view constructionName(Construction c) {
  switch (c) {
    case Construction::ExtendedBSpline: return "extended_bspline";
    case Construction::AlphaEB: return "alpha_eb";
    case Construction::GB: return "gb";
    case Construction::UBP: return "ubp";
    case Construction::GUBP: return "gubp";
    case Construction::BSpline: return "bspline";
  }
  return "unknown";
}

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
