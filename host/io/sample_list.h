#pragma once
// `eval --at` sample lists: the JSON document {"samples": [...]} (the shape of a golden case's
// `inputs`) read into samples checked against the curve or surface they are for. Curves take
// {"span": j, "t": t} (j in spans(), t in [0, 1]) or {"u": u} (a global parameter in
// parameterRange(); the only form a knot-vector B-spline takes); surfaces take {"patch": [i, j],
// "uv": [u, v]} (i, j in patches(), u, v in [0, 1]). Every failure is a ModelError naming the field
// under the document's (`documentField`: "--at.samples[3].t"), the value (io::shortValue) and the
// rule: a query the model cannot answer is the user's input, never an evaluation error.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>

namespace shapespline::io {

// Samples one list may hold (the output of `eval` is about 200 bytes per sample).
inline constexpr std::size_t kMaxSamples = 1'000'000;

struct CurveSample {
  bool global = false;  // {"u": u}; otherwise {"span": span, "t": t}
  int span = 0;
  double t = 0.0, u = 0.0;
};

struct SurfaceSample {
  int patchU = 0, patchV = 0;
  double u = 0.0, v = 0.0;
};

// Throws ModelError.
std::vector<CurveSample> parseCurveSamples(const nlohmann::json& doc, const Curve& curve,
                                           const std::string& documentField = "--at");
std::vector<SurfaceSample> parseSurfaceSamples(const nlohmann::json& doc, const Surface& surface,
                                               const std::string& documentField = "--at");

}  // namespace shapespline::io
