#pragma once
// Golden-vector harness: loads tests/data/golden (or $SHAPESPLINE_GOLDEN_DIR), dispatches each case to
// the checker registered for its family, and makes sure nothing is skipped silently: a case of an
// unknown family fails, and so does a case whose checker did not compare every `expected` field.
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace shapespline::test {

using nlohmann::json;

std::filesystem::path goldenDir();

struct GoldenFile {
  std::string name;  // file name, e.g. "curves_plain.json"
  json doc;
};
// Every *.json in goldenDir(), sorted by name. Throws if the folder is missing or empty.
std::vector<GoldenFile> loadGoldenFiles();

// Expected values are exact decimal strings (parsed with strtod) or, in inputs, plain numbers.
double number(const json& j);
glm::dvec3 vec(const json& j);  // 2 or 3 coordinates; z = 0 for 2-D

// "field[i]" and "field[i][j]": the names under which a checker compares values.
std::string fieldAt(const std::string& field, size_t i);
std::string fieldAt(const std::string& field, size_t i, size_t j);
// The limit of a comparison that must be exact (the smallest normal double: the ratio stays finite).
inline constexpr double kExactLimit = std::numeric_limits<double>::min();
// The case's fp64 limit for `field` (the case's top-level limit when the field has none).
double goldenLimit(const json& testCase, const std::string& field);

// Collects the comparisons of one case. Reading an expected field through expected() marks it as
// compared; fields never read make the case fail.
class CaseReport {
 public:
  CaseReport(const json& testCase, std::string label);

  const json& testCase() const { return case_; }
  const json& model() const { return case_.at("model"); }
  const json& inputs() const { return case_.at("inputs"); }
  // Marks `key` of case["expected"] as compared and returns it.
  const json& expected(const std::string& key);
  // Marks a key as deliberately consumed without a numeric comparison (e.g. debugging aids that
  // are checked through another field); `why` is recorded in the report.
  void acknowledge(const std::string& key, const std::string& why);

  void compare(const std::string& what, const json& expected, double actual, double tol);
  void compare(const std::string& what, const json& expected, const glm::dvec3& actual, int dim, double tol);
  void fail(const std::string& message);

  double maxError() const { return maxError_; }
  double maxRatio() const { return maxRatio_; }  // largest error / tolerance
  const std::vector<std::string>& failures() const { return failures_; }
  std::vector<std::string> uncomparedFields() const;
  int comparisons() const { return comparisons_; }

 private:
  json case_;
  std::string label_;
  std::set<std::string> used_;
  std::vector<std::string> failures_;
  double maxError_ = 0.0, maxRatio_ = 0.0;
  int comparisons_ = 0;
};

using FamilyChecker = std::function<void(CaseReport&)>;

// family name -> checker. Each test executable fills its own registry.
class GoldenRegistry {
 public:
  void add(const std::string& family, FamilyChecker checker) { checkers_[family] = std::move(checker); }
  const FamilyChecker* find(const std::string& family) const;

 private:
  std::map<std::string, FamilyChecker> checkers_;
};

// Runs every case of `file` through `registry`; returns human-readable failures (empty on success)
// and prints one summary line (cases, comparisons, largest error and largest error/tolerance).
std::vector<std::string> runGoldenFile(const GoldenFile& file, const GoldenRegistry& registry,
                                       const std::string& label);

// Bounding-box diagonal of all numbers in model.points (any nesting), at least 1e-300.
double modelScale(const json& model);

}  // namespace shapespline::test
