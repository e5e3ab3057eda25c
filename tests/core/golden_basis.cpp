// Golden checkers for the basis families: basis.xuwang, basis.gb, basis.singular_blend,
// basis.ubp, basis.gubp (golden/README.md "Families").
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "core/golden_registry.h"
#include <shapespline/core/singular_blend.h>
#include <shapespline/core/span_basis.h>

namespace shapespline::test {
namespace {

// Basis values are bounded by 1 (UBP order 2 by 1.5); Horner in t in [0,1] loses a few ulps per
// step of at most 11, so 1e-13 relative to max(1, |value|) is ~50x the expected fp64 error.
constexpr double kBasisRel = 1e-13;
double basisTol(const json& expected) { return kBasisRel * std::max(1.0, std::abs(number(expected))); }


// values/d1/d2 tables of the four-function families, evaluated from the span matrix.
void checkSpanTables(CaseReport& r, const SpanBasis& basis) {
  const json& ts = r.inputs().at("t");
  const json& values = r.expected("values");
  const json& d1 = r.expected("d1");
  const json& d2 = r.expected("d2");
  for (size_t i = 0; i < ts.size(); ++i) {
    double b[kMaxBasisCount], db[kMaxBasisCount], ddb[kMaxBasisCount];
    evalSpanBasis(basis, number(ts[i]), b, db, ddb);
    for (int k = 0; k < basis.count; ++k) {
      r.compare(fieldAt("values", i, k), values[i][k], b[k], basisTol(values[i][k]));
      r.compare(fieldAt("d1", i, k), d1[i][k], db[k], basisTol(d1[i][k]));
      r.compare(fieldAt("d2", i, k), d2[i][k], ddb[k], basisTol(d2[i][k]));
    }
    if (values[i].size() != static_cast<size_t>(basis.count)) r.fail(fieldAt("values", i) + ": wrong function count");
  }
}

// N, dN at global x and the local span basis at t, shared by UBP and GUBP.
void checkBellAndLocal(CaseReport& r, const SpanBasis& basis) {
  const json& xs = r.inputs().at("x");
  const json& n = r.expected("N");
  const json& dn = r.expected("dN");
  for (size_t i = 0; i < xs.size(); ++i) {
    double v = 0, d = 0;
    evalBell(basis, number(xs[i]), &v, &d);
    r.compare(fieldAt("N", i), n[i], v, basisTol(n[i]));
    r.compare(fieldAt("dN", i), dn[i], d, basisTol(dn[i]));
  }
  const json& ts = r.inputs().at("t");
  const json& lv = r.expected("local_values");
  const json& ld = r.expected("local_d1");
  for (size_t i = 0; i < ts.size(); ++i) {
    double b[kMaxBasisCount], db[kMaxBasisCount];
    evalSpanBasis(basis, number(ts[i]), b, db, nullptr);
    if (lv[i].size() != static_cast<size_t>(basis.count)) r.fail(fieldAt("local_values", i) + ": wrong function count");
    for (int k = 0; k < basis.count; ++k) {
      r.compare(fieldAt("local_values", i, k), lv[i][k], b[k], basisTol(lv[i][k]));
      r.compare(fieldAt("local_d1", i, k), ld[i][k], db[k], basisTol(ld[i][k]));
    }
  }
}

// "a + (b)*lambda" with a, b rationals like "-1/2" -> (a, b).
std::pair<double, double> parseAffine(const std::string& s) {
  auto rational = [](std::string q) {
    q.erase(std::remove(q.begin(), q.end(), ' '), q.end());
    const auto slash = q.find('/');
    if (slash == std::string::npos) return std::strtod(q.c_str(), nullptr);
    return std::strtod(q.substr(0, slash).c_str(), nullptr) / std::strtod(q.substr(slash + 1).c_str(), nullptr);
  };
  const auto plus = s.find(" + (");
  const auto close = s.find(")*lambda");
  if (plus == std::string::npos || close == std::string::npos) throw std::runtime_error("bad affine form: " + s);
  return {rational(s.substr(0, plus)), rational(s.substr(plus + 4, close - plus - 4))};
}

const GoldenRegistration kXuWang("basis.xuwang", [](CaseReport& r) {
  const json& p = r.testCase().at("params");
  checkSpanTables(r, xuWangSpanBasis(p.at("degree").get<int>(), number(p.at("lambda"))));
});

const GoldenRegistration kGb("basis.gb", [](CaseReport& r) {
  checkSpanTables(r, gbSpanBasis(number(r.testCase().at("params").at("lambda"))));
});

const GoldenRegistration kSingular("basis.singular_blend", [](CaseReport& r) {
  const json& ts = r.inputs().at("t");
  const json& s = r.expected("S");
  const json& d1 = r.expected("d1");
  const json& d2 = r.expected("d2");
  for (size_t i = 0; i < ts.size(); ++i) {
    const BlendValue v = singularBlend(number(ts[i]));
    r.compare(fieldAt("S", i), s[i], v.s, basisTol(s[i]));
    r.compare(fieldAt("d1", i), d1[i], v.d1, basisTol(d1[i]));
    r.compare(fieldAt("d2", i), d2[i], v.d2, basisTol(d2[i]));
  }
});

const GoldenRegistration kUbp("basis.ubp", [](CaseReport& r) {
  const json& p = r.testCase().at("params");
  const int order = p.at("order").get<int>();
  const double lambda = number(p.at("lambda"));
  checkBellAndLocal(r, ubpSpanBasis(order, lambda));
  const std::vector<double> coeffs = ubpDoubledKnotCoefficients(order, lambda);
  const json& dk = r.expected("doubled_knot_coefficients");
  if (dk.size() != coeffs.size()) r.fail("doubled_knot_coefficients: wrong length");
  for (size_t i = 0; i < coeffs.size() && i < dk.size(); ++i)
    r.compare(fieldAt("doubled_knot_coefficients", i), dk[i], coeffs[i], basisTol(dk[i]));
  // The exact form a + b*lambda: our recurrence is affine in lambda, so a = f(0), b = f(1) - f(0).
  const std::vector<double> at0 = ubpDoubledKnotCoefficients(order, 0.0);
  const std::vector<double> at1 = ubpDoubledKnotCoefficients(order, 1.0);
  const json& exact = r.expected("doubled_knot_coefficients_exact");
  for (size_t i = 0; i < coeffs.size() && i < exact.size(); ++i) {
    const auto [a, b] = parseAffine(exact[i].get<std::string>());
    r.compare(fieldAt("doubled_knot_coefficients_exact.a", i), json(a), at0[i], kBasisRel);
    r.compare(fieldAt("doubled_knot_coefficients_exact.b", i), json(b), at1[i] - at0[i], kBasisRel);
  }
});

const GoldenRegistration kGubp("basis.gubp", [](CaseReport& r) {
  const json& p = r.testCase().at("params");
  const int order = p.at("order").get<int>();
  const std::vector<double> mu = p.at("mu").get<std::vector<double>>();
  checkBellAndLocal(r, gubpSpanBasis(order, mu));
  const std::vector<double> full = gubpFullMu(order, mu);
  const json& mf = r.expected("mu_full");
  if (mf.size() != full.size()) r.fail("mu_full: wrong length");
  for (size_t i = 0; i < full.size() && i < mf.size(); ++i) r.compare(fieldAt("mu_full", i), mf[i], full[i], basisTol(mf[i]));
});

}  // namespace
}  // namespace shapespline::test
