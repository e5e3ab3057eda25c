// `shapespline extend MODEL --to X,Y[,Z] ... -o OUT`: extension of a right-clamped knot-vector
// B-spline curve to target points (docs/math.md §10.5); surfaces take `--to-curve FILE` target curves
// (§10.6). --u gives explicit parameters instead of chord length. Writes the extended model.
#include <shapespline/cli/common.h>
#include <shapespline/core/extension.h>
#include <shapespline/core/validate.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/output_set.h>

#include <cstdio>
#include <memory>

namespace shapespline::cli {
namespace {

struct ExtendArgs {
  std::string model, out, u, svg;
  std::vector<std::string> to, toCurve;
  bool quiet = false;
};

std::vector<glm::dvec3> readTargetCurve(const std::string& path, size_t index) {
  const std::string field = "--to-curve[" + std::to_string(index) + "]";
  nlohmann::json j = readJsonFile(path, field);
  if (j.is_object() && j.contains("points")) j = j["points"];
  if (!j.is_array() || j.empty()) throw InputError(field, io::shortValue(j), "expected a list of [x, y, z] control points");
  std::vector<glm::dvec3> pts;
  for (size_t i = 0; i < j.size(); ++i) {
    const auto& p = j[i];
    if (!p.is_array() || p.size() != 3) throw InputError(field + ".points[" + std::to_string(i) + "]", io::shortValue(p), "must be [x, y, z]");
    glm::dvec3 v;
    for (int k = 0; k < 3; ++k) {
      if (!p[static_cast<size_t>(k)].is_number() || !std::isfinite(p[static_cast<size_t>(k)].get<double>())) {
        throw InputError(field + ".points[" + std::to_string(i) + "]", io::shortValue(p), "must hold finite numbers");
      }
      v[k] = p[static_cast<size_t>(k)].get<double>();
    }
    pts.push_back(v);
  }
  return pts;
}

void runExtend(const ExtendArgs& a) {
  io::Model m = loadModel(a.model);
  std::optional<std::vector<double>> givenU;
  if (!a.u.empty()) givenU = parseNumbers(a.u, "--u");
  io::OutputSet outputs;  // the model and the plot appear together or not at all
  outputs.reads(a.model, "MODEL");
  for (size_t i = 0; i < a.toCurve.size(); ++i) outputs.reads(a.toCurve[i], "--to-curve[" + std::to_string(i) + "]");
  io::AtomicFile& out = outputs.add(a.out, "-o");
  io::AtomicFile* svg = nullptr;
  if (std::holds_alternative<CurveModel>(m)) {
    const CurveModel& cm = std::get<CurveModel>(m);
    if (a.to.empty()) throw InputError("--to", "", "at least one target X,Y[,Z] is required for a curve");
    if (!a.toCurve.empty()) throw InputError("--to-curve", "", "target curves extend surfaces; use --to for a curve");
    if (cm.family.construction != Construction::BSpline || cm.knots.empty()) {
      throw InputError("MODEL", a.model, "extend needs a 'bspline' curve with a knot vector");
    }
    std::vector<glm::dvec3> targets;
    int dim = cm.dimension;
    for (size_t i = 0; i < a.to.size(); ++i) {
      int d = 2;
      targets.push_back(parsePoint(a.to[i], "--to[" + std::to_string(i) + "]", &d));
      if (d != cm.dimension) {
        throw InputError("--to[" + std::to_string(i) + "]", a.to[i],
                         "must have " + std::to_string(cm.dimension) + " coordinates like the model's points");
      }
    }
    if (givenU && givenU->size() != targets.size()) {
      throw InputError("--u", a.u, "needs one parameter per --to target (" + std::to_string(targets.size()) + ")");
    }
    if (!a.svg.empty()) svg = &outputs.add(a.svg, "--svg");
    const ExtensionResult r = extendCurve(bsplineCurveFromModel(cm), targets, givenU);
    CurveModel ext = extendedModel(cm, r);
    ext.dimension = dim;
    validateCurve(ext);
    out.write(io::toJson(ext).dump(2) + "\n");
    if (!a.quiet) {
      std::printf("extended %zu -> %zu points; target parameters:", cm.points.size(), ext.points.size());
      for (double u : r.u) std::printf(" %s", number17(u).c_str());
      std::printf("\n");
    }
    if (svg) svg->write(curveSvg(Curve::create(ext), targets, "extended B-spline curve"));
  } else {
    const SurfaceModel& sm = std::get<SurfaceModel>(m);
    if (a.toCurve.empty()) throw InputError("--to-curve", "", "at least one target curve file is required for a surface");
    if (!a.to.empty()) throw InputError("--to", "", "a surface is extended with --to-curve FILE");
    if (!a.svg.empty()) throw InputError("--svg", a.svg, "does not apply to surfaces (it plots an extended curve)");
    if (sm.family.construction != Construction::BSpline || sm.knotsU.empty()) {
      throw InputError("MODEL", a.model, "extend needs a 'bspline' surface with knot vectors");
    }
    std::vector<std::vector<glm::dvec3>> curves;
    for (size_t i = 0; i < a.toCurve.size(); ++i) {
      curves.push_back(readTargetCurve(a.toCurve[i], i));
      if (curves.back().size() != static_cast<size_t>(sm.cols)) {
        throw InputError("--to-curve[" + std::to_string(i) + "]", a.toCurve[i],
                         "needs " + std::to_string(sm.cols) + " control points (one per column of the surface)");
      }
    }
    if (givenU && givenU->size() != curves.size()) {
      throw InputError("--u", a.u, "needs one parameter per --to-curve (" + std::to_string(curves.size()) + ")");
    }
    const SurfaceExtensionResult r = extendSurfaceU(bsplineSurfaceFromModel(sm), curves, givenU);
    const SurfaceModel ext = extendedModel(sm, r);
    validateSurface(ext);
    out.write(io::toJson(ext).dump(2) + "\n");
    if (!a.quiet) {
      std::printf("extended %d -> %d rows; target parameters:", sm.rows, ext.rows);
      for (double u : r.u) std::printf(" %s", number17(u).c_str());
      std::printf("\n");
    }
  }
  io::flushStdout();  // stdout failed: exit 3 and no file
  outputs.commit();
}

}  // namespace

void registerExtend(CLI::App& app) {
  auto a = std::make_shared<ExtendArgs>();
  CLI::App* sub = app.add_subcommand("extend", "Extend a clamped B-spline curve to target points (or a B-spline surface to target curves).");
  sub->add_option("MODEL", a->model, "a 'bspline' model with knots, right-clamped")->required();
  sub->add_option("--to", a->to, "target point X,Y[,Z] (repeatable, in order)");
  sub->add_option("--to-curve", a->toCurve, "surfaces: JSON file with a target curve's control points (repeatable)");
  sub->add_option("--u", a->u, "explicit target parameters u1,...,um (default: chord length)");
  sub->add_option("-o,--output", a->out, "extended model file")->required();
  sub->add_option("--svg", a->svg, "curves: plot the extended curve with its control polygon and the targets");
  addQuietFlag(sub, a->quiet, "no summary line (the extended model is the output)");
  sub->footer(kExitCodeHelp);
  sub->callback([a] { runExtend(*a); });
}

}  // namespace shapespline::cli
