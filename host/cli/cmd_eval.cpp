// `shapespline eval MODEL --at SAMPLES.json`: evaluation at an explicit list of samples, in the
// shape of a golden case's `inputs`; prints {"samples": [...]} with the golden field names and 17
// significant digits. Surfaces: `normal` is null where the golden convention calls it undefined
// (sin of the angle between du and dv below 0.01); `render_normal` then gives the MATH.md §5.3
// rendering normal.
#include "cli/common.h"
#include "cli/sampling.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

namespace shapespline::cli {
namespace {

struct EvalArgs {
  std::string model, at, device = "vulkan", precision = "double";
  bool quiet = false, requireDevice = false;
};

using nlohmann::json;

double numberAt(const json& obj, const char* key, const std::string& path) {
  if (!obj.is_object() || !obj.contains(key)) throw InputError(path + "." + key, "", "missing");
  const json& v = obj.at(key);
  if (!v.is_number()) throw InputError(path + "." + key, v.dump(), "must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw InputError(path + "." + key, v.dump(), "must be finite");
  return d;
}

int integerAt(const json& v, const std::string& path) {
  if (!v.is_number()) throw InputError(path, v.dump(), "must be an integer");
  const double d = v.get<double>();
  if (d != std::floor(d) || std::fabs(d) > 1e9) throw InputError(path, v.dump(), "must be an integer");
  return static_cast<int>(d);
}

double rounded(double v, Precision p) { return p == Precision::Float ? static_cast<double>(static_cast<float>(v)) : v; }
glm::dvec3 rounded(const glm::dvec3& v, Precision p) { return {rounded(v.x, p), rounded(v.y, p), rounded(v.z, p)}; }

// 2^-e with the vector's largest |component| in [2^e, 2^(e+1)); 1 for a zero vector.
double unitScale(const glm::dvec3& v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  return m > 0.0 && std::isfinite(m) ? std::ldexp(1.0, -std::ilogb(m)) : 1.0;
}

struct CurveQuery {
  bool global = false;  // {"u": u}
  int span = 0;
  double t = 0.0, u = 0.0;
};

std::string evalCurve(const Curve& curve, const json& samples, Precision p, bool gpu) {
  const int dim = curve.dimension();
  std::vector<CurveQuery> queries;
  queries.reserve(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const std::string path = "samples[" + std::to_string(i) + "]";
    const json& s = samples[i];
    if (!s.is_object()) throw InputError(path, s.dump(), "must be an object");
    CurveQuery q;
    if (s.contains("u") && !s.contains("span")) {
      q.global = true;
      q.u = numberAt(s, "u", path);
    } else {
      if (curve.usesKnotVector()) throw InputError(path, s.dump(), "a knot-vector B-spline takes {\"u\": value}");
      if (!s.contains("span")) throw InputError(path + ".span", "", "missing");
      q.span = integerAt(s.at("span"), path + ".span");
      q.t = numberAt(s, "t", path);
      const SpanRange r = curve.spans();
      if (q.span < r.first || q.span > r.last) {
        throw InputError(path + ".span", std::to_string(q.span),
                         "must be in [" + std::to_string(r.first) + ", " + std::to_string(r.last) + "]");
      }
      if (!(q.t >= 0.0 && q.t <= 1.0)) throw InputError(path + ".t", number17(q.t), "must be in [0, 1]");
    }
    queries.push_back(q);
  }
  std::vector<CurvePoint> points(queries.size());
  bool onGpu = gpu;
  for (const auto& q : queries) onGpu = onGpu && !q.global;
  if (gpu && !onGpu) {
    std::fprintf(stderr, "shapespline: notice: {\"u\": ...} samples are evaluated on the CPU fp64 path\n");
  }
  if (onGpu) {
    std::vector<std::pair<int, double>> list;
    for (const auto& q : queries) list.emplace_back(q.span, q.t);
    points = gpuEvaluateCurve(curve, list, p);
  } else {
    for (size_t i = 0; i < queries.size(); ++i) {
      try {
        points[i] = queries[i].global ? curve.evaluateAt(queries[i].u) : curve.evaluate(queries[i].span, queries[i].t);
      } catch (const std::out_of_range& e) {
        throw InputError("samples[" + std::to_string(i) + "]", samples[i].dump(),
                         std::string("outside the model's parameter range: ") + e.what());
      }
    }
  }
  std::string out = "{\"samples\": [";
  if (nanFaultInjected() && !points.empty()) points[0].point.x = std::nan("");
  for (size_t i = 0; i < queries.size(); ++i) {
    const auto& q = queries[i];
    const CurvePoint& cp = points[i];
    // Checked after rounding: an fp64 value beyond 3.4e38 becomes inf in fp32.
    requireFinite(rounded(cp.point, p), "point");
    requireFinite(rounded(cp.d1, p), "d1");
    requireFinite(rounded(cp.d2, p), "d2");
    const std::string head = q.global ? "\"u\": " + number17(q.u)
                                      : "\"span\": " + std::to_string(q.span) + ", \"t\": " + number17(q.t) +
                                            ", \"u\": " + number17(curve.parameterOf(q.span, q.t));
    out += std::string(i ? ",\n  " : "\n  ") + "{" + head + ", \"point\": " + vector17(rounded(cp.point, p), dim) +
           ", \"d1\": " + vector17(rounded(cp.d1, p), dim) + ", \"d2\": " + vector17(rounded(cp.d2, p), dim) + "}";
  }
  return out + "\n]}\n";
}

std::string evalSurface(const Surface& surface, const json& samples, Precision p, bool gpu) {
  std::vector<std::array<double, 4>> queries;
  queries.reserve(samples.size());
  const PatchRange range = surface.patches();
  for (size_t i = 0; i < samples.size(); ++i) {
    const std::string path = "samples[" + std::to_string(i) + "]";
    const json& s = samples[i];
    if (!s.is_object()) throw InputError(path, s.dump(), "must be an object");
    if (!s.contains("patch") || !s["patch"].is_array() || s["patch"].size() != 2) {
      throw InputError(path + ".patch", s.contains("patch") ? s["patch"].dump() : "", "must be [i, j]");
    }
    if (!s.contains("uv") || !s["uv"].is_array() || s["uv"].size() != 2) {
      throw InputError(path + ".uv", s.contains("uv") ? s["uv"].dump() : "", "must be [u, v]");
    }
    const int pi = integerAt(s["patch"][0], path + ".patch[0]"), pj = integerAt(s["patch"][1], path + ".patch[1]");
    if (pi < range.u.first || pi > range.u.last) {
      throw InputError(path + ".patch[0]", std::to_string(pi),
                       "must be in [" + std::to_string(range.u.first) + ", " + std::to_string(range.u.last) + "]");
    }
    if (pj < range.v.first || pj > range.v.last) {
      throw InputError(path + ".patch[1]", std::to_string(pj),
                       "must be in [" + std::to_string(range.v.first) + ", " + std::to_string(range.v.last) + "]");
    }
    double uv[2];
    for (int k = 0; k < 2; ++k) {
      const json& v = s["uv"][static_cast<size_t>(k)];
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0.0 || v.get<double>() > 1.0) {
        throw InputError(path + ".uv[" + std::to_string(k) + "]", v.dump(), "must be a number in [0, 1]");
      }
      uv[k] = v.get<double>();
    }
    queries.push_back({static_cast<double>(pi), static_cast<double>(pj), uv[0], uv[1]});
  }
  std::vector<SurfacePoint> points(queries.size());
  if (gpu) {
    points = gpuEvaluateSurface(surface, queries, p);
  } else {
    for (size_t i = 0; i < queries.size(); ++i) {
      const auto& q = queries[i];
      try {
        points[i] = surface.evaluate(static_cast<int>(q[0]), static_cast<int>(q[1]), q[2], q[3]);
      } catch (const std::out_of_range& e) {
        throw InputError("samples[" + std::to_string(i) + "]", samples[i].dump(),
                         std::string("outside the model's patch/parameter range: ") + e.what());
      }
    }
  }
  const auto& m = surface.model();
  auto global = [&](int idx, double local, const std::vector<double>& knots) {
    return surface.usesKnotVector()
               ? knots[static_cast<size_t>(idx)] + local * (knots[static_cast<size_t>(idx) + 1] - knots[static_cast<size_t>(idx)])
               : idx + local;
  };
  std::string out = "{\"samples\": [";
  for (size_t i = 0; i < queries.size(); ++i) {
    const int pi = static_cast<int>(queries[i][0]), pj = static_cast<int>(queries[i][1]);
    const double u = queries[i][2], v = queries[i][3];
    if (nanFaultInjected() && i == 0) points[0].point.x = std::nan("");
    const SurfacePoint& sp = points[i];
    for (const auto* x : {&sp.point, &sp.du, &sp.dv, &sp.duu, &sp.duv, &sp.dvv, &sp.normal}) {
      requireFinite(rounded(*x, p), "value");
    }
    // du and dv scaled by powers of two (exact) first, so that cross and lengths neither overflow
    // for huge nets nor underflow for tiny ones; the normal and the sine test are scale-free.
    const glm::dvec3 du = sp.du * unitScale(sp.du), dv = sp.dv * unitScale(sp.dv);
    const glm::dvec3 cross = glm::cross(du, dv);
    const double denom = glm::length(du) * glm::length(dv);
    const bool defined = denom > 0.0 && glm::length(cross) >= 0.01 * denom;
    const std::string normal = defined ? vector17(rounded(glm::normalize(cross), p), 3) : "null";
    out += std::string(i ? ",\n  " : "\n  ") + "{\"patch\": [" + std::to_string(pi) + ", " + std::to_string(pj) +
           "], \"uv\": [" + number17(u) + ", " + number17(v) + "], \"UV\": [" + number17(global(pi, u, m.knotsU)) +
           ", " + number17(global(pj, v, m.knotsV)) + "], \"point\": " + vector17(rounded(sp.point, p), 3) +
           ", \"du\": " + vector17(rounded(sp.du, p), 3) + ", \"dv\": " + vector17(rounded(sp.dv, p), 3) +
           ", \"duu\": " + vector17(rounded(sp.duu, p), 3) + ", \"duv\": " + vector17(rounded(sp.duv, p), 3) +
           ", \"dvv\": " + vector17(rounded(sp.dvv, p), 3) + ", \"normal\": " + normal +
           (defined ? std::string() : ", \"render_normal\": " + vector17(rounded(sp.normal, p), 3)) + "}";
  }
  return out + "\n]}\n";
}

void runEval(const EvalArgs& args) {
  const Device requested = parseDevice(args.device);
  const Precision precision = parsePrecision(args.precision);
  io::Model model = loadModel(args.model);
  const json at = readJsonFile(args.at, "--at");
  if (!at.is_object() || !at.contains("samples") || !at["samples"].is_array()) {
    throw InputError("--at", args.at, "expected an object {\"samples\": [...]}");
  }
  if (at["samples"].size() > 100'000'000) throw InputError("--at", args.at, "at most 1e8 samples");
  std::visit([&](const auto& m) { requireFloatRange(m.points, precision); }, model);
  const Device device = resolveDevice(requested, precision, args.quiet, args.requireDevice);
  std::string text;
  if (std::holds_alternative<CurveModel>(model)) {
    const Curve curve = Curve::create(std::get<CurveModel>(std::move(model)));
    const bool gpu = device == Device::Vulkan && gpuHandles(&curve, nullptr, precision, args.quiet, args.requireDevice);
    printPrecisionWarnings(curve.model(), gpu && precision == Precision::Float, args.quiet);
    text = evalCurve(curve, at["samples"], precision, gpu);
  } else {
    const Surface surface = Surface::create(std::get<SurfaceModel>(std::move(model)));
    const bool gpu = device == Device::Vulkan && gpuHandles(nullptr, &surface, precision, args.quiet, args.requireDevice);
    printPrecisionWarnings(surface.model(), gpu && precision == Precision::Float, args.quiet);
    text = evalSurface(surface, at["samples"], precision, gpu);
  }
  std::fwrite(text.data(), 1, text.size(), stdout);
  if (std::fflush(stdout) != 0) throw std::runtime_error("writing to stdout failed");
}

}  // namespace

void registerEval(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* sub = app.add_subcommand("eval", "Evaluate a model at an explicit list of samples; prints JSON.");
  sub->add_option("MODEL", args->model, "model file (FORMAT.md)")->required();
  sub->add_option("--at", args->at,
                  "samples file: {\"samples\":[{\"span\":j,\"t\":t}]} (curves), [{\"u\":u}] (knot-vector "
                  "B-splines), [{\"patch\":[i,j],\"uv\":[u,v]}] (surfaces)")
      ->required();
  sub->add_option("--device", args->device, "vulkan (default; falls back to cpu with a notice) or cpu");
  sub->add_option("--precision", args->precision, "float or double (default double)");
  sub->add_flag("--require-device", args->requireDevice,
                "with --device vulkan: fail (exit 3) instead of falling back to the CPU");
  sub->add_flag("-q,--quiet", args->quiet, "no notices and no warnings");
  sub->footer(kExitCodeHelp);
  sub->callback([args] { runEval(*args); });
}

}  // namespace shapespline::cli
