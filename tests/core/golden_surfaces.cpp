// Golden checker for the `surface` family (golden/README.md "surface"): α-EB surfaces, plain tensor
// surfaces and knot-vector B-spline surfaces, evaluated by core/surface.h from io::parseModel.
//
// Tolerances (support/tolerances.h: kFp64Rel relative to the bounding-box diagonal `scale`):
//  * point / base_nodes / V: kFp64Rel * scale * g with g = 1 (plain) or 1/α_min (α-EB, docs/math.md §14:
//    V_ij has magnitude up to scale/α_min and later roundings are relative to it).
//  * a partial of order (r,q): kFp64Rel * scale * g * F_rq. For the base tensor patch
//    D_rq = max over the samples of (Σ_n |B_n^(r)(u)|)(Σ_m |B_m^(q)(v)|), the sum of absolute
//    weights on the points. α-EB adds the blend terms of §5.3: the weight pairs have absolute sums
//    W_0 = 1, W_1 = 2 max|S'| = 4.5, W_2 = 2 max|S''| = 18 per direction, and by the product rule
//    Q_rq = Σ binom(r,a) binom(q,b) a_ab M_(r-a)(q-b) + C_rq with |M_xy| <= D_xy + W_xy, so
//    F_rq = D_rq + Σ_{a<=r, b<=q} binom(r,a) binom(q,b) W_a W_b (D + W)_{(r-a)(q-b)}.
//  * normal n = x/|x| with x = du x dv: |δn| <= 2 |δx|/|x| <= 2 (tol_du/|du| + tol_dv/|dv|)/sin∠,
//    computed from the expected du, dv of the sample. Null normals (sin∠ < 0.01) are not compared,
//    but the computed normal must still be a finite unit vector (§5.3 "never NaN").
//  * UV: kFp64Rel * max(1, |U|); patch / uv / patch_range echo inputs and must match exactly.
// Each limit is capped by the case's own fp64 limit (golden/README.md), never loosened by it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <variant>

#include <glm/geometric.hpp>

#include "core/golden_registry.h"
#include <shapespline/core/surface.h>
#include <shapespline/io/model_json.h>
#include "support/tolerances.h"

namespace shapespline::test {
namespace {

constexpr double kBlendPairSum[3] = {1.0, 4.5, 18.0};  // W_0, W_1, W_2 (docs/math.md §3 maxima)

// Σ |B^(r)| at t for r = 0, 1, 2.
void absSums(const SpanBasis& b, double t, double out[3]) {
  double v[3][kMaxBasisCount];
  evalSpanBasis(b, std::clamp(t, 0.0, 1.0), v[0], v[1], v[2]);
  for (int r = 0; r < 3; ++r) {
    out[r] = 0.0;
    for (int i = 0; i < b.count; ++i) out[r] += std::abs(v[r][i]);
  }
}

double binom(int n, int k) { return (n == 2 && k == 1) ? 2.0 : 1.0; }

void checkSurface(CaseReport& r) {
  const io::Model parsed = io::parseModel(r.model());
  const auto* model = std::get_if<SurfaceModel>(&parsed);
  if (!model) {
    r.fail("model is not a surface");
    return;
  }
  const Surface surface = Surface::create(*model);
  const double scale = modelScale(r.model());
  const bool aeb = model->family.construction == Construction::AlphaEB;
  const double g = aeb ? 1.0 / *std::min_element(model->alpha.begin(), model->alpha.end()) : 1.0;
  const json& inSamples = r.inputs().at("samples");
  const json& tc = r.testCase();

  // D[r][q] over the samples (knot-vector surfaces: the same bound with the knot-span basis is
  // not available through the span basis, so they use D = 1 scaled by the golden cap).
  double d[3][3] = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  if (!surface.usesKnotVector()) {
    for (const json& s : inSamples) {
      double su[3], sv[3];
      absSums(surface.basisU(), number(s.at("uv")[0]), su);
      absSums(surface.basisV(), number(s.at("uv")[1]), sv);
      for (int a = 0; a < 3; ++a)
        for (int b = 0; a + b <= 2 && b < 3; ++b) d[a][b] = std::max(d[a][b], su[a] * sv[b]);
    }
  }
  auto factor = [&](int rr, int qq) {
    double f = d[rr][qq];
    if (!aeb) return f;
    for (int a = 0; a <= rr; ++a)
      for (int b = 0; b <= qq; ++b)
        f += binom(rr, a) * binom(qq, b) * kBlendPairSum[a] * kBlendPairSum[b] *
             (d[rr - a][qq - b] + kBlendPairSum[rr - a] * kBlendPairSum[qq - b]);
    return f;
  };
  auto tolOf = [&](const char* field, int rr, int qq) {
    return std::min(kFp64Rel * scale * g * factor(rr, qq), goldenLimit(tc, field));
  };
  const double tolPoint = tolOf("point", 0, 0), tolDu = tolOf("du", 1, 0), tolDv = tolOf("dv", 0, 1);
  const double tolDuu = tolOf("duu", 2, 0), tolDuv = tolOf("duv", 1, 1), tolDvv = tolOf("dvv", 0, 2);
  const double normalCap = goldenLimit(tc, "normal");
  auto tolU = [](double u) { return kFp64Rel * std::max(1.0, std::abs(u)); };

  const json& pr = r.expected("patch_range");
  const PatchRange range = surface.patches();
  r.compare("patch_range[0][0]", pr[0][0], range.u.first, kExactLimit);
  r.compare("patch_range[0][1]", pr[0][1], range.u.last, kExactLimit);
  r.compare("patch_range[1][0]", pr[1][0], range.v.first, kExactLimit);
  r.compare("patch_range[1][1]", pr[1][1], range.v.last, kExactLimit);

  if (aeb) {
    const json& nodes = r.expected("base_nodes");
    const json& vs = r.expected("V");
    const double tolNode = std::min(kFp64Rel * scale * g, goldenLimit(tc, "base_nodes"));
    const double tolV = std::min(kFp64Rel * scale * g, goldenLimit(tc, "V"));
    if (static_cast<int>(nodes.size()) != model->rows || static_cast<int>(vs.size()) != model->rows)
      r.fail("base_nodes/V: row count differs from the net");
    for (int i = 0; i < model->rows && i < static_cast<int>(nodes.size()) && i < static_cast<int>(vs.size()); ++i) {
      if (static_cast<int>(nodes[i].size()) != model->cols || static_cast<int>(vs[i].size()) != model->cols)
        r.fail(fieldAt("base_nodes", i) + ": column count differs from the net");
      for (int j = 0; j < model->cols && j < static_cast<int>(nodes[i].size()) && j < static_cast<int>(vs[i].size());
           ++j) {
        r.compare(fieldAt("base_nodes", i, j), nodes[i][j], surface.alphaNode(i, j), 3, tolNode);
        r.compare(fieldAt("V", i, j), vs[i][j], surface.alphaVertex(i, j), 3, tolV);
      }
    }
  }

  const json& samples = r.expected("samples");
  if (samples.size() != inSamples.size()) r.fail("samples: count differs from inputs.samples");
  int nullNormals = 0;
  for (size_t n = 0; n < samples.size() && n < inSamples.size(); ++n) {
    const json& e = samples[n];
    const std::string name = fieldAt("samples", n);
    const int i = inSamples[n].at("patch")[0].get<int>(), j = inSamples[n].at("patch")[1].get<int>();
    const double u = number(inSamples[n].at("uv")[0]), v = number(inSamples[n].at("uv")[1]);
    const SurfacePoint p = surface.evaluate(i, j, u, v);
    const auto [gu, gv] = surface.parameterOf(i, j, u, v);
    r.compare(name + ".patch[0]", e.at("patch")[0], i, kExactLimit);
    r.compare(name + ".patch[1]", e.at("patch")[1], j, kExactLimit);
    r.compare(name + ".uv[0]", e.at("uv")[0], u, kExactLimit);
    r.compare(name + ".uv[1]", e.at("uv")[1], v, kExactLimit);
    r.compare(name + ".UV[0]", e.at("UV")[0], gu, tolU(gu));
    r.compare(name + ".UV[1]", e.at("UV")[1], gv, tolU(gv));
    r.compare(name + ".point", e.at("point"), p.point, 3, tolPoint);
    r.compare(name + ".du", e.at("du"), p.du, 3, tolDu);
    r.compare(name + ".dv", e.at("dv"), p.dv, 3, tolDv);
    r.compare(name + ".duu", e.at("duu"), p.duu, 3, tolDuu);
    r.compare(name + ".duv", e.at("duv"), p.duv, 3, tolDuv);
    r.compare(name + ".dvv", e.at("dvv"), p.dvv, 3, tolDvv);
    const double len = glm::length(p.normal);
    if (!(std::abs(len - 1.0) < 1e-12)) r.fail(name + ".normal: not a finite unit vector");
    if (e.at("normal").is_null()) {
      ++nullNormals;
    } else {
      const glm::dvec3 du = vec(e.at("du")), dv = vec(e.at("dv"));
      const double lu = glm::length(du), lv = glm::length(dv);
      const double sinAngle = glm::length(glm::cross(du, dv)) / (lu * lv);
      const double tolN = std::min(2.0 * (tolDu / lu + tolDv / lv) / sinAngle, normalCap);
      r.compare(name + ".normal", e.at("normal"), p.normal, 3, tolN);
    }
    for (const auto& [key, value] : e.items()) {
      static const char* kKnown[] = {"patch", "uv", "UV", "point", "du", "dv", "duu", "duv", "dvv", "normal"};
      if (std::find(std::begin(kKnown), std::end(kKnown), key) == std::end(kKnown))
        r.fail(name + ": unknown expected field '" + key + "' was not compared");
    }
  }
  if (nullNormals > 0)
    r.acknowledge("samples.normal(null)", std::to_string(nullNormals) +
                                              " null normals (sin angle < 0.01): checked finite and unit only");
}

const GoldenRegistration kSurface("surface", checkSurface);

}  // namespace
}  // namespace shapespline::test
