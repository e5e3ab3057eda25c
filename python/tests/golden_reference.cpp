// The C++ CPU results of every golden case (tests/data/golden, or the folder given as argv[1]), for
// python/tests/test_golden.py: the Python module must reproduce each of them bit for bit. Reads each
// case as tests/core/golden_*.cpp do and prints one JSON object {case id: {quantity: [values]}} with
// every double as a C99 hex float ("%a"), exact in both directions. Not a checker: the expected
// values are compared by tests/core (and, with the golden tolerances, by the Python test).
#include <shapespline/core/bspline.h>
#include <shapespline/core/curve.h>
#include <shapespline/core/extension.h>
#include <shapespline/core/gb_tools.h>
#include <shapespline/core/singular_blend.h>
#include <shapespline/core/span_basis.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/model_json.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <variant>
#include <vector>

using namespace shapespline;
using nlohmann::json;

namespace {

double num(const json& j) { return j.is_string() ? std::strtod(j.get<std::string>().c_str(), nullptr) : j.get<double>(); }

std::string hex(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", v);
  return buf;
}

void put(json& a, double v) { a.push_back(hex(v)); }
void put(json& a, const glm::dvec3& p) {
  for (int c = 0; c < 3; ++c) put(a, p[c]);
}
json list(const std::vector<double>& v) {
  json a = json::array();
  for (double x : v) put(a, x);
  return a;
}
json list(const std::vector<glm::dvec3>& v) {
  json a = json::array();
  for (const auto& p : v) put(a, p);
  return a;
}
std::vector<glm::dvec3> points(const json& j) {
  std::vector<glm::dvec3> out;
  for (const auto& p : j) {
    glm::dvec3 v(0.0);
    for (size_t c = 0; c < p.size(); ++c) v[int(c)] = num(p[c]);
    out.push_back(v);
  }
  return out;
}
std::optional<std::vector<double>> given(const json& inputs) {
  const json& p = inputs.at("parametrization");
  if (p.is_string()) return std::nullopt;
  std::vector<double> u;
  for (const auto& x : p.at("u")) u.push_back(num(x));
  return u;
}

json spanTable(const SpanBasis& b, const json& ts, bool second) {
  json v = json::array(), d1 = json::array(), d2 = json::array();
  for (const auto& t : ts) {
    double x[kMaxBasisCount], y[kMaxBasisCount], z[kMaxBasisCount];
    evalSpanBasis(b, num(t), x, y, z);
    for (int r = 0; r < b.count; ++r) put(v, x[r]), put(d1, y[r]), put(d2, z[r]);
  }
  json o = {{"values", v}, {"d1", d1}};
  if (second) o["d2"] = d2;
  return o;
}

json bell(const SpanBasis& b, const json& xs) {
  json n = json::array(), dn = json::array();
  for (const auto& x : xs) {
    double v = 0, d = 0;
    evalBell(b, num(x), &v, &d);
    put(n, v), put(dn, d);
  }
  return {{"N", n}, {"dN", dn}};
}

json curveCase(const json& c) {
  const Curve curve = Curve::create(std::get<CurveModel>(io::parseModel(c.at("model"))));
  json samples = json::array();
  for (const auto& s : c.at("inputs").at("samples")) {
    const CurvePoint p = s.contains("u") ? curve.evaluateAt(num(s.at("u"))) : curve.evaluate(s.at("span").get<int>(), num(s.at("t")));
    put(samples, p.point), put(samples, p.d1), put(samples, p.d2);
  }
  const auto [u0, u1] = curve.parameterRange();
  return {{"samples", samples},
          {"u_range", list(std::vector<double>{u0, u1})},
          {"span_range", {curve.spans().first, curve.spans().last}},
          {"alpha_nodes", list(curve.alphaNodes())},
          {"alpha_v", list(curve.alphaV())}};
}

json surfaceCase(const json& c) {
  const Surface surface = Surface::create(std::get<SurfaceModel>(io::parseModel(c.at("model"))));
  json samples = json::array();
  for (const auto& s : c.at("inputs").at("samples")) {
    const SurfacePoint p = surface.evaluate(s.at("patch")[0].get<int>(), s.at("patch")[1].get<int>(), num(s.at("uv")[0]),
                                            num(s.at("uv")[1]));
    for (const auto* f : {&p.point, &p.du, &p.dv, &p.duu, &p.duv, &p.dvv, &p.normal}) put(samples, *f);
  }
  const PatchRange r = surface.patches();
  return {{"samples", samples},
          {"patch_range", {r.u.first, r.u.last, r.v.first, r.v.last}},
          {"alpha_nodes", list(surface.alphaNodes())},
          {"alpha_v", list(surface.alphaV())}};
}

json caseResult(const json& c) {
  const std::string family = c.at("family");
  const json& in = c.contains("inputs") ? c.at("inputs") : json::object();
  const json params = c.value("params", json::object());
  if (family == "curve") return curveCase(c);
  if (family == "surface") return surfaceCase(c);
  if (family == "basis.xuwang") return spanTable(xuWangSpanBasis(params.at("degree").get<int>(), num(params.at("lambda"))), in.at("t"), true);
  if (family == "basis.gb") return spanTable(gbSpanBasis(num(params.at("lambda"))), in.at("t"), true);
  if (family == "basis.singular_blend") {
    json s = json::array(), d1 = json::array(), d2 = json::array();
    for (const auto& t : in.at("t")) {
      const BlendValue b = singularBlend(num(t));
      put(s, b.s), put(d1, b.d1), put(d2, b.d2);
    }
    return {{"values", s}, {"d1", d1}, {"d2", d2}};
  }
  if (family == "basis.ubp" || family == "basis.gubp") {
    const int order = params.at("order").get<int>();
    SpanBasis b;
    json o;
    if (family == "basis.ubp") {
      b = ubpSpanBasis(order, num(params.at("lambda")));
      o["doubled_knot_coefficients"] = list(ubpDoubledKnotCoefficients(order, num(params.at("lambda"))));
    } else {
      std::vector<double> mu;
      for (const auto& x : params.at("mu")) mu.push_back(num(x));
      b = gubpSpanBasis(order, mu);
    }
    o.update(bell(b, in.at("x")));
    const json local = spanTable(b, in.at("t"), false);
    o["local_values"] = local.at("values");
    o["local_d1"] = local.at("d1");
    return o;
  }
  if (family == "gb_modify") {
    const auto model = std::get<CurveModel>(io::parseModel(c.at("model")));
    const glm::dvec3 x = points(json::array({in.at("target")}))[0];
    const GbFitResult fit = gbConstrainedModify(model, in.at("span").get<int>(), {x.x, x.y});
    json all = json::array();
    for (const auto& s : fit.all) put(all, s.t0), put(all, s.lambda0), put(all, s.w);
    return {{"reachable", fit.reachable},
            {"bisection", list(std::vector<double>{fit.bisection.t0, fit.bisection.lambda0, fit.bisection.w})},
            {"all_solutions", all}};
  }
  if (family == "bspline_unclamp") {
    const auto model = std::get<CurveModel>(io::parseModel(c.at("model")));
    std::vector<double> knots;
    for (const auto& x : in.at("new_right_knots")) knots.push_back(num(x));
    const BSplineCurveData un = unclampRight(bsplineCurveFromModel(model), knots);
    return {{"points", list(un.points)}, {"knots", list(un.knots)}};
  }
  if (family == "bspline_extend_curve") {
    const auto model = std::get<CurveModel>(io::parseModel(c.at("model")));
    const ExtensionResult e = extendCurve(bsplineCurveFromModel(model), points(in.at("targets")), given(in));
    CurveModel ext = model;
    ext.points = e.curve.points;
    ext.knots = e.curve.knots;
    const Curve curve = Curve::create(ext);
    json samples = json::array();
    for (const auto& s : c.at("expected").at("samples")) {
      const CurvePoint p = curve.evaluateAt(num(s.at("t")));
      put(samples, p.point), put(samples, p.d1);
    }
    return {{"u", list(e.u)},
            {"unclamp_knots", list(e.unclampKnots)},
            {"unclamped_points", list(e.unclampedPoints)},
            {"points", list(e.curve.points)},
            {"knots", list(e.curve.knots)},
            {"knots_normalized", list(e.knotsNormalized)},
            {"samples", samples}};
  }
  if (family == "bspline_extend_surface") {
    const auto model = std::get<SurfaceModel>(io::parseModel(c.at("model")));
    std::vector<std::vector<glm::dvec3>> curves;
    for (const auto& t : in.at("target_curves")) curves.push_back(points(t));
    const SurfaceExtensionResult e = extendSurfaceU(bsplineSurfaceFromModel(model), curves, given(in));
    SurfaceModel ext = model;
    ext.rows = e.surface.rows;
    ext.cols = e.surface.cols;
    ext.points = e.surface.points;
    ext.knotsU = e.surface.knotsU;
    ext.knotsV = e.surface.knotsV;
    const Surface surface = Surface::create(ext);
    json samples = json::array();
    for (const auto& s : c.at("expected").at("samples")) {
      const SurfacePoint p = surface.evaluateAt(num(s.at("t")), num(s.at("s")));
      put(samples, p.point), put(samples, p.du), put(samples, p.dv);
    }
    return {{"u", list(e.u)},
            {"points", list(e.surface.points)},
            {"knots_u", list(e.surface.knotsU)},
            {"knots_v", list(e.surface.knotsV)},
            {"knots_normalized_u", list(e.knotsNormalizedU)},
            {"samples", samples}};
  }
  if (family == "validation") {
    try {
      io::parseModel(c.at("model"));
      return {{"valid", true}};
    } catch (const ModelError& e) {
      return {{"valid", false}, {"field", e.field()}};
    }
  }
  throw std::runtime_error("no reference for family " + family);
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path dir = argc > 1 ? argv[1] : "tests/data/golden";
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  json out = json::object();
  try {
    for (const auto& f : files) {
      std::ifstream in(f);
      const json doc = json::parse(in);
      for (const auto& c : doc.at("cases")) out[c.at("id").get<std::string>()] = caseResult(c);
    }
  } catch (const std::exception& e) {
    std::cerr << "golden_reference: " << e.what() << "\n";
    return 1;
  }
  std::cout << out.dump() << "\n";
  return 0;
}
