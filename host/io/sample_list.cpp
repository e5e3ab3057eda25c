#include <shapespline/io/sample_list.h>

#include <cmath>

#include <shapespline/core/value_text.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/number_text.h>

namespace shapespline::io {

namespace {

using nlohmann::json;

// Integers any sample index can meaningfully hold; larger ones are rejected before conversion.
constexpr double kMaxIndex = 1e9;

std::string range(const SpanRange& r) { return "[" + std::to_string(r.first) + ", " + std::to_string(r.last) + "]"; }

const json& sampleArray(const json& doc, const std::string& documentField) {
  if (!doc.is_object() || !doc.contains("samples") || !doc.at("samples").is_array())
    throw ModelError(documentField, shortValue(doc), "expected an object {\"samples\": [...]}");
  const json& samples = doc.at("samples");
  if (samples.size() > kMaxSamples)
    throw ModelError(documentField, std::to_string(samples.size()) + " samples",
         "a sample list holds at most " + std::to_string(kMaxSamples) + " samples");
  return samples;
}

double numberAt(const json& obj, const char* key, const std::string& path) {
  if (!obj.contains(key)) throw ModelError(path + "." + key, "", "missing");
  const json& v = obj.at(key);
  if (!v.is_number()) throw ModelError(path + "." + key, shortValue(v), "must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw ModelError(path + "." + key, shortValue(v), "must be finite");
  return d;
}

int integerAt(const json& v, const std::string& path) {
  if (!v.is_number()) throw ModelError(path, shortValue(v), "must be an integer");
  const double d = v.get<double>();
  if (d != std::floor(d) || std::fabs(d) > kMaxIndex) throw ModelError(path, shortValue(v), "must be an integer");
  return static_cast<int>(d);
}

}  // namespace

std::vector<CurveSample> parseCurveSamples(const json& doc, const Curve& curve, const std::string& documentField) {
  const json& samples = sampleArray(doc, documentField);
  const SpanRange r = curve.spans();
  const auto [lo, hi] = curve.parameterRange();
  std::vector<CurveSample> out;
  out.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const std::string path = documentField + ".samples[" + std::to_string(i) + "]";
    const json& s = samples[i];
    if (!s.is_object()) throw ModelError(path, shortValue(s), "must be an object");
    CurveSample q;
    if (s.contains("u") && !s.contains("span")) {
      q.global = true;
      q.u = numberAt(s, "u", path);
      if (!(q.u >= lo && q.u <= hi))
        throw ModelError(path + ".u", shortValue(s.at("u")), "must be in the model's parameter range [" + shortestText(lo) + ", " +
                                                     shortestText(hi) + "]");
    } else {
      if (curve.usesKnotVector()) throw ModelError(path, shortValue(s), "a knot-vector B-spline takes {\"u\": value}");
      if (!s.contains("span")) throw ModelError(path + ".span", "", "missing");
      q.span = integerAt(s.at("span"), path + ".span");
      q.t = numberAt(s, "t", path);
      if (q.span < r.first || q.span > r.last) throw ModelError(path + ".span", std::to_string(q.span), "must be in " + range(r));
      if (!(q.t >= 0.0 && q.t <= 1.0)) throw ModelError(path + ".t", shortValue(s.at("t")), "must be in [0, 1]");
    }
    out.push_back(q);
  }
  return out;
}

std::vector<SurfaceSample> parseSurfaceSamples(const json& doc, const Surface& surface,
                                               const std::string& documentField) {
  const json& samples = sampleArray(doc, documentField);
  const PatchRange patches = surface.patches();
  std::vector<SurfaceSample> out;
  out.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const std::string path = documentField + ".samples[" + std::to_string(i) + "]";
    const json& s = samples[i];
    if (!s.is_object()) throw ModelError(path, shortValue(s), "must be an object");
    if (!s.contains("patch") || !s.at("patch").is_array() || s.at("patch").size() != 2)
      throw ModelError(path + ".patch", s.contains("patch") ? shortValue(s.at("patch")) : "", "must be [i, j]");
    if (!s.contains("uv") || !s.at("uv").is_array() || s.at("uv").size() != 2)
      throw ModelError(path + ".uv", s.contains("uv") ? shortValue(s.at("uv")) : "", "must be [u, v]");
    SurfaceSample q;
    q.patchU = integerAt(s.at("patch")[0], path + ".patch[0]");
    q.patchV = integerAt(s.at("patch")[1], path + ".patch[1]");
    if (q.patchU < patches.u.first || q.patchU > patches.u.last)
      throw ModelError(path + ".patch[0]", std::to_string(q.patchU), "must be in " + range(patches.u));
    if (q.patchV < patches.v.first || q.patchV > patches.v.last)
      throw ModelError(path + ".patch[1]", std::to_string(q.patchV), "must be in " + range(patches.v));
    if (surface.usesKnotVector()) {
      const SurfaceShape& m = surface.model();
      const auto empty = [](const std::vector<double>& knots, int k) { return !(knots[k + 1] > knots[k]); };
      if (empty(m.knotsU, q.patchU))
        throw ModelError(path + ".patch[0]", std::to_string(q.patchU), "is an empty knot interval (knotsU[i] = knotsU[i+1])");
      if (empty(m.knotsV, q.patchV))
        throw ModelError(path + ".patch[1]", std::to_string(q.patchV), "is an empty knot interval (knotsV[j] = knotsV[j+1])");
    }
    double uv[2];
    for (std::size_t k = 0; k < 2; ++k) {
      const json& v = s.at("uv")[k];
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0.0 || v.get<double>() > 1.0)
        throw ModelError(path + ".uv[" + std::to_string(k) + "]", shortValue(v), "must be a number in [0, 1]");
      uv[k] = v.get<double>();
    }
    q.u = uv[0];
    q.v = uv[1];
    out.push_back(q);
  }
  return out;
}

}  // namespace shapespline::io
