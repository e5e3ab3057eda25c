// GPU kernels against the CPU fp64 core (core/curve.h, core/surface.h) on regular grids: family x
// degree/order x λ/μ x α x open/closed x grid sizes (including sizes that are not multiples of the
// 4-point invocation or the workgroup; samplesV = 8 without normals takes surface_grid.comp for plain
// families) and
// jobs forced into several chunks (small maxPlaneBytes).
// Also: the λ/α update path never re-uploads the net, basis tables equal evalSpanBasis, and list
// evaluation equals grid evaluation.
//
// Tolerances, relative to scale = bounding-box diagonal of the net, g = 1/α_min (α-EB) or 1:
//  * point: kFp64Rel / kFp32Rel * scale * g (support/tolerances.h).
//  * first derivatives: the same times 8·m: Σ|B_r'| ≤ ~2 for the 4-function families and grows
//    roughly like m for order-m UBP; α-EB adds 2 max S' = 4.5 (tests/core/golden_curves.cpp).
//  * second derivatives: times 64·m (Σ|B_r''| grows like m^2; α-EB adds 4 max S' D1 + 2 max S'').
//  * normals: 1e-9 (fp64) / 2e-3 (fp32) in absolute value where sin∠(du,dv) > 0.05: a unit vector
//    perturbed by relative errors ε of du, dv moves by ≤ 2ε / sin∠.
// Each test prints its largest error / tolerance ratio.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>
#include <shapespline/gpu/evaluator.h>
#include "support/tolerances.h"
#include "support/degenerate_nets.h"
#include "support/vk_fixture.h"

namespace shapespline::test {
namespace {

struct ErrorTracker {
  double maxRatio = 0.0, maxErr[9] = {};
  int failures = 0, count[9] = {};
  void check(const char* what, int field, const glm::dvec3& expect, const glm::dvec3& got, double tol,
             const std::string& where) {
    ++count[field];
    for (int k = 0; k < 3; ++k) {
      const double e = std::abs(expect[k] - got[k]);
      if (!(e <= tol)) {
        if (failures++ < 8)
          ADD_FAILURE() << what << " at " << where << " axis " << k << ": expected " << expect[k] << " got "
                        << got[k] << " err " << e << " tol " << tol;
      }
      maxErr[field] = std::max(maxErr[field], e);
      maxRatio = std::max(maxRatio, e / tol);
    }
  }
};

double bboxDiag(const std::vector<glm::dvec3>& pts) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return std::max(glm::length(hi - lo), 1e-300);
}

std::vector<glm::dvec3> randomPoints(int n, unsigned seed, bool flat) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  std::vector<glm::dvec3> p(n);
  for (int i = 0; i < n; ++i) p[i] = {3.0 * i / n + 0.3 * d(rng), d(rng), flat ? 0.0 : d(rng)};
  return p;
}

std::vector<double> randomAlpha(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(0.25, 1.0);
  std::vector<double> a(n);
  for (auto& x : a) x = d(rng);
  if (n > 1) a[n / 2] = 1.0;  // exercise V = P
  return a;
}

struct CurveCase {
  std::string name;
  FamilySpec family;
  bool closed;
  int n;
  bool knots = false;
};

std::vector<CurveCase> curveCases() {
  std::vector<CurveCase> c;
  auto fam = [](Construction k, int degree, int order, double lambda, std::vector<double> mu = {}) {
    FamilySpec f;
    f.construction = k;
    f.degree = degree;
    f.order = order;
    f.lambda = lambda;
    f.mu = std::move(mu);
    return f;
  };
  for (bool closed : {false, true}) {
    const std::string cs = closed ? "closed" : "open";
    c.push_back({"xw4_l0_" + cs, fam(Construction::ExtendedBSpline, 4, 0, 0.0), closed, 9});
    c.push_back({"xw6_lm7_" + cs, fam(Construction::ExtendedBSpline, 6, 0, -7.5), closed, 8});
    c.push_back({"gb_l3_" + cs, fam(Construction::GB, 0, 0, 3.0), closed, 7});
    c.push_back({"ubp7_" + cs, fam(Construction::UBP, 0, 7, 0.25), closed, 12});
    c.push_back({"gubp5_" + cs, fam(Construction::GUBP, 0, 5, 0.0, {0.25, 0.5, 0.25}), closed, 10});
    c.push_back({"bspline10_" + cs, fam(Construction::BSpline, 0, 10, 0.0), closed, 14});
    c.push_back({"aeb4_" + cs, fam(Construction::AlphaEB, 4, 0, 0.5), closed, 6});
    c.push_back({"aeb5_" + cs, fam(Construction::AlphaEB, 5, 0, -3.0), closed, 5});
    c.push_back({"aeb6_" + cs, fam(Construction::AlphaEB, 6, 0, 1.0), closed, 7});
  }
  c.push_back({"xw5_knots", fam(Construction::ExtendedBSpline, 5, 0, 0.5), false, 8, true});
  return c;
}

Curve makeCurve(const CurveCase& cc) {
  CurveModel m;
  m.family = cc.family;
  m.closed = cc.closed;
  m.dimension = 3;
  m.points = randomPoints(cc.n, 17u + cc.n, false);
  if (cc.family.construction == Construction::AlphaEB) m.alpha = randomAlpha(cc.n, 5u + cc.n);
  if (cc.knots) {
    const int spans = cc.n - 3;
    double k = 0.0;
    for (int s = 0; s <= spans; ++s) m.knots.push_back(k), k += 0.5 + 0.25 * (s % 3);
  }
  return Curve::create(std::move(m));
}

void compareCurveGrid(const Curve& cpu, gpu::CurveEvaluator& ev, gpu::GpuCurve& state, int samples, size_t planeBytes,
                      ErrorTracker& err, Precision pr, int* chunks = nullptr) {
  (void)planeBytes;
  const double rel = pr == Precision::Double ? kFp64Rel : kFp32Rel;
  const auto& m = cpu.model();
  const double g = m.alpha.empty() ? 1.0 : 1.0 / *std::min_element(m.alpha.begin(), m.alpha.end());
  double hmin = 1.0;
  for (size_t s = 0; s + 1 < cpu.spanKnots().size(); ++s) hmin = std::min(hmin, cpu.spanKnots()[s + 1] - cpu.spanKnots()[s]);
  const double tol = rel * bboxDiag(m.points) * g * 4.0;
  const double mm = cpu.basis().count;
  GridSpec grid;
  grid.samplesU = samples;
  const FieldMask mask = fieldBit(Field::Point) | fieldBit(Field::D1) | fieldBit(Field::D2);
  size_t seen = 0;
  ev.evaluateGrid(state, grid, mask, [&](const GridChunk& c) {
    EXPECT_EQ(c.firstItem, seen);
    seen += c.itemCount;
    if (chunks) ++*chunks;
    for (size_t it = 0; it < c.itemCount; ++it)
      for (int s = 0; s < samples; ++s) {
        const int span = cpu.spans().first + int(c.firstItem + it);
        const double t = samples > 1 ? double(s) / (samples - 1) : 0.0;
        const CurvePoint e = cpu.evaluate(span, t);
        const size_t k = it * samples + s;
        auto got = [&](Field f) { return glm::dvec3(c.coord(f, k, 0), c.coord(f, k, 1), c.coord(f, k, 2)); };
        const std::string where = "span " + std::to_string(span) + " t " + std::to_string(t);
        err.check("point", 0, e.point, got(Field::Point), tol, where);
        err.check("d1", 1, e.d1, got(Field::D1), tol * 8 * mm / hmin, where);
        err.check("d2", 2, e.d2, got(Field::D2), tol * 64 * mm / (hmin * hmin), where);
      }
  });
  EXPECT_EQ(seen, cpu.spans().last - cpu.spans().first + 1u);
}

class GpuCurveSweep : public VulkanTest, public ::testing::WithParamInterface<Precision> {};

TEST_P(GpuCurveSweep, GridMatchesCpu) {
  const Precision pr = GetParam();
  if (pr == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  gpu::CurveEvaluator ev(ctx_, pr);
  gpu::EvaluatorOptions plain;
  plain.packedStores = false;
  gpu::CurveEvaluator evPlain(ctx_, pr, plain);
  ErrorTracker err;
  for (const CurveCase& cc : curveCases()) {
    SCOPED_TRACE(cc.name);
    const Curve cpu = makeCurve(cc);
    gpu::GpuCurve state(ctx_, cpu, pr);
    // 1, 2, 7, 33: curve_eval.comp; multiples of 4: curve_grid.comp (whole spans per invocation up
    // to 256 samples, runs of 4 for 300).
    for (int samples : {1, 2, 7, 33, 8, 12, 300}) compareCurveGrid(cpu, ev, state, samples, 0, err, pr);
    // Plain float stores (devices without shaderInt64) on a few families only: each family is one
    // more pipeline to compile.
    if (cc.name == "aeb5_closed" || cc.name == "xw5_knots") compareCurveGrid(cpu, evPlain, state, 16, 0, err, pr);
  }
  std::printf("  curve sweep %s: max error point %.3g d1 %.3g d2 %.3g, max error/tol %.3g\n",
              pr == Precision::Double ? "fp64" : "fp32", err.maxErr[0], err.maxErr[1], err.maxErr[2], err.maxRatio);
}

TEST_P(GpuCurveSweep, ChunkedJobAndListMatch) {
  const Precision pr = GetParam();
  if (pr == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  gpu::EvaluatorOptions opt;
  opt.maxPlaneBytes = 4096;  // forces many chunks
  opt.workgroupSize = 32;
  gpu::CurveEvaluator ev(ctx_, pr, opt);
  ErrorTracker err;
  CurveCase cc{"aeb5_closed_long", {}, true, 40};
  cc.family.construction = Construction::AlphaEB;
  cc.family.degree = 5;
  cc.family.lambda = 0.25;
  const Curve cpu = makeCurve(cc);
  gpu::GpuCurve state(ctx_, cpu, pr);
  int chunks = 0;
  compareCurveGrid(cpu, ev, state, 29, opt.maxPlaneBytes, err, pr, &chunks);
  EXPECT_GT(chunks, 3);
  // List mode at random (span, t).
  std::mt19937 rng(3);
  std::vector<gpu::CurveSample> s;
  for (int i = 0; i < 1001; ++i)
    s.push_back({cpu.spans().first + int(rng() % (cpu.spans().last - cpu.spans().first + 1)),
                 std::uniform_real_distribution<double>(0, 1)(rng)});
  const auto got = ev.evaluateList(state, s);
  const double tol = (pr == Precision::Double ? kFp64Rel : kFp32Rel) * bboxDiag(cpu.model().points) * 4.0 /
                     *std::min_element(cpu.model().alpha.begin(), cpu.model().alpha.end());
  for (size_t i = 0; i < s.size(); ++i) {
    const CurvePoint e = cpu.evaluate(s[i].span, s[i].t);
    err.check("list point", 0, e.point, got[i].point, tol, std::to_string(i));
    err.check("list d1", 1, e.d1, got[i].d1, tol * 32, std::to_string(i));
    err.check("list d2", 2, e.d2, got[i].d2, tol * 256, std::to_string(i));
  }
  std::printf("  chunked curve (%d chunks) + list: max error/tol %.3g\n", chunks, err.maxRatio);
}

// ---- Surfaces -----------------------------------------------------------------------------------

struct SurfaceCase {
  std::string name;
  FamilySpec family;
  int orderV = 0;
  bool closedU, closedV;
  int rows, cols;
};

std::vector<SurfaceCase> surfaceCases() {
  std::vector<SurfaceCase> c;
  auto fam = [](Construction k, int degree, int order, double lambda) {
    FamilySpec f;
    f.construction = k;
    f.degree = degree;
    f.order = order;
    f.lambda = lambda;
    return f;
  };
  const bool flags[4][2] = {{false, false}, {true, false}, {false, true}, {true, true}};
  for (auto& f : flags) {
    const std::string cs = std::string(f[0] ? "C" : "O") + (f[1] ? "C" : "O");
    c.push_back({"aeb4_" + cs, fam(Construction::AlphaEB, 4, 0, 0.0), 0, f[0], f[1], 5, 6});
    c.push_back({"aeb6_" + cs, fam(Construction::AlphaEB, 6, 0, -10.0), 0, f[0], f[1], 5, 4});
    c.push_back({"xw5_" + cs, fam(Construction::ExtendedBSpline, 5, 0, 0.5), 0, f[0], f[1], 6, 5});
  }
  c.push_back({"gb_OO", fam(Construction::GB, 0, 0, 2.0), 0, false, true, 5, 6});
  c.push_back({"ubp6_OC", fam(Construction::UBP, 0, 6, 0.5), 0, false, true, 8, 7});
  c.push_back({"bspline_3x5", fam(Construction::BSpline, 0, 3, 0.0), 5, true, false, 5, 7});
  return c;
}

Surface makeSurface(const SurfaceCase& sc) {
  SurfaceModel m;
  m.family = sc.family;
  m.orderV = sc.orderV;
  m.closedU = sc.closedU;
  m.closedV = sc.closedV;
  m.rows = sc.rows;
  m.cols = sc.cols;
  std::mt19937 rng(sc.rows * 31 + sc.cols);
  std::uniform_real_distribution<double> d(-0.3, 0.3);
  for (int i = 0; i < sc.rows; ++i)
    for (int j = 0; j < sc.cols; ++j) m.points.push_back({i + d(rng), j + d(rng), std::sin(i + 0.7 * j) + d(rng)});
  if (sc.family.construction == Construction::AlphaEB) m.alpha = randomAlpha(sc.rows * sc.cols, sc.rows + 7u * sc.cols);
  return Surface::create(std::move(m));
}

void compareSurfaceGrid(const Surface& cpu, gpu::SurfaceEvaluator& ev, gpu::GpuSurface& state, int su, int sv,
                        ErrorTracker& err, Precision pr, int* chunks = nullptr, bool normals = true) {
  const bool fp64 = pr == Precision::Double;
  const auto& m = cpu.model();
  const double g = m.alpha.empty() ? 1.0 : 1.0 / *std::min_element(m.alpha.begin(), m.alpha.end());
  const double tol = (fp64 ? kFp64Rel : kFp32Rel) * bboxDiag(cpu.controlPoints()) * g * 4.0;
  const double mm = std::max(cpu.basisU().count, cpu.basisV().count);
  GridSpec grid;
  grid.samplesU = su;
  grid.samplesV = sv;
  FieldMask mask = 0;
  for (Field f : {Field::Point, Field::Du, Field::Dv, Field::Duu, Field::Duv, Field::Dvv, Field::Normal}) mask |= fieldBit(f);
  if (!normals) mask &= ~fieldBit(Field::Normal);
  const size_t pv = cpu.patches().v.last - cpu.patches().v.first + 1;
  size_t seen = 0;
  ev.evaluateGrid(state, grid, mask, [&](const GridChunk& c) {
    EXPECT_EQ(c.firstItem, seen);
    seen += c.itemCount;
    if (chunks) ++*chunks;
    for (size_t it = 0; it < c.itemCount; ++it) {
      const size_t lin = c.firstItem + it;
      const int i = cpu.patches().u.first + int(lin / pv), j = cpu.patches().v.first + int(lin % pv);
      for (int a = 0; a < su; ++a)
        for (int b = 0; b < sv; ++b) {
          const double u = su > 1 ? double(a) / (su - 1) : 0.0, v = sv > 1 ? double(b) / (sv - 1) : 0.0;
          const SurfacePoint e = cpu.evaluate(i, j, u, v);
          const size_t k = it * su * sv + a * sv + b;
          auto got = [&](Field f) { return glm::dvec3(c.coord(f, k, 0), c.coord(f, k, 1), c.coord(f, k, 2)); };
          const std::string where = "patch " + std::to_string(i) + "," + std::to_string(j) + " uv " +
                                    std::to_string(u) + "," + std::to_string(v);
          err.check("point", 0, e.point, got(Field::Point), tol, where);
          err.check("du", 1, e.du, got(Field::Du), tol * 8 * mm, where);
          err.check("dv", 2, e.dv, got(Field::Dv), tol * 8 * mm, where);
          err.check("duu", 3, e.duu, got(Field::Duu), tol * 64 * mm, where);
          err.check("duv", 4, e.duv, got(Field::Duv), tol * 64 * mm, where);
          err.check("dvv", 5, e.dvv, got(Field::Dvv), tol * 64 * mm, where);
          if (!normals) continue;
          const glm::dvec3 n = got(Field::Normal);
          if (!(std::abs(glm::length(n) - 1.0) < (fp64 ? 1e-12 : 1e-5))) {
            ADD_FAILURE() << "normal not unit at " << where;
            continue;
          }
          const double sinA = glm::length(glm::cross(e.du, e.dv)) / (glm::length(e.du) * glm::length(e.dv));
          if (e.normalRule == NormalRule::Regular && sinA > 0.05)
            err.check("normal", 6, e.normal, n, (fp64 ? 1e-9 : 2e-3), where);
          else if (e.normalRule != NormalRule::Regular && fp64)
            err.check("normal(fallback)", 7, e.normal, n, 1e-6, where);
        }
    }
  });
  EXPECT_EQ(seen, (cpu.patches().u.last - cpu.patches().u.first + 1u) * pv);
}

class GpuSurfaceSweep : public VulkanTest, public ::testing::WithParamInterface<Precision> {};

TEST_P(GpuSurfaceSweep, GridMatchesCpu) {
  const Precision pr = GetParam();
  if (pr == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  gpu::SurfaceEvaluator ev(ctx_, pr);
  ErrorTracker err;
  for (const SurfaceCase& sc : surfaceCases()) {
    SCOPED_TRACE(sc.name);
    const Surface cpu = makeSurface(sc);
    gpu::GpuSurface state(ctx_, cpu, pr);
    for (auto [su, sv] : {std::pair{2, 2}, std::pair{5, 3}, std::pair{9, 9}}) compareSurfaceGrid(cpu, ev, state, su, sv, err, pr);
    // Without normals and with samplesV % 4 == 0, plain families take surface_grid.comp (a few
    // cases only: every family/degree is one more pipeline to compile).
    if (sc.name == "xw5_CO" || sc.name == "ubp6_OC" || sc.name == "bspline_3x5")
      compareSurfaceGrid(cpu, ev, state, 6, 8, err, pr, nullptr, false);  // groups of 8 samples
    if (sc.name == "xw5_CO" || sc.name == "aeb4_OO")
      compareSurfaceGrid(cpu, ev, state, 3, 12, err, pr);  // 12 per row: groups of 4, with normals
  }
  std::printf("  surface sweep %s: max error point %.3g du %.3g dv %.3g duu %.3g duv %.3g dvv %.3g normal %.3g "
              "(fallback normals %.3g), max error/tol %.3g\n",
              pr == Precision::Double ? "fp64" : "fp32", err.maxErr[0], err.maxErr[1], err.maxErr[2], err.maxErr[3],
              err.maxErr[4], err.maxErr[5], err.maxErr[6], err.maxErr[7], err.maxRatio);
}

// collapsedRowsNet: patch row 0 is a point (fixed-axis normals everywhere) and the u = 0 row of
// patch row 1 a pole (shifted-rule normals). Every sample of those grid rows needs the fallback, more than surface_grid.comp remembers per invocation, so it redoes whole
// invocations; fp64 matches the CPU's fallback normals within 1e-6, fp32 stays finite and unit.
TEST_P(GpuSurfaceSweep, DegenerateRowsRedoWholeInvocations) {
  const Precision pr = GetParam();
  if (pr == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  const Surface cpu = Surface::create(collapsedRowsNet());
  gpu::SurfaceEvaluator ev(ctx_, pr);
  gpu::GpuSurface state(ctx_, cpu, pr);
  ErrorTracker err;
  compareSurfaceGrid(cpu, ev, state, 5, 8, err, pr);  // samplesV % 4 == 0: surface_grid.comp
  std::printf("  degenerate rows %s: max error point %.3g normal %.3g fallback normal %.3g\n",
              pr == Precision::Double ? "fp64" : "fp32", err.maxErr[0], err.maxErr[6], err.maxErr[7]);
  if (pr == Precision::Double) {
    EXPECT_GT(err.count[7], 40) << "fallback normals compared";
  }
}

// surface_grid.comp with plain float stores (devices without shaderInt64) as well as the packed
// ones the other tests use on lavapipe: an α-EB surface with every field and normals, a plain
// family without normals, over several chunks.
TEST_P(GpuSurfaceSweep, PlainStoresMatchCpu) {
  const Precision pr = GetParam();
  if (pr == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  gpu::EvaluatorOptions opt;
  opt.packedStores = false;
  opt.maxPlaneBytes = 2048;  // one or two patches per chunk
  gpu::SurfaceEvaluator ev(ctx_, pr, opt);
  ErrorTracker err;
  for (const SurfaceCase& sc : surfaceCases()) {
    if (sc.name != "aeb6_CO" && sc.name != "xw5_OC") continue;
    SCOPED_TRACE(sc.name);
    const Surface cpu = makeSurface(sc);
    gpu::GpuSurface state(ctx_, cpu, pr);
    int chunks = 0;
    compareSurfaceGrid(cpu, ev, state, 9, 8, err, pr, &chunks, sc.name == "aeb6_CO");
    EXPECT_GT(chunks, 1);
  }
  EXPECT_GT(err.count[0], 0) << "cases compared";
  std::printf("  plain stores %s: max error point %.3g du %.3g normal %.3g, max error/tol %.3g\n",
              pr == Precision::Double ? "fp64" : "fp32", err.maxErr[0], err.maxErr[1], err.maxErr[6], err.maxRatio);
}

TEST_P(GpuSurfaceSweep, ChunkedJobMatches) {
  const Precision pr = GetParam();
  if (pr == Precision::Double && !ctx().supportsFloat64()) GTEST_SKIP() << "no shaderFloat64";
  gpu::EvaluatorOptions opt;
  opt.maxPlaneBytes = 6000;
  opt.workgroupSize = 48;
  gpu::SurfaceEvaluator ev(ctx_, pr, opt);
  ErrorTracker err;
  SurfaceCase sc{"aeb5_CO", {}, 0, true, false, 7, 6};
  sc.family.construction = Construction::AlphaEB;
  sc.family.degree = 5;
  sc.family.lambda = 0.75;
  const Surface cpu = makeSurface(sc);
  gpu::GpuSurface state(ctx_, cpu, pr);
  int chunks = 0;
  compareSurfaceGrid(cpu, ev, state, 11, 7, err, pr, &chunks);
  EXPECT_GT(chunks, 3);
  std::printf("  chunked surface job: %d chunks, max error/tol %.3g\n", chunks, err.maxRatio);
}

INSTANTIATE_TEST_SUITE_P(Precisions, GpuCurveSweep, ::testing::Values(Precision::Float, Precision::Double),
                         [](const auto& i) { return std::string(i.param == Precision::Double ? "fp64" : "fp32"); });
INSTANTIATE_TEST_SUITE_P(Precisions, GpuSurfaceSweep, ::testing::Values(Precision::Float, Precision::Double),
                         [](const auto& i) { return std::string(i.param == Precision::Double ? "fp64" : "fp32"); });

}  // namespace
}  // namespace shapespline::test
