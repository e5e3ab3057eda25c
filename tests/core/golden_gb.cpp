// Golden checker for the GB constrained modification (family gb_modify, docs/math.md §7.2).
#include <cmath>
#include <string>
#include <variant>

#include <shapespline/core/gb_tools.h>
#include "core/golden_registry.h"
#include <shapespline/io/model_json.h>

namespace shapespline::test {
namespace {

// docs/math.md §7.2 suggested acceptance for fp64: |t0 − t0_ref| ≤ 1e−9 and the same for w (w is a
// Lipschitz function of t0 along the path). The bisection itself stops at 2^−40 ≈ 9e−13, so 1e−9
// leaves the margin the spec intends for other stopping rules, not for our rounding.
constexpr double kGbParamTol = 1e-9;
// λ0 = 12(1 − w)/w has |dλ/dw| = 12/w², so the w tolerance becomes (12/w²)·1e−9 (docs/math.md §7.2).
double lambdaTol(double w) { return 12.0 / (w * w) * kGbParamTol; }

const GoldenRegistration kGbModify("gb_modify", [](CaseReport& r) {
  const auto model = std::get<CurveModel>(io::parseModel(r.model()));
  const int span = r.inputs().at("span").get<int>();
  const glm::dvec3 x = vec(r.inputs().at("target"));
  const GbFitResult fit = gbConstrainedModify(model, span, glm::dvec2(x.x, x.y));
  if (!fit.reachable) r.fail("target reported unreachable: " + fit.reason);

  const json& wRef = r.expected("w");
  const double w = number(wRef);
  r.compare("t0", r.expected("t0"), fit.bisection.t0, kGbParamTol);
  r.compare("w", wRef, fit.bisection.w, kGbParamTol);
  r.compare("lambda0", r.expected("lambda0"), fit.bisection.lambda0, lambdaTol(w));

  const json& all = r.expected("all_solutions");
  if (all.size() != fit.all.size()) {
    r.fail("all_solutions: expected " + std::to_string(all.size()) + " solutions, found " +
           std::to_string(fit.all.size()));
    return;
  }
  for (size_t i = 0; i < all.size(); ++i) {
    // The file's order is not specified: pair each expected solution with the nearest t0 found.
    const double tRef = number(all[i].at("t0"));
    size_t best = 0;
    for (size_t k = 1; k < fit.all.size(); ++k)
      if (std::abs(fit.all[k].t0 - tRef) < std::abs(fit.all[best].t0 - tRef)) best = k;
    const std::string name = "all_solutions[" + std::to_string(i) + "]";
    const double lambdaRef = number(all[i].at("lambda0"));
    r.compare(name + ".t0", all[i].at("t0"), fit.all[best].t0, kGbParamTol);
    r.compare(name + ".lambda0", all[i].at("lambda0"), fit.all[best].lambda0, lambdaTol(12.0 / (12.0 + lambdaRef)));
  }
});

}  // namespace
}  // namespace shapespline::test
