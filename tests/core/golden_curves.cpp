// Golden checker for the `curve` family (golden/README.md "curve"): local families, α-EB and
// knot-vector B-splines, evaluated by core/curve.h from the model parsed by io::parseModel.
//
// Tolerances (support/tolerances.h: kFp64Rel relative to the bounding-box diagonal `scale`):
//  * point / base_nodes / V: kFp64Rel * scale * g, where g = 1 for plain curves and 1/α_min for
//    α-EB, because V_j = P_j + ((1-α)/α)(P_j - node_j) carries |V| up to scale/α_min and every
//    later rounding is relative to that magnitude (docs/math.md §14).
//  * d1: kFp64Rel * scale * g * D1 with D1 = max over the case's samples of Σ_r |B_r'(t)| / h
//    (the sum of the absolute coefficients that multiply the points, so rounding of the sum is
//    bounded by that many ulps of scale); α-EB adds 2 * max S' = 4.5 for the a' M and L' terms.
//  * d2: the same with D2 = max Σ_r |B_r''(t)| / h^2; α-EB adds 4 * max S' * D1 + 2 * max S'' (the
//    2 a' M' and a'' M, L'' terms of §4.2; max S' = 9/4, max S'' = 9).
//  * knot-vector B-splines: D1 = max Σ |N_i'(u)| at the samples (core/bspline.h basis derivatives).
//  * u, u_range: kFp64Rel * max(1, |u|). span / t / span_range echo inputs and must match exactly.
// Each limit is then capped by the case's own fp64 limit (golden/README.md), so neither rule is
// ever loosened by the other.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <variant>

#include <shapespline/core/bspline.h>
#include <shapespline/core/curve.h>
#include "core/golden_registry.h"
#include <shapespline/io/model_json.h>
#include "support/tolerances.h"

namespace shapespline::test {
namespace {

constexpr double kMaxBlendD1 = 2.25;                            // max |S'| (docs/math.md §3, at t = 1/2)
constexpr double kMaxBlendD2 = 9.0;                             // max |S''| (at t = 0, 1/3, 2/3, 1)

void checkCurve(CaseReport& r) {
  const io::Model parsed = io::parseModel(r.model());
  const auto* model = std::get_if<CurveModel>(&parsed);
  if (!model) {
    r.fail("model is not a curve");
    return;
  }
  const Curve curve = Curve::create(*model);
  const int dim = model->dimension;
  const double scale = modelScale(r.model());
  const bool aeb = model->family.construction == Construction::AlphaEB;
  double g = 1.0;
  if (aeb) g = 1.0 / *std::min_element(model->alpha.begin(), model->alpha.end());
  const json& inSamples = r.inputs().at("samples");

  // Derivative magnitude factors over this case's samples.
  double d1Factor = 1.0, d2Factor = 1.0;
  for (const json& s : inSamples) {
    if (curve.usesKnotVector()) {
      const double u = number(s.at("u"));
      const int k = model->family.order;
      const int span = findKnotSpan(k, model->knots, static_cast<int>(model->points.size()), u);
      double nd[3][kMaxBasisCount] = {};
      bsplineBasisDerivs(k, model->knots, span, u, 2, nd);
      double a1 = 0.0, a2 = 0.0;
      for (int i = 0; i < k; ++i) a1 += std::abs(nd[1][i]), a2 += std::abs(nd[2][i]);
      d1Factor = std::max(d1Factor, a1);
      d2Factor = std::max(d2Factor, a2);
      continue;
    }
    const int span = s.at("span").get<int>();
    const double t = number(s.at("t"));
    double invH = 1.0;
    if (!curve.spanKnots().empty()) {
      const int i = span - curve.spans().first;
      if (i >= 0 && i + 1 < static_cast<int>(curve.spanKnots().size()))
        invH = 1.0 / (curve.spanKnots()[i + 1] - curve.spanKnots()[i]);
    }
    double b1[kMaxBasisCount], b2[kMaxBasisCount];
    evalSpanBasis(curve.basis(), std::clamp(t, 0.0, 1.0), nullptr, b1, b2);
    double a1 = 0.0, a2 = 0.0;
    for (int i = 0; i < curve.basis().count; ++i) a1 += std::abs(b1[i]), a2 += std::abs(b2[i]);
    d1Factor = std::max(d1Factor, a1 * invH);
    d2Factor = std::max(d2Factor, a2 * invH * invH);
  }
  if (aeb) {
    d2Factor += 4.0 * kMaxBlendD1 * d1Factor + 2.0 * kMaxBlendD2;
    d1Factor += 2.0 * kMaxBlendD1;
  }
  const json& tc = r.testCase();
  const double tolPoint = std::min(kFp64Rel * scale * g, goldenLimit(tc, "point"));
  const double tolD1 = std::min(kFp64Rel * scale * g * d1Factor, goldenLimit(tc, "d1"));
  const double tolD2 = std::min(kFp64Rel * scale * g * d2Factor, goldenLimit(tc, "d2"));
  auto tolU = [](double u) { return kFp64Rel * std::max(1.0, std::abs(u)); };

  // Ranges.
  const auto [u0, u1] = curve.parameterRange();
  const json& ur = r.expected("u_range");
  r.compare("u_range[0]", ur[0], u0, tolU(u0));
  r.compare("u_range[1]", ur[1], u1, tolU(u1));
  if (!curve.usesKnotVector()) {
    const json& sr = r.expected("span_range");
    r.compare("span_range[0]", sr[0], curve.spans().first, kExactLimit);
    r.compare("span_range[1]", sr[1], curve.spans().last, kExactLimit);
  }

  // α-EB debugging aids, compared as values in their own right.
  if (aeb) {
    const json& nodes = r.expected("base_nodes");
    const json& vs = r.expected("V");
    if (nodes.size() != curve.alphaNodes().size() || vs.size() != curve.alphaV().size())
      r.fail("base_nodes/V: expected " + std::to_string(nodes.size()) + "/" + std::to_string(vs.size()) +
             " entries, have " + std::to_string(curve.alphaNodes().size()));
    const double tolNode = std::min(kFp64Rel * scale * g, goldenLimit(tc, "base_nodes"));
    const double tolV = std::min(kFp64Rel * scale * g, goldenLimit(tc, "V"));
    for (size_t j = 0; j < nodes.size() && j < curve.alphaNodes().size(); ++j)
      r.compare(fieldAt("base_nodes", j), nodes[j], curve.alphaNodes()[j], dim, tolNode);
    for (size_t j = 0; j < vs.size() && j < curve.alphaV().size(); ++j)
      r.compare(fieldAt("V", j), vs[j], curve.alphaV()[j], dim, tolV);
  }

  const json& samples = r.expected("samples");
  if (samples.size() != inSamples.size()) r.fail("samples: count differs from inputs.samples");
  for (size_t i = 0; i < samples.size() && i < inSamples.size(); ++i) {
    const json& e = samples[i];
    const std::string name = fieldAt("samples", i);
    CurvePoint p;
    if (curve.usesKnotVector()) {
      const double u = number(inSamples[i].at("u"));
      p = curve.evaluateAt(u);
      r.compare(name + ".u", e.at("u"), u, tolU(u));
    } else {
      const int span = inSamples[i].at("span").get<int>();
      const double t = number(inSamples[i].at("t"));
      p = curve.evaluate(span, t);
      const double u = curve.parameterOf(span, t);
      r.compare(name + ".span", e.at("span"), span, kExactLimit);
      r.compare(name + ".t", e.at("t"), t, kExactLimit);
      r.compare(name + ".u", e.at("u"), u, tolU(u));
    }
    r.compare(name + ".point", e.at("point"), p.point, dim, tolPoint);
    r.compare(name + ".d1", e.at("d1"), p.d1, dim, tolD1);
    if (e.contains("d2")) {
      r.compare(name + ".d2", e.at("d2"), p.d2, dim, tolD2);
    } else if (!curve.usesKnotVector()) {
      r.fail(name + ": d2 missing for a local-family curve");
    }
    for (const auto& [key, value] : e.items()) {
      static const char* kKnown[] = {"span", "t", "u", "point", "d1", "d2"};
      if (std::find(std::begin(kKnown), std::end(kKnown), key) == std::end(kKnown))
        r.fail(name + ": unknown expected field '" + key + "' was not compared");
    }
  }
}

const GoldenRegistration kCurve("curve", checkCurve);

}  // namespace
}  // namespace shapespline::test
