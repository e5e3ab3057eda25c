#include "support/golden.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace shapespline::test {

std::filesystem::path goldenDir() {
  if (const char* env = std::getenv("SHAPESPLINE_GOLDEN_DIR"); env && *env) {
    std::filesystem::path p(env);
    // Relative paths are relative to the repository root, like the default.
    return p.is_absolute() ? p : std::filesystem::path(SHAPESPLINE_SOURCE_DIR) / p;
  }
  return std::filesystem::path(SHAPESPLINE_SOURCE_DIR) / "tests" / "data" / "golden";
}

std::vector<GoldenFile> loadGoldenFiles() {
  const auto dir = goldenDir();
  if (!std::filesystem::is_directory(dir)) throw std::runtime_error("golden folder not found: " + dir.string());
  std::vector<GoldenFile> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    std::ifstream in(entry.path());
    GoldenFile f;
    f.name = entry.path().filename().string();
    f.doc = json::parse(in);
    files.push_back(std::move(f));
  }
  if (files.empty()) throw std::runtime_error("no *.json in golden folder " + dir.string());
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return files;
}

std::string fieldAt(const std::string& field, size_t i) { return field + "[" + std::to_string(i) + "]"; }
std::string fieldAt(const std::string& field, size_t i, size_t j) {
  return fieldAt(field, i) + "[" + std::to_string(j) + "]";
}

double goldenLimit(const json& testCase, const std::string& field) {
  const json& t = testCase.at("tolerance");
  if (t.contains("fields") && t.at("fields").contains(field)) return number(t.at("fields").at(field).at("fp64"));
  return number(t.at("fp64"));
}

double number(const json& j) {
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str()) throw std::runtime_error("not a number: " + s);
    return v;
  }
  return j.get<double>();
}

glm::dvec3 vec(const json& j) {
  glm::dvec3 v(0.0);
  for (size_t i = 0; i < j.size() && i < 3; ++i) v[static_cast<int>(i)] = number(j[i]);
  return v;
}

CaseReport::CaseReport(const json& testCase, std::string label) : case_(testCase), label_(std::move(label)) {}

const json& CaseReport::expected(const std::string& key) {
  used_.insert(key);
  return case_.at("expected").at(key);
}

void CaseReport::acknowledge(const std::string& key, const std::string& /*why*/) { used_.insert(key); }

void CaseReport::compare(const std::string& what, const json& expected, double actual, double tol) {
  ++comparisons_;
  const double e = number(expected);
  const double err = std::abs(actual - e);
  const bool bad = !(err <= tol);  // NaN fails
  maxError_ = std::max(maxError_, std::isnan(err) ? INFINITY : err);
  maxRatio_ = std::max(maxRatio_, std::isnan(err) ? INFINITY : err / tol);
  if (bad) {
    std::ostringstream os;
    os.precision(17);
    os << label_ << " " << case_.value("id", "?") << " " << what << ": expected " << e << " got " << actual
       << " error " << err << " > tol " << tol;
    failures_.push_back(os.str());
  }
}

void CaseReport::compare(const std::string& what, const json& expected, const glm::dvec3& actual, int dim,
                         double tol) {
  if (!expected.is_array() || static_cast<int>(expected.size()) != dim) {
    fail(what + ": expected a vector of " + std::to_string(dim) + " coordinates, got " + expected.dump());
    return;
  }
  for (int i = 0; i < dim; ++i) compare(what + "[" + std::to_string(i) + "]", expected[i], actual[i], tol);
}

void CaseReport::fail(const std::string& message) {
  failures_.push_back(label_ + " " + case_.value("id", "?") + ": " + message);
}

std::vector<std::string> CaseReport::uncomparedFields() const {
  std::vector<std::string> out;
  if (!case_.contains("expected")) return out;
  for (const auto& [key, value] : case_.at("expected").items())
    if (!used_.count(key)) out.push_back(key);
  return out;
}

const FamilyChecker* GoldenRegistry::find(const std::string& family) const {
  auto it = checkers_.find(family);
  return it == checkers_.end() ? nullptr : &it->second;
}

std::vector<std::string> runGoldenFile(const GoldenFile& file, const GoldenRegistry& registry,
                                       const std::string& label) {
  std::vector<std::string> failures;
  double maxError = 0.0, maxRatio = 0.0;
  int comparisons = 0, cases = 0;
  for (const auto& c : file.doc.at("cases")) {
    ++cases;
    const std::string family = c.at("family").get<std::string>();
    const FamilyChecker* checker = registry.find(family);
    if (!checker) {
      failures.push_back(label + " " + c.value("id", "?") + ": no checker for family '" + family + "'");
      continue;
    }
    CaseReport report(c, label);
    try {
      (*checker)(report);
    } catch (const std::exception& e) {
      report.fail(std::string("threw: ") + e.what());
    }
    for (const auto& key : report.uncomparedFields())
      report.fail("expected field '" + key + "' was not compared");
    if (report.comparisons() == 0) report.fail("no value was compared");
    failures.insert(failures.end(), report.failures().begin(), report.failures().end());
    maxError = std::max(maxError, report.maxError());
    maxRatio = std::max(maxRatio, report.maxRatio());
    comparisons += report.comparisons();
  }
  std::printf("[%s] %-28s %3d cases %6d comparisons  max |error| %.3e  max error/tol %.3f\n", label.c_str(),
              file.name.c_str(), cases, comparisons, maxError, maxRatio);
  return failures;
}

double modelScale(const json& model) {
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  std::function<void(const json&)> walk = [&](const json& j) {
    if (!j.is_array() || j.empty()) return;
    if (j[0].is_number()) {
      for (size_t i = 0; i < j.size() && i < 3; ++i) {
        lo[static_cast<int>(i)] = std::min(lo[static_cast<int>(i)], j[i].get<double>());
        hi[static_cast<int>(i)] = std::max(hi[static_cast<int>(i)], j[i].get<double>());
      }
      if (j.size() == 2) lo.z = std::min(lo.z, 0.0), hi.z = std::max(hi.z, 0.0);
      return;
    }
    for (const auto& e : j) walk(e);
  };
  if (model.contains("points")) walk(model.at("points"));
  double d = 0.0;
  for (int i = 0; i < 3; ++i)
    if (std::isfinite(hi[i] - lo[i])) d += (hi[i] - lo[i]) * (hi[i] - lo[i]);
  return std::max(std::sqrt(d), 1e-300);
}

}  // namespace shapespline::test
