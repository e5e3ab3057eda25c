// `shapespline eval MODEL --at SAMPLES.json`: evaluation at an explicit list of samples, in the
// shape of a golden case's `inputs`; prints {"samples": [...]} with the golden field names and 17
// significant digits. Surfaces: `normal` is null where the golden convention calls it undefined
// (sin of the angle between du and dv below 0.01); `render_normal` then gives the docs/math.md §5.3
// rendering normal.
#include <shapespline/cli/common.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/sample_list.h>
#include <shapespline/sampling/session.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <tuple>

namespace shapespline::cli {
namespace {

struct EvalArgs {
  std::string model, at, device = "auto", precision = "double", fields;
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
      throw RuntimeError(field, number17(v[k]), beyondRangeRule(p));
  requireFinite(v, field);
}

// A global parameter is derived from the knots, not evaluated: checked like every number written.
double finiteParameter(double v, const char* field) {
  if (!std::isfinite(v)) throw RuntimeError(field, number17(v), "the global parameter is not finite; nothing was written");
  return v;
}

// Points of a CPU-path query outside the model's range name the sample (parse checks first, so
// this is a last line of defence).
template <class Result, class Run>
Result evaluated(const json& at, Run&& run) {
  try {
    return run();
  } catch (const sampling::QueryRangeError& e) {
    throw InputError("samples[" + std::to_string(e.index()) + "]", io::shortValue(at.at("samples")[e.index()]),
                     std::string("outside the model's parameter range: ") + e.what());
  }
}

std::string evalCurve(sampling::Session& session, const Curve& curve, const json& at,
                      const sampling::DeviceRequest& request, FieldMask fields) {
  const Precision p = request.precision;
  const int dim = curve.dimension();
  const std::vector<io::CurveSample> queries = io::parseCurveSamples(at, curve, "--at");
  std::vector<sampling::CurveQuery> list;
  list.reserve(queries.size());
  for (const auto& q : queries) list.push_back({q.global, q.span, q.t, q.u});
  std::vector<CurvePoint> points;
  // The list kernel when the fields allow (core/list_eval.h, the same bits); every field otherwise.
  if (const auto lean = listFieldsFor(fields, false)) {
    auto result =
        evaluated<sampling::ListResult<CurveFirst>>(at, [&] { return session.evaluate(curve, request, list, *lean); });
    points.reserve(result.points.size());
    for (const CurveFirst& f : result.points) points.push_back(pointOf(f));
  } else {
    points = evaluated<sampling::ListResult<CurvePoint>>(at, [&] { return session.evaluate(curve, request, list); }).points;
  }
  auto wanted = [&](Field f) { return (fields & fieldBit(f)) != 0; };
  std::string out = "{\"samples\": [";
  if (nanFaultInjected() && !points.empty()) points[0].point.x = std::nan("");
  for (size_t i = 0; i < queries.size(); ++i) {
    const auto& q = queries[i];
    const CurvePoint& cp = points[i];
    // Checked after rounding: an fp64 value beyond 3.4e38 becomes inf in fp32.
    requireInRange(rounded(cp.point, p), "point", p);
    if (wanted(Field::D1)) requireInRange(rounded(cp.d1, p), "d1", p);
    if (wanted(Field::D2)) requireInRange(rounded(cp.d2, p), "d2", p);
    const std::string head = q.global ? "\"u\": " + numberText(q.u, Precision::Double)
                                      : "\"span\": " + std::to_string(q.span) + ", \"t\": " + numberText(q.t, Precision::Double) +
                                            ", \"u\": " + numberText(finiteParameter(curve.parameterOf(q.span, q.t), "u"), Precision::Double);
    out += std::string(i ? ",\n  " : "\n  ") + "{" + head + ", \"point\": " + vectorText(cp.point, dim, p) +
           (wanted(Field::D1) ? ", \"d1\": " + vectorText(cp.d1, dim, p) : std::string()) +
           (wanted(Field::D2) ? ", \"d2\": " + vectorText(cp.d2, dim, p) : std::string()) + "}";
  }
  return out + "\n]}\n";
}

std::string evalSurface(sampling::Session& session, const Surface& surface, const json& at,
                        const sampling::DeviceRequest& request, FieldMask fields) {
  const Precision p = request.precision;
  std::vector<std::array<double, 4>> queries;
  std::vector<sampling::SurfaceQuery> list;
  for (const io::SurfaceSample& q : io::parseSurfaceSamples(at, surface, "--at")) {
    queries.push_back({static_cast<double>(q.patchU), static_cast<double>(q.patchV), q.u, q.v});
    list.push_back({false, q.patchU, q.patchV, q.u, q.v});
  }
  std::vector<SurfacePoint> points;
  if (const auto lean = listFieldsFor(fields, true)) {
    auto result = evaluated<sampling::ListResult<SurfaceFirst>>(
        at, [&] { return session.evaluate(surface, request, list, *lean); });
    points.reserve(result.points.size());
    for (const SurfaceFirst& f : result.points) points.push_back(pointOf(f));
  } else {
    points = evaluated<sampling::ListResult<SurfacePoint>>(at, [&] { return session.evaluate(surface, request, list); }).points;
  }
  auto wanted = [&](Field f) { return (fields & fieldBit(f)) != 0; };
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
    const std::tuple<Field, const char*, const glm::dvec3*> values[] = {
        {Field::Point, "point", &sp.point}, {Field::Du, "du", &sp.du},     {Field::Dv, "dv", &sp.dv},
        {Field::Duu, "duu", &sp.duu},       {Field::Duv, "duv", &sp.duv}, {Field::Dvv, "dvv", &sp.dvv},
        {Field::Normal, "normal", &sp.normal}};
    std::string written;
    for (const auto& [field, name, x] : values) {
      if (!wanted(field)) continue;
      requireInRange(rounded(*x, p), name, p);
      if (field != Field::Normal) written += std::string(", \"") + name + "\": " + vectorText(*x, 3, p);
    }
    // du and dv scaled by powers of two (exact) first, so that cross and lengths neither overflow
    // for huge nets nor underflow for tiny ones; the normal and the sine test are scale-free.
    const glm::dvec3 du = unitScaled(sp.du), dv = unitScaled(sp.dv);
    const glm::dvec3 cross = glm::cross(du, dv);
    const double denom = glm::length(du) * glm::length(dv);
    const bool defined = denom > 0.0 && glm::length(cross) >= 0.01 * denom;
    const std::string normal = defined ? vectorText(glm::normalize(cross), 3, p) : "null";
    out += std::string(i ? ",\n  " : "\n  ") + "{\"patch\": [" + std::to_string(pi) + ", " + std::to_string(pj) +
           "], \"uv\": [" + numberText(u, Precision::Double) + ", " + numberText(v, Precision::Double) + "], \"UV\": [" + numberText(finiteParameter(global(pi, u, m.knotsU), "UV"), Precision::Double) +
           ", " + numberText(finiteParameter(global(pj, v, m.knotsV), "UV"), Precision::Double) + "]" + written +
           (wanted(Field::Normal) ? ", \"normal\": " + normal +
                                        (defined ? std::string() : ", \"render_normal\": " + vectorText(sp.normal, 3, p))
                                  : std::string()) +
           "}";
  }
  return out + "\n]}\n";
}

void runEval(const EvalArgs& args) {
  const sampling::DeviceRequest request = parseDeviceRequest(args.device, args.precision, args.requireDevice);
  io::Model model = loadModel(args.model);
  const json at = readJsonFile(args.at, "--at");
  std::visit([&](const auto& m) { requireFloatRange(m.points, request.precision); }, model);
  sampling::Session session;
  std::string text;
  if (std::holds_alternative<CurveModel>(model)) {
    const Curve curve = Curve::create(std::get<CurveModel>(std::move(model)));
    const sampling::Report plan = session.plan(curve, request);
    printNotices(plan, args.quiet);
    printPrecisionWarnings(curve.model(), plan.gpu && plan.computedPrecision == Precision::Float, args.quiet);
    text = evalCurve(session, curve, at, request,
                     args.fields.empty() ? kCurveFields : parseFields(args.fields, false, false));
  } else {
    const Surface surface = Surface::create(std::get<SurfaceModel>(std::move(model)));
    const sampling::Report plan = session.plan(surface, request);
    printNotices(plan, args.quiet);
    printPrecisionWarnings(surface, plan.gpu && plan.computedPrecision == Precision::Float, args.quiet);
    text = evalSurface(session, surface, at, request,
                       args.fields.empty() ? kSurfaceFields : parseFields(args.fields, true, false));
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
  sub->add_option("--device", args->device,
                  "auto (default) or vulkan: the GPU, falling back to the CPU with a notice; cpu: the CPU fp64 path");
  sub->add_option("--precision", args->precision, "float or double (default double)");
  sub->add_flag("--require-device", args->requireDevice,
                "with --device auto or vulkan: fail (exit 3) instead of falling back to the CPU");
  sub->add_option("--fields", args->fields,
                  "the fields to print, comma-separated (default: all): point, du, dv, duu, duv, dvv, normal "
                  "(surfaces), point, d1, d2 (curves); the point is always printed. The point and first "
                  "derivatives alone run the lean list kernel");
  addQuietFlag(sub, args->quiet, "no notices and no warnings");
  sub->footer(kExitCodeHelp);
  sub->callback([args] { runEval(*args); });
}

}  // namespace shapespline::cli
