// Knot-vector B-splines (docs/math.md §10.1) on the GPU (bspline_curve_eval.comp,
// bspline_surface_eval.comp) against the CPU fp64 core (core/curve.h, core/surface.h): orders 2..10,
// random non-uniform knots with repeated interior knots (multiplicity up to the order, i.e. down to
// a discontinuity), clamped and unclamped ends, grids over the non-empty intervals
// (core/grid_sampler.h items), lists of (interval, t) and of global knot parameters, and the
// results of B-spline extension (core/extension.h extendCurve). fp32 and fp64.
//
// Tolerances, scale = bounding-box diagonal of the net, h = smallest non-empty knot interval,
// k = order (per direction, the larger for surfaces):
//  * point: 4 kFp64Rel / kFp32Rel * scale (de Boor–Cox values are convex weights).
//  * first derivatives: the same times 8 k / h (Σ|N'| ≤ 2(k-1)/h for the non-zero functions).
//  * second derivatives: times 64 k^2 / h^2.
//  * normals where the CPU used the regular rule and sin∠(du,dv) > 0.05: 2 (tol_du/|du| +
//    tol_dv/|dv|) / sin∠ (first-order perturbation of du×dv/|du×dv|).
// Each test prints its largest error / tolerance ratio.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <shapespline/core/curve.h>
#include <shapespline/core/extension.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/gpu/evaluator.h>
#include <shapespline/gpu/kernel_runs.h>
#include "support/test_models.h"
#include "support/tolerances.h"
#include "support/vk_fixture.h"

namespace shapespline::test {
namespace {

struct Tracker {
  double maxRatio = 0.0;
  int failures = 0;
  void check(const char* what, const glm::dvec3& expect, const glm::dvec3& got, double tol, const std::string& where) {
    for (int k = 0; k < 3; ++k) {
      const double e = std::abs(expect[k] - got[k]);
      if (!(e <= tol) && failures++ < 8)
        ADD_FAILURE() << what << " at " << where << " axis " << k << ": expected " << expect[k] << " got " << got[k]
                      << " err " << e << " tol " << tol;
      if (std::isfinite(e)) maxRatio = std::max(maxRatio, e / tol);
    }
  }
};

double bboxDiag(const std::vector<glm::dvec3>& pts) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return std::max(glm::length(hi - lo), 1e-300);
}

// count + order knots: interior knots repeated up to `maxMult` times (probability 1/3 each),
// clamped (end knots repeated `order` times) or unclamped (the first and last `order` knots
// distinct), so the domain [t_{k-1}, t_N] always has at least one non-empty interval.
std::vector<double> randomKnots(int order, int count, bool clamped, int maxMult, std::mt19937& rng) {
  std::uniform_real_distribution<double> gap(0.15, 0.6);
  std::uniform_int_distribution<int> mult(2, std::max(2, maxMult));
  const int total = count + order;
  std::vector<double> k;
  double x = 0.0;
  if (clamped) {
    k.assign(order, 0.0);
    x = gap(rng);
  } else {
    for (int i = 0; i < order; ++i) k.push_back(x), x += gap(rng);
  }
  const int interiorEnd = total - order;  // indices [k.size(), interiorEnd) are interior
  while (static_cast<int>(k.size()) < interiorEnd) {
    const int m = (maxMult > 1 && rng() % 3 == 0) ? mult(rng) : 1;
    for (int i = 0; i < m && static_cast<int>(k.size()) < interiorEnd; ++i) k.push_back(x);
    x += gap(rng);
  }
  for (int i = 0; i < order; ++i) {
    k.push_back(x);
    if (!clamped) x += gap(rng);
  }
  return k;
}

double minInterval(const std::vector<double>& k) {
  double h = 1e300;
  for (size_t i = 0; i + 1 < k.size(); ++i)
    if (k[i + 1] > k[i]) h = std::min(h, k[i + 1] - k[i]);
  return h;
}

Curve knotCurve(int order, int count, bool clamped, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  CurveModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = order;
  m.dimension = 3;
  for (int i = 0; i < count; ++i) m.points.push_back({0.5 * i + 0.3 * d(rng), d(rng), d(rng)});
  // Multiplicity up to the order: the validator allows it (a discontinuity inside the domain).
  m.knots = randomKnots(order, count, clamped, order, rng);
  return Curve::create(std::move(m));
}

double relFor(Precision pr) { return pr == Precision::Double ? kFp64Rel : kFp32Rel; }

// Grid over curveGridItems + list of (interval, t) + list of global u, all against the CPU.
void compareCurve(const Curve& cpu, gpu::CurveEvaluator& ev, gpu::GpuCurve& state, Precision pr, Tracker& err) {
  const auto& m = cpu.model();
  const double k = m.family.order, h = minInterval(m.knots);
  const double tol = 4.0 * relFor(pr) * bboxDiag(m.points), tol1 = tol * 8 * k / h, tol2 = tol * 64 * k * k / (h * h);
  const std::vector<int> items = curveGridItems(cpu);
  for (int S : {2, 7}) {
    GridSpec grid;
    grid.samplesU = S;
    size_t seen = 0;
    ev.evaluateGrid(state, grid, fieldBit(Field::Point) | fieldBit(Field::D1) | fieldBit(Field::D2),
                    [&](const GridChunk& c) {
                      for (size_t it = 0; it < c.itemCount; ++it)
                        for (int s = 0; s < S; ++s) {
                          const int span = items[c.firstItem + it];
                          const double t = double(s) / (S - 1);
                          const CurvePoint e = cpu.evaluate(span, t);
                          const size_t p = it * S + s;
                          auto got = [&](Field f) { return glm::dvec3(c.coord(f, p, 0), c.coord(f, p, 1), c.coord(f, p, 2)); };
                          const std::string where = "interval " + std::to_string(span) + " t " + std::to_string(t);
                          err.check("point", e.point, got(Field::Point), tol, where);
                          err.check("d1", e.d1, got(Field::D1), tol1, where);
                          err.check("d2", e.d2, got(Field::D2), tol2, where);
                        }
                      seen += c.itemCount;
                    });
    EXPECT_EQ(seen, items.size());
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<gpu::CurveSample> list;
  for (int i = 0; i < 64; ++i) list.push_back({items[rng() % items.size()], i % 8 == 0 ? 1.0 : unit(rng)});
  const auto got = ev.evaluateList(state, list);
  for (size_t i = 0; i < list.size(); ++i) {
    const CurvePoint e = cpu.evaluate(list[i].span, list[i].t);
    const std::string where = "list " + std::to_string(i);
    err.check("list point", e.point, got[i].point, tol, where);
    err.check("list d1", e.d1, got[i].d1, tol1, where);
    err.check("list d2", e.d2, got[i].d2, tol2, where);
  }
  const auto [lo, hi] = cpu.parameterRange();
  std::vector<double> us = {lo, hi};
  for (size_t j = static_cast<size_t>(m.family.order); j + 1 < m.knots.size() && m.knots[j] < hi; ++j) us.push_back(m.knots[j]);
  for (int i = 0; i < 32; ++i) us.push_back(lo + (hi - lo) * unit(rng));
  const auto gotU = ev.evaluateListAt(state, us);
  for (size_t i = 0; i < us.size(); ++i) {
    const CurvePoint e = cpu.evaluateAt(us[i]);
    const std::string where = "u " + std::to_string(us[i]);
    err.check("at point", e.point, gotU[i].point, tol, where);
    err.check("at d1", e.d1, gotU[i].d1, tol1, where);
    err.check("at d2", e.d2, gotU[i].d2, tol2, where);
  }
}

class GpuBSpline : public VulkanTest, public ::testing::WithParamInterface<Precision> {
 protected:
  bool skipFp64() { return GetParam() == Precision::Double && !ctx().supportsFloat64(); }
};

TEST_P(GpuBSpline, CurvesOrders2To10MatchCpu) {
  if (skipFp64()) GTEST_SKIP() << "no shaderFloat64";
  const Precision pr = GetParam();
  gpu::CurveEvaluator ev(ctx_, pr);
  Tracker err;
  for (int order = 2; order <= 10; ++order)
    for (bool clamped : {true, false}) {
      SCOPED_TRACE("order " + std::to_string(order) + (clamped ? " clamped" : " unclamped"));
      const Curve cpu = knotCurve(order, order + 6, clamped, 100u * order + clamped);
      gpu::GpuCurve state(ctx_, cpu, pr);
      compareCurve(cpu, ev, state, pr, err);
    }
  std::printf("  knot-vector curves %s: max error/tol %.3g\n", pr == Precision::Double ? "fp64" : "fp32", err.maxRatio);
}

TEST_P(GpuBSpline, ExtensionResultsMatchCpu) {
  if (skipFp64()) GTEST_SKIP() << "no shaderFloat64";
  const Precision pr = GetParam();
  gpu::CurveEvaluator ev(ctx_, pr);
  Tracker err;
  for (int order : {3, 4, 6}) {
    SCOPED_TRACE("order " + std::to_string(order));
    std::mt19937 rng(order);
    BSplineCurveData c;
    c.order = order;
    for (int i = 0; i < order + 3; ++i) c.points.push_back({double(i), std::sin(1.3 * i), 0.25 * i});
    c.knots = randomKnots(order, order + 3, true, order - 1, rng);
    const glm::dvec3 targets[2] = {c.points.back() + glm::dvec3(1.0, 0.5, 0.0), c.points.back() + glm::dvec3(2.0, -0.5, 0.5)};
    const ExtensionResult x = extendCurve(c, targets);
    CurveModel m;
    m.family.construction = Construction::BSpline;
    m.family.order = x.curve.order;
    m.dimension = 3;
    m.points = x.curve.points;
    m.knots = x.curve.knots;
    const Curve cpu = Curve::create(std::move(m));
    gpu::GpuCurve state(ctx_, cpu, pr);
    compareCurve(cpu, ev, state, pr, err);
    // The extended curve passes through the targets at u_s (docs/math.md §10.5), on the GPU too.
    const auto got = ev.evaluateListAt(state, x.u);
    const double tol = 4.0 * relFor(pr) * bboxDiag(cpu.model().points) * 16;
    for (size_t s = 0; s < x.u.size(); ++s) err.check("target", targets[s], got[s].point, tol, "u_" + std::to_string(s + 1));
  }
  std::printf("  extension results %s: max error/tol %.3g\n", pr == Precision::Double ? "fp64" : "fp32", err.maxRatio);
}

Surface knotSurface(int ku, int kv, int rows, int cols, bool clampedU, bool clampedV, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-0.3, 0.3);
  SurfaceModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = ku;
  m.orderV = kv;
  m.rows = rows;
  m.cols = cols;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) m.points.push_back({i + d(rng), j + d(rng), std::sin(i + 0.7 * j) + d(rng)});
  m.knotsU = randomKnots(ku, rows, clampedU, ku - 1, rng);
  m.knotsV = randomKnots(kv, cols, clampedV, kv - 1, rng);
  return Surface::create(std::move(m));
}

// The knot-patch grid path (surface_grid.comp on each interval's power-basis coefficients,
// gpu/kernel_runs.h knotPatchGridJob): taken exactly where every interior knot is as smooth as the
// highest partial asked, and there equal to the CPU, partials with respect to the knot parameters;
// rational (weights in [0.5, 2]) as well, through the quotient rule.
TEST_P(GpuBSpline, KnotPatchGridMatchesCpuWhereItApplies) {
  if (skipFp64()) GTEST_SKIP() << "no shaderFloat64";
  const Precision pr = GetParam();
  gpu::SurfaceEvaluator ev(ctx_, pr);
  const FieldMask first = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv) | fieldBit(Field::Normal);
  const FieldMask all = first | fieldBit(Field::Duu) | fieldBit(Field::Duv) | fieldBit(Field::Dvv);
  struct Case {
    int order;
    std::vector<double> knotsU, knotsV;
    FieldMask fields;
    bool patches;  // knotPatchGridJob applies
    bool rational = false;
  };
  const std::vector<double> simple4 = {0, 0, 0, 0, 0.15, 0.4, 0.45, 1, 1, 1, 1};  // 7 points
  const std::vector<double> open4 = {-1, -0.5, 0, 0.2, 0.9, 1.0, 1.7, 2.5, 2.6, 3, 3.2};
  const std::vector<double> double4 = {0, 0, 0, 0, 0.3, 0.3, 0.7, 1, 1, 1, 1};     // a C1 knot
  const std::vector<double> simple3 = {0, 0, 0, 0.1, 0.35, 0.5, 0.8, 1, 1, 1};       // 7 points, C1
  const Case cases[] = {{4, simple4, open4, all, true},       {4, double4, simple4, all, false},
                        {4, double4, simple4, fieldBit(Field::Point), true}, {3, simple3, simple3, all, false},
                        {3, simple3, simple3, first, true},   {4, simple4, open4, all, true, true},
                        {4, double4, simple4, all, false, true}, {3, simple3, simple3, first, true, true}};
  for (const Case& c : cases) {
    SurfaceModel m;
    m.family.construction = Construction::BSpline;
    m.family.order = m.orderV = c.order;
    m.rows = m.cols = 7;
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 7; ++j) {
        m.points.push_back({double(i), double(j), std::sin(0.8 * i + 0.5 * j)});
        if (c.rational) m.weights.push_back(std::exp2(std::sin(1.7 * i + 2.3 * j)));
      }
    m.knotsU = c.knotsU;
    m.knotsV = c.knotsV;
    const Surface cpu = Surface::create(m);
    gpu::GpuSurface state(ctx_, cpu, pr);
    GridSpec grid;
    grid.samplesU = 5;
    grid.samplesV = 8;
    SCOPED_TRACE("order " + std::to_string(c.order) + " fields " + std::to_string(c.fields) +
                 (c.rational ? " rational" : ""));
    EXPECT_EQ(gpu::knotPatchGridJob(state, grid, c.fields).has_value(), c.patches);
    const double h = std::min(minInterval(m.knotsU), minInterval(m.knotsV));
    const double tol = 4.0 * relFor(pr) * bboxDiag(cpu.controlPoints()), tol1 = tol * 8 * c.order / h,
                 tol2 = tol * 64 * c.order * c.order / (h * h);
    const auto items = surfaceGridItems(cpu);
    double worst = 0.0;  // error / tolerance
    ev.evaluateGrid(state, grid, c.fields, [&](const GridChunk& ch) {
      for (size_t it = 0; it < ch.itemCount; ++it) {
        const auto [i, j] = items[ch.firstItem + it];
        for (int a = 0; a < grid.samplesU; ++a)
          for (int b = 0; b < grid.samplesV; ++b) {
            const SurfacePoint e = cpu.evaluate(i, j, a / 4.0, b / 7.0);
            const size_t p = it * 40 + size_t(a) * 8 + b;
            const std::pair<Field, std::pair<glm::dvec3, double>> want[] = {
                {Field::Point, {e.point, tol}}, {Field::Du, {e.du, tol1}},   {Field::Dv, {e.dv, tol1}},
                {Field::Duu, {e.duu, tol2}},    {Field::Duv, {e.duv, tol2}}, {Field::Dvv, {e.dvv, tol2}}};
            for (const auto& [f, ref] : want) {
              if (!(c.fields & fieldBit(f))) continue;
              const glm::dvec3 got(ch.coord(f, p, 0), ch.coord(f, p, 1), ch.coord(f, p, 2));
              worst = std::max(worst, glm::length(got - ref.first) / ref.second);
            }
          }
      }
    });
    EXPECT_LE(worst, 1.0);
  }
}

TEST_P(GpuBSpline, SurfacesMatchCpu) {
  if (skipFp64()) GTEST_SKIP() << "no shaderFloat64";
  const Precision pr = GetParam();
  const bool fp64 = pr == Precision::Double;
  gpu::SurfaceEvaluator ev(ctx_, pr);
  Tracker err;
  struct Case { int ku, kv, rows, cols; bool cu, cv; };
  const Case cases[] = {{2, 2, 4, 5, true, true},  {3, 4, 6, 6, true, false}, {4, 4, 7, 6, false, true},
                        {5, 2, 7, 4, false, false}, {7, 3, 9, 5, true, true},  {10, 6, 11, 8, true, false}};
  FieldMask mask = 0;
  for (Field f : {Field::Point, Field::Du, Field::Dv, Field::Duu, Field::Duv, Field::Dvv, Field::Normal}) mask |= fieldBit(f);
  for (const Case& c : cases) {
    const std::string name = std::to_string(c.ku) + "x" + std::to_string(c.kv) + (c.cu ? "C" : "U") + (c.cv ? "C" : "U");
    SCOPED_TRACE(name);
    const Surface cpu = knotSurface(c.ku, c.kv, c.rows, c.cols, c.cu, c.cv, 31u * c.ku + c.kv);
    const auto& m = cpu.model();
    const double h = std::min(minInterval(m.knotsU), minInterval(m.knotsV)), k = std::max(c.ku, c.kv);
    const double tol = 4.0 * relFor(pr) * bboxDiag(cpu.controlPoints()), tol1 = tol * 8 * k / h, tol2 = tol * 64 * k * k / (h * h);
    gpu::GpuSurface state(ctx_, cpu, pr);
    const auto items = surfaceGridItems(cpu);
    auto checkPoint = [&](const SurfacePoint& e, const SurfacePoint& g, const std::string& where) {
      err.check("point", e.point, g.point, tol, where);
      err.check("du", e.du, g.du, tol1, where);
      err.check("dv", e.dv, g.dv, tol1, where);
      err.check("duu", e.duu, g.duu, tol2, where);
      err.check("duv", e.duv, g.duv, tol2, where);
      err.check("dvv", e.dvv, g.dvv, tol2, where);
      if (!(std::abs(glm::length(g.normal) - 1.0) < (fp64 ? 1e-12 : 1e-5))) ADD_FAILURE() << "normal not unit at " << where;
      const double lu = glm::length(e.du), lv = glm::length(e.dv);
      const double sinA = glm::length(glm::cross(e.du, e.dv)) / (lu * lv);
      if (e.normalRule == NormalRule::Regular && sinA > 0.05)
        err.check("normal", e.normal, g.normal, 2.0 * (tol1 / lu + tol1 / lv) / sinA, where);
    };
    // 5 x 3: one sample per invocation of the knot grid kernel; 4 x 8: runs of 8 samples, whose
    // last one may change span (a knot where a derivative jumps).
    for (const auto& shape : {std::pair{5, 3}, std::pair{4, 8}}) {
      const int su = shape.first, sv = shape.second;  // not a structured binding: the lambdas capture them (clang 15)
      GridSpec grid;
      grid.samplesU = su;
      grid.samplesV = sv;
      size_t seen = 0;
      ev.evaluateGrid(state, grid, mask, [&](const GridChunk& ch) {
        for (size_t it = 0; it < ch.itemCount; ++it) {
          const auto [i, j] = items[ch.firstItem + it];
          for (int a = 0; a < grid.samplesU; ++a)
            for (int b = 0; b < grid.samplesV; ++b) {
              const double u = a / double(su - 1), v = b / double(sv - 1);
              const size_t p = it * size_t(su * sv) + a * sv + b;
              auto got = [&](Field f) { return glm::dvec3(ch.coord(f, p, 0), ch.coord(f, p, 1), ch.coord(f, p, 2)); };
              SurfacePoint g;
              g.point = got(Field::Point), g.du = got(Field::Du), g.dv = got(Field::Dv);
              g.duu = got(Field::Duu), g.duv = got(Field::Duv), g.dvv = got(Field::Dvv), g.normal = got(Field::Normal);
              checkPoint(cpu.evaluate(i, j, u, v), g,
                         "interval " + std::to_string(i) + "," + std::to_string(j) + " uv " + std::to_string(u) + "," +
                             std::to_string(v));
            }
        }
        seen += ch.itemCount;
      });
      EXPECT_EQ(seen, items.size());
    }
    std::mt19937 rng(c.ku * 7 + c.kv);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<gpu::SurfaceSample> list;
    for (int n = 0; n < 48; ++n) {
      const auto [i, j] = items[rng() % items.size()];
      list.push_back({i, j, n % 6 == 0 ? 1.0 : unit(rng), n % 5 == 0 ? 0.0 : unit(rng)});
    }
    const auto got = ev.evaluateList(state, list);
    for (size_t n = 0; n < list.size(); ++n)
      checkPoint(cpu.evaluate(list[n].i, list[n].j, list[n].u, list[n].v), got[n], "list " + std::to_string(n));
    const auto [ulo, uhi] = cpu.parameterRangeU();
    const auto [vlo, vhi] = cpu.parameterRangeV();
    std::vector<std::pair<double, double>> uv = {{ulo, vlo}, {uhi, vhi}};
    for (int n = 0; n < 24; ++n) uv.push_back({ulo + (uhi - ulo) * unit(rng), vlo + (vhi - vlo) * unit(rng)});
    const auto gotAt = ev.evaluateListAt(state, uv);
    for (size_t n = 0; n < uv.size(); ++n)
      checkPoint(cpu.evaluateAt(uv[n].first, uv[n].second), gotAt[n], "at " + std::to_string(n));
  }
  std::printf("  knot-vector surfaces %s: max error/tol %.3g\n", fp64 ? "fp64" : "fp32", err.maxRatio);
}

TEST_P(GpuBSpline, ControlPointUpdateAndRejectedParameters) {
  if (skipFp64()) GTEST_SKIP() << "no shaderFloat64";
  const Precision pr = GetParam();
  Curve cpu = knotCurve(4, 9, true, 5);
  gpu::GpuCurve state(ctx_, cpu, pr);
  gpu::CurveEvaluator ev(ctx_, pr);
  EXPECT_THROW(state.setLambda(1.0), std::invalid_argument);
  CurveModel m = cpu.model();
  m.points[4] += glm::dvec3(0.5, -1.0, 2.0);
  state.updateControlPoint(4, m.points[4]);
  EXPECT_EQ(state.uploadStats().netWrites, 2u);
  cpu = Curve::create(m);
  Tracker err;
  compareCurve(cpu, ev, state, pr, err);
}

// Rational B-splines (docs/math.md §10.8) on the GPU, grid and list kernels: the NURBS unit circle
// stays on the circle to the precision, and a general rational surface (a torus of revolution with
// one weight changed) matches the CPU.
TEST_P(GpuBSpline, RationalCurvesAndSurfacesMatchCpu) {
  if (skipFp64()) GTEST_SKIP() << "no shaderFloat64";
  const Precision pr = GetParam();
  const double rel = relFor(pr);
  const CurveModel cm = nurbsCircle(1.0);
  const Curve curve = Curve::create(cm);
  gpu::CurveEvaluator cev(ctx_, pr);
  gpu::GpuCurve gcurve(ctx_, curve, pr);
  Tracker err;
  double worstRadius = 0.0;
  GridSpec cgrid;
  cgrid.samplesU = 9;
  const std::vector<int> items = curveGridItems(curve);
  cev.evaluateGrid(gcurve, cgrid, fieldBit(Field::Point) | fieldBit(Field::D1) | fieldBit(Field::D2), [&](const GridChunk& c) {
    for (size_t i = 0; i < c.pointCount(); ++i) {
      const glm::dvec3 p(c.coord(Field::Point, i, 0), c.coord(Field::Point, i, 1), c.coord(Field::Point, i, 2));
      worstRadius = std::max(worstRadius, std::abs(glm::length(p) - 1.0));
      const size_t item = c.firstItem + i / 9;
      const CurvePoint e = curve.evaluate(items[item], double(i % 9) / 8);
      const glm::dvec3 d1(c.coord(Field::D1, i, 0), c.coord(Field::D1, i, 1), c.coord(Field::D1, i, 2));
      err.check("circle point", e.point, p, 4 * rel, "grid " + std::to_string(i));
      err.check("circle d1", e.d1, d1, 64 * rel * glm::length(e.d1), "grid " + std::to_string(i));
    }
  });
  std::vector<double> us;
  for (int k = 0; k <= 40; ++k) us.push_back(k / 40.0);
  const auto at = cev.evaluateListAt(gcurve, us);
  for (size_t k = 0; k < us.size(); ++k) {
    worstRadius = std::max(worstRadius, std::abs(glm::length(at[k].point) - 1.0));
    const CurvePoint e = curve.evaluateAt(us[k]);
    err.check("circle list d2", e.d2, at[k].d2, 256 * rel * (1.0 + glm::length(e.d2)), "u " + std::to_string(us[k]));
  }
  EXPECT_LE(worstRadius, pr == Precision::Double ? 1e-15 : 1e-6);

  // The exact torus on the knot-patch grid path (points: its C0 quadrant knots allow it): every
  // sample at distance r from the tube's centre circle.
  {
    const Surface torus = Surface::create(nurbsTorus(3.0, 1.25));
    gpu::SurfaceEvaluator tev(ctx_, pr);
    gpu::GpuSurface gtorus(ctx_, torus, pr);
    const GridSpec tgrid{6, 8, 0, 0};
    ASSERT_TRUE(gpu::knotPatchGridJob(gtorus, tgrid, fieldBit(Field::Point)).has_value());
    double worstTube = 0.0;
    tev.evaluateGrid(gtorus, tgrid, fieldBit(Field::Point), [&](const GridChunk& ch) {
      for (size_t i = 0; i < ch.pointCount(); ++i) {
        const glm::dvec3 p(ch.coord(Field::Point, i, 0), ch.coord(Field::Point, i, 1), ch.coord(Field::Point, i, 2));
        const double ring = std::hypot(p.x, p.y) - 3.0;
        worstTube = std::max(worstTube, std::abs(std::hypot(ring, p.z) - 1.25) / 1.25);
      }
    });
    std::printf("  rational %s: knot-patch torus max relative | d - r | %.2e\n",
                pr == Precision::Double ? "fp64" : "fp32", worstTube);
    EXPECT_LE(worstTube, pr == Precision::Double ? 1e-15 : 1e-6);
  }

  SurfaceModel sm = nurbsTorus(3.0, 1.25);
  sm.weights[40] = 2.5;
  const Surface surface = Surface::create(sm);
  gpu::SurfaceEvaluator sev(ctx_, pr);
  gpu::GpuSurface gsurface(ctx_, surface, pr);
  const double tol = 16 * rel * bboxDiag(sm.points), tol1 = 64 * tol, tol2 = 1024 * tol;
  const auto sitems = surfaceGridItems(surface);
  FieldMask all = 0;
  for (Field f : {Field::Point, Field::Du, Field::Dv, Field::Duu, Field::Duv, Field::Dvv, Field::Normal}) all |= fieldBit(f);
  for (const auto& shape : {std::pair{5, 3}, std::pair{4, 8}}) {
    const int su = shape.first, sv = shape.second;  // not a structured binding: the lambdas capture them (clang 15)
    sev.evaluateGrid(gsurface, {su, sv, 0, 0}, all, [&](const GridChunk& ch) {
      for (size_t i = 0; i < ch.pointCount(); ++i) {
        const size_t item = ch.firstItem + i / size_t(su * sv), k = i % size_t(su * sv);
        const auto [pi, pj] = sitems[item];
        const SurfacePoint e = surface.evaluate(pi, pj, double(k / size_t(sv)) / (su - 1), double(k % size_t(sv)) / (sv - 1));
        auto got = [&](Field f) { return glm::dvec3(ch.coord(f, i, 0), ch.coord(f, i, 1), ch.coord(f, i, 2)); };
        const std::string where = "grid " + std::to_string(su) + "x" + std::to_string(sv) + " point " + std::to_string(i);
        err.check("point", e.point, got(Field::Point), tol, where);
        err.check("du", e.du, got(Field::Du), tol1, where);
        err.check("dv", e.dv, got(Field::Dv), tol1, where);
        err.check("duu", e.duu, got(Field::Duu), tol2, where);
        err.check("duv", e.duv, got(Field::Duv), tol2, where);
        err.check("dvv", e.dvv, got(Field::Dvv), tol2, where);
      }
    });
  }
  std::vector<std::pair<double, double>> uv;
  for (int k = 0; k < 30; ++k) uv.push_back({(k * 37 % 101) / 100.0, (k * 53 % 101) / 100.0});
  const auto sat = sev.evaluateListAt(gsurface, uv);
  for (size_t k = 0; k < uv.size(); ++k) {
    const SurfacePoint e = surface.evaluateAt(uv[k].first, uv[k].second);
    err.check("list point", e.point, sat[k].point, tol, "at " + std::to_string(k));
    err.check("list duv", e.duv, sat[k].duv, tol2, "at " + std::to_string(k));
  }
  std::printf("  rational %s: circle max | |P| - 1 | %.2e, max error/tol %.3g\n",
              pr == Precision::Double ? "fp64" : "fp32", worstRadius, err.maxRatio);
}

INSTANTIATE_TEST_SUITE_P(Precisions, GpuBSpline, ::testing::Values(Precision::Float, Precision::Double),
                         [](const auto& i) { return std::string(i.param == Precision::Double ? "fp64" : "fp32"); });

}  // namespace
}  // namespace shapespline::test
