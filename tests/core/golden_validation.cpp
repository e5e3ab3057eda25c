// Golden family `validation` (tests/data/golden/README.md): each case's model must be accepted or rejected
// as `expected.valid` says. A rejection must be a ModelError naming a field (the message mentions it).
#include <cstdio>
#include <string>

#include "core/golden_registry.h"
#include <shapespline/core/model.h>
#include <shapespline/io/model_json.h>

namespace shapespline::test {
namespace {

void checkValidation(CaseReport& r) {
  const bool expectValid = r.expected("valid").get<bool>();
  const std::string reason = r.expected("reason").get<std::string>();
  const std::string id = r.testCase().value("id", "?");

  bool accepted = false;
  std::string detail;
  try {
    io::parseModel(r.model());
    accepted = true;
  } catch (const ModelError& e) {
    detail = e.what();
    if (e.field().empty()) r.fail("rejection names no field: " + detail);
    else if (detail.find(e.field()) == std::string::npos)
      r.fail("message does not mention field '" + e.field() + "': " + detail);
  } catch (const std::exception& e) {
    r.fail(std::string("rejected with an exception that is not a ModelError: ") + e.what());
    detail = e.what();
  }

  if (accepted != expectValid) {
    r.fail(std::string(expectValid ? "valid model was rejected" : "invalid model was accepted") + " (" + reason +
           ")" + (detail.empty() ? "" : ": " + detail));
  } else {
    std::printf("  %s %s: %s%s%s\n", id.c_str(), expectValid ? "accepted" : "rejected", reason.c_str(),
                detail.empty() ? "" : " -> ", detail.c_str());
  }
  // One comparison per case, so the harness counts it (a numeric string is parsed by number()).
  r.compare("valid (" + reason + ")", nlohmann::json(expectValid ? "1" : "0"), accepted ? 1.0 : 0.0, 0.0);
}

const GoldenRegistration kRegistration("validation", checkValidation);

}  // namespace
}  // namespace shapespline::test
