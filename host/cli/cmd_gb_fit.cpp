// `shapespline gb-fit MODEL --span J --through X,Y`: GB constrained modification (docs/math.md §7.2).
// Prints every admissible (t0, λ0) and the bisection's answer as JSON; -o writes the model with
// λ replaced by the bisection's λ0, --svg plots the modified curve with the target point.
#include <shapespline/cli/common.h>
#include <shapespline/core/gb_tools.h>
#include <shapespline/core/validate.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/output_set.h>

#include <cstdio>
#include <memory>

namespace shapespline::cli {
namespace {

struct GbFitArgs {
  std::string model, through, out, svg;
  int span = 0;
  bool spanGiven = false;
  bool quiet = false;
};

void runGbFit(const GbFitArgs& a) {
  io::Model m = loadModel(a.model);
  if (!std::holds_alternative<CurveModel>(m) || std::get<CurveModel>(m).family.construction != Construction::GB) {
    throw InputError("MODEL", a.model, "gb-fit needs a 'gb' curve");
  }
  int dims = 2;
  const glm::dvec3 target = parsePoint(a.through, "--through", &dims);
  if (dims != 2) throw InputError("--through", a.through, "the GB modification takes a 2-D target X,Y");
  CurveModel curve = std::get<CurveModel>(m);
  if (curve.dimension != 2) throw InputError("MODEL", a.model, "gb-fit needs a 2-D curve");
  io::OutputSet outputs;  // the model and the plot appear together or not at all
  outputs.reads(a.model, "MODEL");
  io::AtomicFile* out = a.out.empty() ? nullptr : &outputs.add(a.out, "-o");
  io::AtomicFile* svg = a.svg.empty() ? nullptr : &outputs.add(a.svg, "--svg");
  GbFitResult r;
  try {
    r = gbConstrainedModify(curve, a.span, {target.x, target.y});
  } catch (const ModelError& e) {
    if (e.field() == "span") throw InputError("--span", std::to_string(a.span), e.rule());
    throw;
  }
  if (!r.reachable) throw InputError("--through", a.through, "target not reachable: " + r.reason);
  std::string s = "{\"span\": " + std::to_string(a.span) + ", \"target\": [" + number17(target.x) + ", " +
                  number17(target.y) + "],\n \"t0\": " + number17(r.bisection.t0) + ", \"lambda0\": " +
                  number17(r.bisection.lambda0) + ", \"w\": " + number17(r.bisection.w) + ",\n \"all_solutions\": [";
  for (size_t i = 0; i < r.all.size(); ++i) {
    s += std::string(i ? ",\n   " : "\n   ") + "{\"t0\": " + number17(r.all[i].t0) + ", \"lambda0\": " +
         number17(r.all[i].lambda0) + ", \"w\": " + number17(r.all[i].w) + "}";
  }
  s += "]}\n";
  curve.family.lambda = r.bisection.lambda0;
  validateCurve(curve);
  if (out) out->write(io::toJson(curve).dump(2) + "\n");
  if (svg) {
    const Curve c = Curve::create(curve);
    svg->write(curveSvg(c, {target}, "gb-fit span " + std::to_string(a.span) + ", lambda0 = " + number17(r.bisection.lambda0)));
  }
  io::writeStdout(s);
  io::flushStdout();  // stdout failed: exit 3 and no file
  outputs.commit();
}

}  // namespace

void registerGbFit(CLI::App& app) {
  auto a = std::make_shared<GbFitArgs>();
  CLI::App* sub = app.add_subcommand("gb-fit", "GB constrained modification: the lambda that makes span J pass through a point.");
  sub->add_option("MODEL", a->model, "a 2-D 'gb' curve model")->required();
  sub->add_option("--span", a->span, "span index J (open: 1..N-3, closed: 0..N-1)")->required();
  sub->add_option("--through", a->through, "target X,Y")->required();
  sub->add_option("-o,--output", a->out, "write the modified model");
  sub->add_option("--svg", a->svg, "plot the modified curve, its control polygon and the target");
  addQuietFlag(sub, a->quiet, "accepted for uniformity: gb-fit prints its result and no notices");
  sub->footer(kExitCodeHelp);
  sub->callback([a] { runGbFit(*a); });
}

}  // namespace shapespline::cli
