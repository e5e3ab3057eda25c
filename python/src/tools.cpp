// Basis tables (as `shapespline basis`), GB λ-paths and constrained modification (as `gb-fit`),
// B-spline unclamping and extension (as `extend`), bound as module functions and methods.
#include "convert.h"
#include "handle.h"

#include <shapespline/core/bspline.h>
#include <shapespline/core/extension.h>
#include <shapespline/core/gb_tools.h>
#include <shapespline/core/singular_blend.h>
#include <shapespline/core/span_basis.h>
#include <shapespline/core/validate.h>

#include <pybind11/stl.h>

#include <cmath>

namespace shapespline::python {
namespace {

// The family of a basis query, named as `shapespline basis --family` names it (cmd_basis.cpp).
FamilySpec basisFamily(const std::string& family, int degree, int order, double lambda, py::object mu) {
  FamilySpec f;
  f.lambda = lambda;
  if (family == "xuwang" || family == "extended_bspline") {
    f.construction = Construction::ExtendedBSpline;
    f.degree = degree;
    if (degree == 0) throw ModelError("degree", "", "required for " + family + " (4, 5 or 6)");
  } else if (family == "gb") {
    f.construction = Construction::GB;
  } else if (family == "ubp") {
    f.construction = Construction::UBP;
    f.order = order;
  } else if (family == "gubp") {
    f.construction = Construction::GUBP;
    f.order = order;
    if (mu.is_none()) throw ModelError("mu", "", "required for gubp: mu_0..mu_floor(k/2)");
    f.mu = doubles(mu, "mu");
  } else if (family == "bspline") {
    f.construction = Construction::BSpline;
    f.order = order;
  } else {
    argumentError("family", "expected xuwang, gb, ubp, gubp, bspline or singular_blend", "'" + family + "'");
  }
  const bool ordered = f.construction == Construction::UBP || f.construction == Construction::GUBP ||
                       f.construction == Construction::BSpline;
  if (ordered && order == 0) throw ModelError("order", "", "required for " + family);
  if (f.construction == Construction::UBP && order == 2) {
    // Order 2 is the UBP seed: a basis query only (not a curve basis).
    if (!(lambda >= ubpLambdaMin(2) && lambda <= 1.0)) throw ModelError("lambda", std::to_string(lambda), "out of range");
  } else {
    validateFamily(f);
  }
  return f;
}

SpanBasis basisOf(const FamilySpec& f) {
  return f.construction == Construction::UBP ? ubpSpanBasis(f.order, f.lambda) : makeSpanBasis(f);
}

py::array table(std::vector<double>&& v, size_t rows, size_t cols) {
  return owned(std::move(v), {py::ssize_t(rows), py::ssize_t(cols)});
}

py::dict basisTable(const std::string& family, py::object t, int degree, int order, double lambda, py::object mu) {
  const std::vector<double> ts = doubles(t, "t");
  py::dict out;
  if (family == "singular_blend" || family == "blend") {
    std::vector<double> s(ts.size()), d1(ts.size()), d2(ts.size());
    for (size_t i = 0; i < ts.size(); ++i) {
      const BlendValue b = singularBlend(ts[i]);
      s[i] = b.s, d1[i] = b.d1, d2[i] = b.d2;
    }
    out["values"] = table(std::move(s), ts.size(), 1);
    out["d1"] = table(std::move(d1), ts.size(), 1);
    out["d2"] = table(std::move(d2), ts.size(), 1);
    return out;
  }
  const SpanBasis basis = basisOf(basisFamily(family, degree, order, lambda, mu));
  const auto m = size_t(basis.count);
  std::vector<double> v(ts.size() * m), d1(ts.size() * m), d2(ts.size() * m);
  for (size_t i = 0; i < ts.size(); ++i) evalSpanBasis(basis, ts[i], &v[i * m], &d1[i * m], &d2[i * m]);
  out["values"] = table(std::move(v), ts.size(), m);
  out["d1"] = table(std::move(d1), ts.size(), m);
  out["d2"] = table(std::move(d2), ts.size(), m);
  return out;
}

py::dict bellFunction(const std::string& family, py::object x, int degree, int order, double lambda, py::object mu) {
  const std::vector<double> xs = doubles(x, "x");
  const SpanBasis basis = basisOf(basisFamily(family, degree, order, lambda, mu));
  std::vector<double> n(xs.size()), dn(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) evalBell(basis, xs[i], &n[i], &dn[i]);
  py::dict out;
  out["N"] = owned(std::move(n), {py::ssize_t(xs.size())});
  out["dN"] = owned(std::move(dn), {py::ssize_t(xs.size())});
  return out;
}

py::array vec1(std::vector<double> v) {
  const auto n = static_cast<py::ssize_t>(v.size());
  return owned(std::move(v), {n});
}

py::array rows(const std::vector<glm::dvec3>& pts, int dims) {
  std::vector<double> v;
  for (const auto& p : pts)
    for (int c = 0; c < dims; ++c) v.push_back(p[c]);
  return owned(std::move(v), {py::ssize_t(pts.size()), py::ssize_t(dims)});
}

CurveModel gbModel(const CurveHandle& h) {
  const CurveModel m = h.model()->model();
  if (m.family.construction != Construction::GB) throw ModelError("construction", "", "GB tools need a 'gb' curve");
  return m;
}

py::dict solution(const GbSolution& s) {
  py::dict d;
  d["t0"] = s.t0;
  d["lambda0"] = s.lambda0;
  d["w"] = s.w;
  return d;
}

std::optional<std::vector<double>> givenU(py::object u, const char* name) {
  if (u.is_none()) return std::nullopt;
  return doubles(u, name);
}

}  // namespace

void bindTools(py::module_& m, py::class_<CurveHandle, std::shared_ptr<CurveHandle>>& curve,
               py::class_<SurfaceHandle, std::shared_ptr<SurfaceHandle>>& surface) {
  m.def("basis", &basisTable, py::arg("family"), py::arg("t"), py::kw_only(), py::arg("degree") = 0,
        py::arg("order") = 0, py::arg("lambda_") = 0.0, py::arg("mu") = py::none(),
        "Span basis B_0..B_{m-1} of a family at t: dict values, d1, d2 of shape (len(t), m). family: xuwang "
        "(= extended_bspline, with degree), gb, ubp (order 2..10), gubp (order, mu), bspline (order), singular_blend (m = 1).");
  m.def("bell", &bellFunction, py::arg("family"), py::arg("x"), py::kw_only(), py::arg("degree") = 0,
        py::arg("order") = 0, py::arg("lambda_") = 0.0, py::arg("mu") = py::none(),
        "The bell function N(x) on [0, m] assembled from the span basis pieces: dict N, dN of shape (len(x),).");
  m.def(
      "ubp_doubled_knot_coefficients",
      [](int order, double lambda) {
        if (order < 2 || order > 10) throw ModelError("order", std::to_string(order), "must be in 2..10");
        if (!(lambda >= ubpLambdaMin(order) && lambda <= 1.0)) {
          throw ModelError("lambda", std::to_string(lambda), "out of the UBP range of this order");
        }
        return vec1(ubpDoubledKnotCoefficients(order, lambda));
      },
      py::arg("order"), py::arg("lambda_"), "Theorem-1 coefficients lambda_{0,k}..lambda_{k,k} of UBP order k.");

  curve.def(
      "gb_lambda_path",
      [](const CurveHandle& h, int span, py::object t) {
        const CurveModel cm = gbModel(h);
        const std::vector<double> ts = doubles(t, "t");
        std::vector<double> c0, e, c8;
        for (double x : ts) {
          const GbLambdaPath p = gbLambdaPath(cm, span, x);
          c0.insert(c0.end(), {p.c0.x, p.c0.y});
          e.insert(e.end(), {p.e.x, p.e.y});
          c8.insert(c8.end(), {p.cMinus8.x, p.cMinus8.y});
        }
        py::dict d;
        const auto n = py::ssize_t(ts.size());
        d["c0"] = owned(std::move(c0), {n, 2});
        d["e"] = owned(std::move(e), {n, 2});
        d["c_minus8"] = owned(std::move(c8), {n, 2});
        return d;
      },
      py::arg("span"), py::arg("t"),
      "Straight lambda-paths of a 2-D gb curve's span at local t: dict c0 (lambda = 0), e (lambda -> inf), "
      "c_minus8 (lambda = -8), each (len(t), 2); C(lambda, t) = w c0 + (1 - w) e, w = 12/(12 + lambda).");
  curve.def(
      "gb_span_points",
      [](const CurveHandle& h, int span, double lambda, py::object t) {
        const CurveModel cm = gbModel(h);
        const std::vector<double> ts = doubles(t, "t");
        std::vector<double> v;
        for (double x : ts) {
          const glm::dvec2 p = gbSpanPoint(cm, span, lambda, x);
          v.insert(v.end(), {p.x, p.y});
        }
        return owned(std::move(v), {py::ssize_t(ts.size()), 2});
      },
      py::arg("span"), py::arg("lambda_"), py::arg("t"), "C_span(lambda, t) of a 2-D gb curve, (len(t), 2).");
  curve.def(
      "gb_constrained_modify",
      [](const CurveHandle& h, int span, py::object target) {
        const CurveModel cm = gbModel(h);
        const glm::dvec3 x = onePoint(target, "target", 2);
        GbFitResult r;
        {
          py::gil_scoped_release release;
          r = gbConstrainedModify(cm, span, {x.x, x.y});
        }
        py::dict d;
        d["reachable"] = r.reachable;
        d["reason"] = r.reason;
        py::list all;
        for (const auto& s : r.all) all.append(solution(s));
        d["all_solutions"] = all;
        if (r.reachable) {
          d["t0"] = r.bisection.t0;
          d["lambda0"] = r.bisection.lambda0;
          d["w"] = r.bisection.w;
          CurveModel next = cm;
          next.family.lambda = r.bisection.lambda0;
          d["curve"] = std::make_shared<CurveHandle>(Curve::create(next));
        } else {
          for (const char* k : {"t0", "lambda0", "w", "curve"}) d[k] = py::none();
        }
        return d;
      },
      py::arg("span"), py::arg("target"),
      "GB constrained modification (docs/math.md 7.2): the lambda0 that makes span `span` pass through the 2-D "
      "target. dict reachable, reason, t0, lambda0, w, all_solutions (list of dicts) and curve (the modified Curve, "
      "or None when unreachable).");
  curve.def(
      "unclamp_right",
      [](const CurveHandle& h, py::object newKnots) {
        const auto held = h.model();
        const Curve& c = *held;
        if (!c.usesKnotVector()) throw ModelError("knots", "", "unclamping needs a 'bspline' curve with a knot vector");
        const BSplineCurveData un = unclampRight(bsplineCurveFromModel(c.model()), doubles(newKnots, "new_knots"));
        py::dict d;
        d["points"] = rows(un.points, c.dimension());
        d["knots"] = vec1(un.knots);
        return d;
      },
      py::arg("new_knots"),
      "Algorithm U (docs/math.md 10.2): the right-clamped curve rewritten on new right knots t_{n+2}..t_{n+k}: "
      "dict points, knots.");
  curve.def(
      "extend",
      [](const CurveHandle& h, py::object targets, py::object u) {
        const auto held = h.model();
        const Curve& c = *held;
        if (!c.usesKnotVector()) throw ModelError("knots", "", "extend needs a 'bspline' curve with a knot vector");
        int dims = 0;
        const std::vector<glm::dvec3> pts = pointRows(targets, "targets", &dims);
        if (dims != c.dimension()) {
          argumentError("targets", "must have " + std::to_string(c.dimension()) + " coordinates like the curve's points");
        }
        const auto given = givenU(u, "u");
        if (given && given->size() != pts.size()) argumentError("u", "needs one parameter per target");
        ExtensionResult r;
        {
          py::gil_scoped_release release;
          r = extendCurve(bsplineCurveFromModel(c.model()), pts, given);
        }
        const CurveModel ext = extendedModel(c.model(), r);
        py::dict d;
        d["curve"] = std::make_shared<CurveHandle>(Curve::create(ext));
        d["u"] = vec1(r.u);
        d["unclamp_knots"] = vec1(r.unclampKnots);
        d["unclamped_points"] = rows(r.unclampedPoints, c.dimension());
        d["knots_normalized"] = vec1(r.knotsNormalized);
        return d;
      },
      py::arg("targets"), py::arg("u") = py::none(),
      "Extend a right-clamped B-spline curve to target points (docs/math.md 10.5; chord-length parameters unless u "
      "is given): dict curve (the extended Curve), u, unclamp_knots, unclamped_points, knots_normalized.");

  surface.def(
      "extend_u",
      [](const SurfaceHandle& h, py::object targetCurves, py::object u) {
        const auto held = h.model();
        const Surface& s = *held;
        if (!s.usesKnotVector()) throw ModelError("knots", "", "extend_u needs a 'bspline' surface with knot vectors");
        std::vector<std::vector<glm::dvec3>> curves;
        size_t i = 0;
        for (auto c : py::reinterpret_borrow<py::iterable>(targetCurves)) {
          const std::string name = "target_curves[" + std::to_string(i++) + "]";
          curves.push_back(pointRows(c, name));
          if (curves.back().size() != size_t(s.model().cols)) {
            argumentError(name, "needs " + std::to_string(s.model().cols) + " control points (one per column)");
          }
        }
        if (curves.empty()) argumentError("target_curves", "at least one target curve is required");
        const auto given = givenU(u, "u");
        if (given && given->size() != curves.size()) argumentError("u", "needs one parameter per target curve");
        SurfaceExtensionResult r;
        {
          py::gil_scoped_release release;
          r = extendSurfaceU(bsplineSurfaceFromModel(s.toModel()), curves, given);
        }
        const SurfaceModel ext = extendedModel(s.toModel(), r);
        py::dict d;
        d["surface"] = std::make_shared<SurfaceHandle>(Surface::create(ext));
        d["u"] = vec1(r.u);
        py::list per;
        for (const auto& col : r.uPerColumn) per.append(vec1(col));
        d["u_per_column"] = per;
        d["knots_normalized_u"] = vec1(r.knotsNormalizedU);
        return d;
      },
      py::arg("target_curves"), py::arg("u") = py::none(),
      "Extend a B-spline surface in u to target curves (each `cols` control points; docs/math.md 10.6): dict "
      "surface, u, u_per_column, knots_normalized_u.");
}

}  // namespace shapespline::python
