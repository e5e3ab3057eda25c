// `shapespline eval MODEL --at SAMPLES.json`: evaluation at an explicit list of samples, in the
// shape of a golden case's `inputs`; prints {"samples": [...]} with the golden field names and 17
// significant digits. Surfaces: `normal` is null where the golden convention calls it undefined
// (sin of the angle between du and dv below 0.01); `render_normal` then gives the docs/math.md §5.3
// rendering normal.
#include <shapespline/cli/common.h>
#include <shapespline/cli/sampling.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/sample_list.h>

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

double rounded(double v, Precision p) { return p == Precision::Float ? static_cast<double>(static_cast<float>(v)) : v; }
glm::dvec3 rounded(const glm::dvec3& v, Precision p) { return {rounded(v.x, p), rounded(v.y, p), rounded(v.z, p)}; }

// v * 2^-e with its largest |component| in [2^e, 2^(e+1)) (v for a zero vector). By ldexp, not by
// the factor 2^-e, which overflows for a subnormal v (a net 1e-320 wide).
glm::dvec3 unitScaled(const glm::dvec3& v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0.0) || !std::isfinite(m)) return v;
  const int e = -std::ilogb(m);
  return {std::ldexp(v.x, e), std::ldexp(v.y, e), std::ldexp(v.z, e)};
}

// ±inf in a result whose evaluation was otherwise sound: a value beyond the output precision (fp64
// derivatives of knot intervals near 1e-310 grow like 1/h^r), not an internal error. NaN goes on to
// requireFinite.
void requireInRange(const glm::dvec3& v, const char* field, Precision p) {
  for (int k = 0; k < 3; ++k)
    if (std::isinf(v[k]))
      throw RuntimeError(field, number17(v[k]),
                         p == Precision::Float
                             ? "exceeds the fp32 range of the output (use --precision double); nothing was written"
                             : "exceeds the fp64 range of the output (derivatives scale with 1/h^r for knot "
                               "intervals h); nothing was written");
  requireFinite(v, field);
}

// A global parameter is derived from the knots, not evaluated: checked like every number written.
double finiteParameter(double v, const char* field) {
  if (!std::isfinite(v)) throw RuntimeError(field, number17(v), "the global parameter is not finite; nothing was written");
  return v;
}

std::string evalCurve(const Curve& curve, const json& at, Precision p, bool gpu) {
  const int dim = curve.dimension();
  const std::vector<io::CurveSample> queries = io::parseCurveSamples(at, curve, "--at");
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
        throw InputError("samples[" + std::to_string(i) + "]", io::shortValue(at.at("samples")[i]),
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
    requireInRange(rounded(cp.point, p), "point", p);
    requireInRange(rounded(cp.d1, p), "d1", p);
    requireInRange(rounded(cp.d2, p), "d2", p);
    const std::string head = q.global ? "\"u\": " + number17(q.u)
                                      : "\"span\": " + std::to_string(q.span) + ", \"t\": " + number17(q.t) +
                                            ", \"u\": " + number17(finiteParameter(curve.parameterOf(q.span, q.t), "u"));
    out += std::string(i ? ",\n  " : "\n  ") + "{" + head + ", \"point\": " + vector17(rounded(cp.point, p), dim) +
           ", \"d1\": " + vector17(rounded(cp.d1, p), dim) + ", \"d2\": " + vector17(rounded(cp.d2, p), dim) + "}";
  }
  return out + "\n]}\n";
}

std::string evalSurface(const Surface& surface, const json& at, Precision p, bool gpu) {
  std::vector<std::array<double, 4>> queries;
  for (const io::SurfaceSample& q : io::parseSurfaceSamples(at, surface, "--at"))
    queries.push_back({static_cast<double>(q.patchU), static_cast<double>(q.patchV), q.u, q.v});
  std::vector<SurfacePoint> points(queries.size());
  if (gpu) {
    points = gpuEvaluateSurface(surface, queries, p);
  } else {
    for (size_t i = 0; i < queries.size(); ++i) {
      const auto& q = queries[i];
      try {
        points[i] = surface.evaluate(static_cast<int>(q[0]), static_cast<int>(q[1]), q[2], q[3]);
      } catch (const std::out_of_range& e) {
        throw InputError("samples[" + std::to_string(i) + "]", io::shortValue(at.at("samples")[i]),
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
    const std::pair<const char*, const glm::dvec3*> fields[] = {{"point", &sp.point}, {"du", &sp.du},
                                                                 {"dv", &sp.dv},       {"duu", &sp.duu},
                                                                 {"duv", &sp.duv},     {"dvv", &sp.dvv},
                                                                 {"normal", &sp.normal}};
    for (const auto& [name, x] : fields) requireInRange(rounded(*x, p), name, p);
    // du and dv scaled by powers of two (exact) first, so that cross and lengths neither overflow
    // for huge nets nor underflow for tiny ones; the normal and the sine test are scale-free.
    const glm::dvec3 du = unitScaled(sp.du), dv = unitScaled(sp.dv);
    const glm::dvec3 cross = glm::cross(du, dv);
    const double denom = glm::length(du) * glm::length(dv);
    const bool defined = denom > 0.0 && glm::length(cross) >= 0.01 * denom;
    const std::string normal = defined ? vector17(rounded(glm::normalize(cross), p), 3) : "null";
    out += std::string(i ? ",\n  " : "\n  ") + "{\"patch\": [" + std::to_string(pi) + ", " + std::to_string(pj) +
           "], \"uv\": [" + number17(u) + ", " + number17(v) + "], \"UV\": [" + number17(finiteParameter(global(pi, u, m.knotsU), "UV")) +
           ", " + number17(finiteParameter(global(pj, v, m.knotsV), "UV")) + "], \"point\": " + vector17(rounded(sp.point, p), 3) +
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
  std::visit([&](const auto& m) { requireFloatRange(m.points, precision); }, model);
  const Device device = resolveDevice(requested, precision, args.quiet, args.requireDevice);
  std::string text;
  if (std::holds_alternative<CurveModel>(model)) {
    const Curve curve = Curve::create(std::get<CurveModel>(std::move(model)));
    const bool gpu = device == Device::Vulkan && gpuHandles(&curve, nullptr, precision, args.quiet, args.requireDevice);
    printPrecisionWarnings(curve.model(), gpu && precision == Precision::Float, args.quiet);
    text = evalCurve(curve, at, precision, gpu);
  } else {
    const Surface surface = Surface::create(std::get<SurfaceModel>(std::move(model)));
    const bool gpu = device == Device::Vulkan && gpuHandles(nullptr, &surface, precision, args.quiet, args.requireDevice);
    printPrecisionWarnings(surface.model(), gpu && precision == Precision::Float, args.quiet);
    text = evalSurface(surface, at, precision, gpu);
  }
  io::writeStdout(text);
  io::flushStdout();
}

}  // namespace

void registerEval(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* sub = app.add_subcommand("eval", "Evaluate a model at an explicit list of samples; prints JSON.");
  sub->add_option("MODEL", args->model, "model file (docs/format.md)")->required();
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
