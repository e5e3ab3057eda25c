// `shapespline basis --family F ...`: CSV table of a span basis B_0..B_{m-1} and its first two
// derivatives on t in [0,1] (or the singular blend S), optionally plotted as SVG (three panels).
#include <shapespline/cli/common.h>
#include <shapespline/core/singular_blend.h>
#include <shapespline/core/span_basis.h>
#include <shapespline/core/validate.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/number_text.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/svg_writer.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

namespace shapespline::cli {
namespace {

struct BasisArgs {
  std::string family, mu, out, svg;
  int degree = 0, order = 0, samples = 101;
  double lambda = 0.0;
  GivenOptions given;
  bool quiet = false;
};

struct Table {
  std::vector<std::string> names;             // column names after t
  std::vector<double> t;
  std::vector<std::vector<double>> v, d1, d2;  // [function][sample]
};

Table tabulate(const BasisArgs& a) {
  if (a.samples < 2 || a.samples > 1'000'000) {
    throw InputError("--samples", std::to_string(a.samples), "must be in [2, 1000000]");
  }
  // Each family's parameters; the others are refused, not ignored.
  const std::map<std::string, std::vector<std::string>> takes = {
      {"singular_blend", {}},           {"blend", {}},         {"xuwang", {"--degree", "--lambda"}},
      {"extended_bspline", {"--degree", "--lambda"}}, {"gb", {"--lambda"}}, {"ubp", {"--order", "--lambda"}},
      {"gubp", {"--order", "--mu"}},    {"bspline", {"--order"}}};
  if (const auto it = takes.find(a.family); it != takes.end()) {
    for (const char* o : {"--degree", "--order", "--lambda", "--mu"}) {
      if (std::find(it->second.begin(), it->second.end(), o) == it->second.end())
        refuseOption(a.given, o, "--family " + a.family);
    }
  }
  Table tab;
  for (int i = 0; i < a.samples; ++i) tab.t.push_back(static_cast<double>(i) / (a.samples - 1));
  if (a.family == "singular_blend" || a.family == "blend") {
    tab.names = {"S"};
    tab.v.assign(1, {});
    tab.d1.assign(1, {});
    tab.d2.assign(1, {});
    for (double t : tab.t) {
      const BlendValue b = singularBlend(t);
      tab.v[0].push_back(b.s);
      tab.d1[0].push_back(b.d1);
      tab.d2[0].push_back(b.d2);
    }
    return tab;
  }
  FamilySpec f;
  f.lambda = a.lambda;
  if (a.family == "xuwang" || a.family == "extended_bspline") {
    f.construction = Construction::ExtendedBSpline;
    f.degree = a.degree;
    if (a.degree == 0) throw InputError("--degree", "", "required for " + a.family + " (4, 5 or 6)");
  } else if (a.family == "gb") {
    f.construction = Construction::GB;
  } else if (a.family == "ubp") {
    f.construction = Construction::UBP;
    f.order = a.order;
  } else if (a.family == "gubp") {
    f.construction = Construction::GUBP;
    f.order = a.order;
    if (a.mu.empty()) throw InputError("--mu", "", "required for gubp: mu_0..mu_{floor(k/2)}");
    f.mu = parseNumbers(a.mu, "--mu");
  } else if (a.family == "bspline") {
    f.construction = Construction::BSpline;
    f.order = a.order;
  } else {
    throw InputError("--family", a.family, "expected xuwang, gb, ubp, gubp, bspline or singular_blend");
  }
  if ((f.construction == Construction::UBP || f.construction == Construction::GUBP ||
       f.construction == Construction::BSpline) && a.order == 0) {
    throw InputError("--order", "", "required for " + a.family);
  }
  try {
    if (f.construction == Construction::UBP && a.order == 2) {
      if (!(a.lambda >= ubpLambdaMin(2) && a.lambda <= 1.0)) throw ModelError("lambda", std::to_string(a.lambda), "out of range");
    } else {
      validateFamily(f);
    }
  } catch (const ModelError& e) {
    throw InputError("--" + e.field(), e.value(), e.rule());
  }
  const SpanBasis basis = f.construction == Construction::UBP ? ubpSpanBasis(f.order, f.lambda) : makeSpanBasis(f);
  tab.v.assign(static_cast<size_t>(basis.count), {});
  tab.d1 = tab.v;
  tab.d2 = tab.v;
  for (int r = 0; r < basis.count; ++r) tab.names.push_back("B" + std::to_string(r));
  for (double t : tab.t) {
    double b[kMaxBasisCount], d1[kMaxBasisCount], d2[kMaxBasisCount];
    evalSpanBasis(basis, t, b, d1, d2);
    for (int r = 0; r < basis.count; ++r) {
      tab.v[static_cast<size_t>(r)].push_back(b[r]);
      tab.d1[static_cast<size_t>(r)].push_back(d1[r]);
      tab.d2[static_cast<size_t>(r)].push_back(d2[r]);
    }
  }
  return tab;
}

std::string csv(const Table& tab) {
  std::string s = "t";
  for (const auto& n : tab.names) s += "," + n;
  for (const auto& n : tab.names) s += ",d1_" + n;
  for (const auto& n : tab.names) s += ",d2_" + n;
  s += "\n";
  char buf[io::kMaxNumberChars];
  // Every number written is checked (a basis of a validated family is finite; this is the guard).
  auto put = [&](double v, size_t column, size_t row) {
    if (!std::isfinite(v)) {
      const size_t n = tab.names.size(), r = (column - 1) % n;
      const std::string name = column == 0 ? "t" : column <= n ? tab.names[r] : (column <= 2 * n ? "d1_" : "d2_") + tab.names[r];
      throw RuntimeError(name, number17(v) + " at row " + std::to_string(row),
                         "the basis table value is not finite; nothing was written");
    }
    s.append(buf, io::writeNumber17(buf, v));
  };
  for (size_t i = 0; i < tab.t.size(); ++i) {
    size_t column = 0;
    put(tab.t[i], column++, i);
    for (const auto* block : {&tab.v, &tab.d1, &tab.d2}) {
      for (const auto& c : *block) {
        s += ',';
        put(c[i], column++, i);
      }
    }
    s += "\n";
  }
  return s;
}

std::string svg(const Table& tab, const std::string& title) {
  const int w = 800, h = 420;
  std::string s = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                  std::to_string(w) + "\" height=\"" + std::to_string(3 * h) + "\">\n";
  const char* panel[3] = {"", "first derivative", "second derivative"};
  const std::vector<std::vector<double>>* data[3] = {&tab.v, &tab.d1, &tab.d2};
  for (int k = 0; k < 3; ++k) {
    io::SvgPlot plot(false, k == 0 ? title : title + ": " + panel[k]);
    plot.setAxes(true);
    for (size_t r = 0; r < tab.names.size(); ++r) {
      io::SvgPolyline line;
      line.color = io::paletteColor(static_cast<int>(r));
      line.label = (k == 0 ? "" : k == 1 ? "d1 " : "d2 ") + tab.names[r];
      for (size_t i = 0; i < tab.t.size(); ++i) line.points.emplace_back(tab.t[i], (*data[k])[r][i]);
      plot.add(std::move(line));
    }
    std::string body;
    try {
      body = plot.render(w, h);
    } catch (const io::SvgValueError& e) {
      throw RuntimeError("--svg", "", e.what());
    }
    body.erase(0, body.find("<svg"));  // drop the XML declaration of the nested document
    s += "<g transform=\"translate(0," + std::to_string(k * h) + ")\">\n" + body + "</g>\n";
  }
  return s + "</svg>\n";
}

void runBasis(const BasisArgs& a) {
  const Table tab = tabulate(a);
  std::string title = a.family;
  if (a.degree) title += " degree " + std::to_string(a.degree);
  if (a.order) title += " order " + std::to_string(a.order);
  if (a.family != "bspline" && a.family != "gubp" && a.family != "singular_blend") title += " lambda " + number17(a.lambda);
  if (!a.mu.empty()) title += " mu " + a.mu;
  // One set: the table and the plot appear together or not at all; the same path twice is refused.
  io::OutputSet outputs;
  io::AtomicFile* out = a.out.empty() ? nullptr : &outputs.add(a.out, "-o");
  io::AtomicFile* plot = a.svg.empty() ? nullptr : &outputs.add(a.svg, "--svg");
  const std::string table = csv(tab);
  if (out) {
    out->write(table);
  } else {
    io::writeStdout(table);
  }
  if (plot) plot->write(svg(tab, title));
  io::flushStdout();  // stdout failed: exit 3 and no file
  outputs.commit();
}

}  // namespace

void registerBasis(CLI::App& app) {
  auto a = std::make_shared<BasisArgs>();
  CLI::App* sub = app.add_subcommand("basis", "Tabulate a span basis and its derivatives (CSV), optionally plot it (SVG).");
  sub->add_option("--family", a->family, "xuwang (= extended_bspline), gb, ubp, gubp, bspline, singular_blend")->required();
  sub->add_option("--degree", a->degree, "Xu-Wang degree 4..6");
  sub->add_option("--order,-k", a->order, "order of ubp (2..10), gubp (3..10), bspline (2..10)");
  sub->add_option("--lambda", a->lambda, "shape parameter (default 0)");
  sub->add_option("--mu", a->mu, "gubp: mu_0,...,mu_floor(k/2)");
  sub->add_option("--samples", a->samples, "rows, t = i/(N-1) (default 101)");
  sub->add_option("-o,--output", a->out, "CSV file (default: stdout)");
  sub->add_option("--svg", a->svg, "SVG plot of the functions and their derivatives");
  addQuietFlag(sub, a->quiet, "accepted for uniformity: basis prints its table and no notices");
  sub->footer(kExitCodeHelp);
  sub->callback([a, sub] {
    a->given = givenOptions(*sub);
    runBasis(*a);
  });
}

}  // namespace shapespline::cli
