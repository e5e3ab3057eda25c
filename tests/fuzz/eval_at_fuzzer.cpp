// libFuzzer target over `eval --at` sample lists (issue 12): the bytes of an --at file, parsed as
// the command line parses them (io::parseJsonText with the input limits, then io::parseCurveSamples
// / io::parseSurfaceSamples) against fixed curves and surfaces, and every accepted sample evaluated
// on the CPU fp64 path. The contract checked here:
//  * parsing either returns or throws ModelError (exit code 2); nothing else escapes;
//  * every error message stays bounded (no serialized input beyond io::kMaxValueChars);
//  * an accepted sample is in range (span/patch in the model's range, t/uv in [0, 1], u finite) and
//    evaluates to finite values, or is refused by evaluation with std::out_of_range (an empty knot
//    interval, u outside the parameter range), which `eval` reports as bad input.
// Sanitizers and libFuzzer's -timeout turn everything else into a finding. The same function is
// linked into `eval_at_fuzz_replay` (replay_main.cpp) for builds without libFuzzer.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/sample_list.h>

namespace {

using namespace shapespline;

constexpr size_t kMaxInputBytes = 1 << 16;
constexpr size_t kMaxEvaluated = 256;  // samples evaluated per model and input
constexpr size_t kMaxMessageChars = 400;

// Models the samples are checked against: a local-family curve, a knot-vector curve with a double
// knot, a local-family surface and a knot-vector surface (docs/format.md).
constexpr const char* kCurves[] = {
    R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, "lambda": -2.5, "closed": false,
        "points": [[0, 0], [1, 2], [3, 3], [5, 1], [6, 4], [8, 3]], "alpha": [0.5, 0.25, 1, 0.75, 0.5, 0.625]})",
    R"({"kind": "curve", "construction": "bspline", "order": 3, "closed": false,
        "points": [[0, 0, 0], [1, 2, 0], [3, 3, 1], [5, 1, 0], [6, 4, 2]], "knots": [0, 0, 0, 1, 1, 2, 2, 2]})",
};
constexpr const char* kSurfaces[] = {
    R"({"kind": "surface", "construction": "alpha_eb", "degree": 4, "lambda": 0, "closed": [false, true],
        "points": [[[0, 0, 0], [0, 1, 0.5], [0, 2, 0], [0, 3, -0.5]], [[1, 0, 0.5], [1, 1, 1.5], [1, 2, 1], [1, 3, 0]],
                   [[2, 0, 0], [2, 1, 1], [2, 2, 0.5], [2, 3, 0]], [[3, 0, 0.5], [3, 1, 0], [3, 2, 1], [3, 3, 0.5]]],
        "alpha": 0.5})",
    R"({"kind": "surface", "construction": "bspline", "order": [3, 3], "closed": [false, false],
        "points": [[[0, 0, 0], [0, 1, 1], [0, 2, 0], [0, 3, 0.5]], [[1, 0, 1], [1, 1, 2], [1, 2, 1], [1, 3, 1]],
                   [[2, 0, 0], [2, 1, 1], [2, 2, 0.5], [2, 3, 0]], [[3, 0, 0.5], [3, 1, 0], [3, 2, 1], [3, 3, 0.5]]],
        "knots": [[0, 0, 0, 0.5, 1, 1, 1], [0, 0, 0, 0.25, 1, 1, 1]]})",
};

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "eval_at_fuzzer: %s: %s\n", what, detail.substr(0, 2000).c_str());
  std::abort();
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void checkMessage(const ModelError& e) {
  if (std::string(e.what()).size() > kMaxMessageChars) finding("unbounded error message", e.what());
}

const std::vector<Curve>& curves() {
  static const std::vector<Curve> c = [] {
    std::vector<Curve> v;
    for (const char* text : kCurves) v.push_back(Curve::create(std::get<CurveModel>(io::parseModelText(text))));
    return v;
  }();
  return c;
}

const std::vector<Surface>& surfaces() {
  static const std::vector<Surface> s = [] {
    std::vector<Surface> v;
    for (const char* text : kSurfaces) v.push_back(Surface::create(std::get<SurfaceModel>(io::parseModelText(text))));
    return v;
  }();
  return s;
}

void fuzzCurve(const nlohmann::json& doc, const Curve& curve) {
  std::vector<io::CurveSample> samples;
  try {
    samples = io::parseCurveSamples(doc, curve);
  } catch (const ModelError& e) {
    checkMessage(e);
    return;
  }
  const SpanRange r = curve.spans();
  for (size_t i = 0; i < samples.size() && i < kMaxEvaluated; ++i) {
    const io::CurveSample& s = samples[i];
    if (s.global ? !std::isfinite(s.u) : (s.span < r.first || s.span > r.last || !(s.t >= 0.0 && s.t <= 1.0)))
      finding("accepted sample out of range", std::to_string(s.span) + " " + std::to_string(s.t));
    CurvePoint p;
    try {
      p = s.global ? curve.evaluateAt(s.u) : curve.evaluate(s.span, s.t);
    } catch (const std::out_of_range&) {
      continue;  // reported by `eval` as InputError
    }
    if (!(finite(p.point) && finite(p.d1) && finite(p.d2))) finding("non-finite curve value", std::to_string(i));
  }
}

void fuzzSurface(const nlohmann::json& doc, const Surface& surface) {
  std::vector<io::SurfaceSample> samples;
  try {
    samples = io::parseSurfaceSamples(doc, surface);
  } catch (const ModelError& e) {
    checkMessage(e);
    return;
  }
  const PatchRange r = surface.patches();
  for (size_t i = 0; i < samples.size() && i < kMaxEvaluated; ++i) {
    const io::SurfaceSample& s = samples[i];
    if (s.patchU < r.u.first || s.patchU > r.u.last || s.patchV < r.v.first || s.patchV > r.v.last ||
        !(s.u >= 0.0 && s.u <= 1.0 && s.v >= 0.0 && s.v <= 1.0))
      finding("accepted sample out of range", std::to_string(s.patchU) + " " + std::to_string(s.patchV));
    SurfacePoint p;
    try {
      p = surface.evaluate(s.patchU, s.patchV, s.u, s.v);
    } catch (const std::out_of_range&) {
      continue;
    }
    if (!(finite(p.point) && finite(p.du) && finite(p.dv) && finite(p.duu) && finite(p.duv) && finite(p.dvv) &&
          finite(p.normal)))
      finding("non-finite surface value", std::to_string(i));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > kMaxInputBytes) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  nlohmann::json doc;
  try {
    doc = io::parseJsonText(text, "--at", "--at");
  } catch (const ModelError& e) {
    checkMessage(e);
    return 0;
  }
  if (io::shortValue(doc).size() > io::kMaxValueChars) finding("shortValue too long", io::shortValue(doc));
  for (const Curve& c : curves()) fuzzCurve(doc, c);
  for (const Surface& s : surfaces()) fuzzSurface(doc, s);
  return 0;
}
