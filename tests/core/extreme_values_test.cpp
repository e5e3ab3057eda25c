// Extreme but valid inputs (issue 7): coordinates near 1e30 and 1e-30, coincident control points,
// λ/μ at both ends of each family's range, α = 1e-12 and α = 1. The CPU sampler (every field,
// normals included) and the typed evaluators must give only finite numbers, normals must be unit
// vectors that do not depend on the scale of the net, and core/diagnostics.h must warn exactly where
// precision is lost.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <shapespline/core/diagnostics.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/validate.h>

#include <glm/geometric.hpp>

namespace shapespline {
namespace {

using glm::dvec3;

// Normals of a net scaled by a power of ten agree with the unscaled ones to this (angle in radians).
constexpr double kNormalScaleTolerance = 1e-9;

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

bool finite(const dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Every field of every chunk, as doubles; fails the test at the first non-finite value.
struct Samples {
  std::vector<double> field[kFieldCount];
  ChunkConsumer consumer(const std::string& label) {
    return [this, label](const GridChunk& c) {
      for (int f = 0; f < kFieldCount; ++f) {
        if (!c.planes[f]) continue;
        for (size_t p = 0; p < c.pointCount(); ++p)
          for (int a = 0; a < 3; ++a) {
            const double x = c.coord(static_cast<Field>(f), p, a);
            field[f].push_back(x);
            ASSERT_TRUE(std::isfinite(x)) << label << ": field " << f << " item " << c.firstItem
                                          << " point " << p << " axis " << a << " = " << x;
          }
      }
    };
  }
};

// The families with the ends of their parameter ranges (docs/math.md §11): name, spec.
struct ExtremeFamilyCase {
  std::string name;
  FamilySpec spec;
};

std::vector<ExtremeFamilyCase> familyEnds(bool forAlphaEB) {
  std::vector<ExtremeFamilyCase> out;
  for (int k = 4; k <= 6; ++k)
    for (double lambda : {-double(k * (k - 2)), 1.0}) {
      FamilySpec f;
      f.construction = forAlphaEB ? Construction::AlphaEB : Construction::ExtendedBSpline;
      f.degree = k;
      f.lambda = lambda;
      out.push_back({(forAlphaEB ? "aeb_k" : "xw_k") + std::to_string(k) + "_lambda" + std::to_string(int(lambda)), f});
    }
  if (forAlphaEB) return out;
  // GB: λ ≥ -8, unbounded above: the lower end, a large λ and the largest double.
  for (double lambda : {-8.0, 1e6, DBL_MAX}) {
    FamilySpec f;
    f.construction = Construction::GB;
    f.lambda = lambda;
    out.push_back({"gb_lambda" + num(lambda), f});
  }
  for (int k : {3, 4, 7, 10})
    for (double lambda : {ubpLambdaMin(k), 1.0}) {
      FamilySpec f;
      f.construction = Construction::UBP;
      f.order = k;
      f.lambda = lambda;
      out.push_back({"ubp_k" + std::to_string(k) + "_lambda" + num(lambda), f});
    }
  // GUBP with μ at the ends of [0,1] (both parity sums 1, §9).
  for (auto [k, mu] : std::vector<std::pair<int, std::vector<double>>>{
           {4, {0.0, 0.5, 1.0}}, {4, {0.5, 0.5, 0.0}}, {5, {0.0, 1.0, 0.0}}, {5, {0.5, 0.0, 0.5}}}) {
    FamilySpec f;
    f.construction = Construction::GUBP;
    f.order = k;
    f.mu = mu;
    out.push_back({"gubp_k" + std::to_string(k) + "_mu" + num(mu[0]), f});
  }
  for (int k : {2, 4, 10}) {
    FamilySpec f;
    f.construction = Construction::BSpline;
    f.order = k;
    out.push_back({"bspline_k" + std::to_string(k), f});
  }
  return out;
}

bool hugeGBLambda(const FamilySpec& f) { return f.construction == Construction::GB && f.lambda > kGBLambdaWarn; }

// A wavy 3-D polygon of n points with coordinates of order `scale`.
std::vector<dvec3> wavyPoints(int n, double scale) {
  std::vector<dvec3> p;
  for (int i = 0; i < n; ++i)
    p.emplace_back(scale * (i + 0.25 * std::sin(1.7 * i)), scale * 2.0 * std::cos(0.9 * i),
                   scale * 0.5 * std::sin(2.3 * i));
  return p;
}

std::vector<dvec3> scaled(std::vector<dvec3> p, double s) {
  for (auto& x : p) x *= s;
  return p;
}

CurveModel curveModel(const FamilySpec& f, std::vector<dvec3> points, bool closed, double alpha) {
  CurveModel m;
  m.family = f;
  m.closed = closed;
  m.dimension = 3;
  m.points = std::move(points);
  if (f.construction == Construction::AlphaEB) m.alpha.assign(m.points.size(), alpha);
  return m;
}

SurfaceModel surfaceModel(const FamilySpec& f, int rows, int cols, double scale, bool cu, bool cv, double alpha) {
  SurfaceModel m;
  m.family = f;
  m.orderV = f.order;
  rows = std::max(rows, f.order), cols = std::max(cols, f.order);  // open order-k directions need k points
  m.rows = rows, m.cols = cols, m.closedU = cu, m.closedV = cv;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const dvec3 p(i + 0.2 * std::sin(1.3 * j), j + 0.1 * std::cos(0.7 * i), 0.3 * std::sin(1.1 * i + 0.6 * j));
      m.points.push_back(scale * p);
    }
  if (f.construction == Construction::AlphaEB) m.alpha.assign(m.points.size(), alpha);
  return m;
}

Samples sampleCurve(const CurveModel& model, const std::string& label) {
  const Curve curve = Curve::create(model);
  Samples s;
  GridSpec grid;
  grid.samplesU = 9;
  sampleCurveGrid(curve, grid, kCurveFields, s.consumer(label), {.threads = 1});
  const auto [lo, hi] = curve.parameterRange();
  for (double u : {lo, hi}) {
    const CurvePoint p = curve.evaluateAt(u);
    EXPECT_TRUE(finite(p.point) && finite(p.d1) && finite(p.d2)) << label << " at u = " << u;
  }
  return s;
}

Samples sampleSurface(const SurfaceModel& model, const std::string& label) {
  const Surface surface = Surface::create(model);
  Samples s;
  GridSpec grid;
  grid.samplesU = 5;
  grid.samplesV = 5;
  sampleSurfaceGrid(surface, grid, kSurfaceFields, s.consumer(label), {.threads = 1});
  const auto& n = s.field[int(Field::Normal)];
  for (size_t k = 0; k + 2 < n.size(); k += 3)
    EXPECT_NEAR(std::hypot(n[k], n[k + 1], n[k + 2]), 1.0, 1e-12) << label << ": normal " << k / 3;
  return s;
}

size_t countFields(const std::vector<Warning>& ws, const std::string& prefix) {
  size_t n = 0;
  for (const auto& w : ws) n += w.field.rfind(prefix, 0) == 0;
  return n;
}

// ---- Curves -------------------------------------------------------------------------------------

TEST(ExtremeValues, CurvesAtParameterEndsAndExtremeScalesStayFinite) {
  for (const auto& fc : familyEnds(false))
    for (bool closed : {false, true}) {
      if (closed && fc.spec.construction == Construction::BSpline) continue;  // bspline: open only
      for (double scale : {1.0, 1e30, 1e-30, 1e-100, 1e100}) {
        const std::string label = fc.name + (closed ? " closed" : " open") + " scale " + num(scale);
        sampleCurve(curveModel(fc.spec, wavyPoints(12, scale), closed, 1.0), label);
        if (HasFatalFailure()) return;
      }
    }
}

TEST(ExtremeValues, AlphaEBCurvesWithTinyAndUnitAlphaStayFinite) {
  for (const auto& fc : familyEnds(true))
    for (bool closed : {false, true})
      for (double alpha : {1e-12, 1e-6, 1.0})
        for (double scale : {1.0, 1e30, 1e-30}) {
          const std::string label = fc.name + (closed ? " closed" : " open") + " alpha " + num(alpha) +
                                    " scale " + num(scale);
          sampleCurve(curveModel(fc.spec, wavyPoints(7, scale), closed, alpha), label);
          if (HasFatalFailure()) return;
        }
}

TEST(ExtremeValues, CoincidentCurvePointsStayFinite) {
  for (const auto& fc : familyEnds(false)) {
    // All points equal; and every point doubled.
    std::vector<dvec3> same(10, dvec3(1.5, -2.0, 3.0)), doubled;
    for (const auto& p : wavyPoints(6, 1.0)) doubled.push_back(p), doubled.push_back(p);
    for (bool closed : {false, true}) {
      if (closed && fc.spec.construction == Construction::BSpline) continue;
      const Samples s = sampleCurve(curveModel(fc.spec, same, closed, 1.0), fc.name + " all coincident");
      if (HasFatalFailure()) return;
      // Partition of unity: a curve over one repeated point is that point (derivatives 0).
      const auto& pts = s.field[int(Field::Point)];
      for (size_t k = 0; k + 2 < pts.size(); k += 3)
        EXPECT_NEAR(pts[k + 1], -2.0, 1e-9) << fc.name << " sample " << k / 3;
      sampleCurve(curveModel(fc.spec, doubled, closed, 1.0), fc.name + " doubled points");
      if (HasFatalFailure()) return;
    }
  }
  for (const auto& fc : familyEnds(true))
    for (double alpha : {1e-12, 1.0}) {
      std::vector<dvec3> same(5, dvec3(1e30, 0.0, -1e30)), pairs = {dvec3(0), dvec3(0), dvec3(1, 0, 0), dvec3(1, 0, 0)};
      for (bool closed : {false, true}) {
        sampleCurve(curveModel(fc.spec, same, closed, alpha), fc.name + " alpha-eb all coincident");
        sampleCurve(curveModel(fc.spec, pairs, closed, alpha), fc.name + " alpha-eb coincident pairs");
        if (HasFatalFailure()) return;
      }
    }
}

TEST(ExtremeValues, CurveSamplesScaleExactlyWithPowersOfTwo) {
  // Scaling the net by 2^100 / 2^-100 scales every field by exactly that factor (no overflow or
  // underflow on the way), the strongest check that nothing is lost at large and small scales.
  for (const auto& fc : familyEnds(false)) {
    if (hugeGBLambda(fc.spec)) continue;  // weights near 1e-308 underflow at 2^-100: see the GB test
    const auto base = wavyPoints(12, 1.0);
    const Samples ref = sampleCurve(curveModel(fc.spec, base, false, 1.0), fc.name);
    for (int e : {100, -100}) {
      const Samples s = sampleCurve(curveModel(fc.spec, scaled(base, std::ldexp(1.0, e)), false, 1.0), fc.name);
      for (int f = 0; f < kFieldCount; ++f)
        for (size_t k = 0; k < ref.field[f].size(); ++k)
          ASSERT_EQ(std::ldexp(ref.field[f][k], e), s.field[f][k]) << fc.name << " field " << f << " value " << k;
    }
  }
}

TEST(ExtremeValues, GBAtHugeLambdaApproachesItsLimit) {
  // docs/math.md §7.1: as λ → ∞ the GB span tends to E(t) = (1-h)P_j + h P_{j+1}, h = 3t² - 2t³.
  const auto pts = wavyPoints(6, 1.0);
  for (double lambda : {1e15, 1e100, DBL_MAX}) {
    FamilySpec f;
    f.construction = Construction::GB;
    f.lambda = lambda;
    const Curve c = Curve::create(curveModel(f, pts, false, 1.0));
    for (double t : {0.0, 0.3, 1.0}) {
      const CurvePoint p = c.evaluate(1, t);
      const double h = 3 * t * t - 2 * t * t * t;
      const dvec3 e = (1 - h) * pts[1] + h * pts[2];
      ASSERT_TRUE(finite(p.point) && finite(p.d1) && finite(p.d2)) << "lambda " << lambda << " t " << t;
      EXPECT_LT(glm::length(p.point - e), 1e-12) << "lambda " << lambda << " t " << t;
    }
  }
}

// ---- Surfaces -----------------------------------------------------------------------------------

std::vector<ExtremeFamilyCase> surfaceFamilies() {
  std::vector<ExtremeFamilyCase> out;
  for (const auto& fc : familyEnds(false))
    if (fc.spec.construction != Construction::BSpline || fc.spec.order <= 4) out.push_back(fc);
  for (const auto& fc : familyEnds(true)) out.push_back(fc);
  return out;
}

TEST(ExtremeValues, SurfacesAtParameterEndsAndExtremeScalesStayFinite) {
  for (const auto& fc : surfaceFamilies()) {
    const bool aeb = fc.spec.construction == Construction::AlphaEB;
    const bool bspline = fc.spec.construction == Construction::BSpline;
    for (auto [cu, cv] : {std::pair{false, false}, std::pair{true, false}, std::pair{true, true}}) {
      if (bspline && (cu || cv)) continue;
      for (double alpha : aeb ? std::vector<double>{1e-12, 1.0} : std::vector<double>{1.0})
        for (double scale : {1e30, 1e-30, 1e100, 1e-100}) {
          const std::string label = fc.name + " closed " + std::to_string(cu) + std::to_string(cv) + " alpha " +
                                    num(alpha) + " scale " + num(scale);
          sampleSurface(surfaceModel(fc.spec, 5, 6, scale, cu, cv, alpha), label);
          if (HasFatalFailure()) return;
        }
    }
  }
}

TEST(ExtremeValues, SurfaceNormalsDoNotDependOnTheScale) {
  for (const auto& fc : surfaceFamilies()) {
    // GB at λ = DBL_MAX (warned) has weights near 1e-308 that underflow against a 1e-100 net.
    if (hugeGBLambda(fc.spec)) continue;
    const bool aeb = fc.spec.construction == Construction::AlphaEB;
    for (double alpha : aeb ? std::vector<double>{0.5, 1.0} : std::vector<double>{1.0}) {
      const Samples ref = sampleSurface(surfaceModel(fc.spec, 5, 6, 1.0, false, false, alpha), fc.name);
      for (double scale : {1e30, 1e-30, 1e100, 1e-100, 1e140, 1e-140}) {
        const std::string label = fc.name + " alpha " + num(alpha) + " scale " + num(scale);
        const Samples s = sampleSurface(surfaceModel(fc.spec, 5, 6, scale, false, false, alpha), label);
        if (HasFatalFailure()) return;
        const auto& a = ref.field[int(Field::Normal)];
        const auto& b = s.field[int(Field::Normal)];
        ASSERT_EQ(a.size(), b.size());
        double worst = 0.0;
        size_t where = 0;
        for (size_t k = 0; k + 2 < a.size(); k += 3) {
          const double d = glm::length(dvec3(a[k], a[k + 1], a[k + 2]) - dvec3(b[k], b[k + 1], b[k + 2]));
          if (d > worst) worst = d, where = k / 3;
        }
        EXPECT_LT(worst, kNormalScaleTolerance) << label << ": normal " << where;
      }
    }
  }
}

TEST(ExtremeValues, CoincidentSurfacePointsGiveFiniteUnitNormals) {
  for (const auto& fc : surfaceFamilies()) {
    const bool aeb = fc.spec.construction == Construction::AlphaEB;
    for (double alpha : aeb ? std::vector<double>{1e-12, 1.0} : std::vector<double>{1.0}) {
      SurfaceModel all = surfaceModel(fc.spec, 4, 5, 1.0, false, false, alpha);
      for (auto& p : all.points) p = dvec3(2.0, -1.0, 1e-30);
      sampleSurface(all, fc.name + " all coincident");
      // Two rows collapsed onto one line, and one collapsed row (a pole).
      SurfaceModel pole = surfaceModel(fc.spec, 5, 5, 1e30, false, false, alpha);
      for (int j = 0; j < pole.cols; ++j) pole.points[j] = dvec3(0.0, 0.0, 1e30);
      sampleSurface(pole, fc.name + " pole row");
      if (HasFatalFailure()) return;
    }
  }
}

// ---- Warnings -----------------------------------------------------------------------------------

TEST(PrecisionWarnings, NoneForOrdinaryModelsAndAtTheIssueExtremes) {
  // 1e30, 1e-30, λ ends and α = 1 lose no precision worth a warning.
  for (const auto& fc : familyEnds(false)) {
    if (hugeGBLambda(fc.spec)) continue;
    for (double scale : {1.0, 1e30, 1e-30}) {
      EXPECT_TRUE(precisionWarnings(curveModel(fc.spec, wavyPoints(8, scale), false, 1.0)).empty()) << fc.name;
    }
  }
  for (const auto& fc : surfaceFamilies()) {
    if (hugeGBLambda(fc.spec)) continue;
    EXPECT_TRUE(precisionWarnings(surfaceModel(fc.spec, 5, 5, 1e-30, false, false, 1.0)).empty()) << fc.name;
  }
}

TEST(PrecisionWarnings, TinyAlphaIsNamedWithItsIndex) {
  FamilySpec f;
  f.construction = Construction::AlphaEB;
  f.degree = 4;
  CurveModel m = curveModel(f, wavyPoints(6, 1.0), false, 0.5);
  m.alpha[3] = 1e-12;
  const auto ws = precisionWarnings(m);
  ASSERT_EQ(ws.size(), 1u);
  EXPECT_EQ(ws[0].field, "alpha[3]");
  EXPECT_NE(ws[0].message.find("1e-12"), std::string::npos) << ws[0].message;
  EXPECT_NE(formatWarning(ws[0]).find("warning: alpha[3]: "), std::string::npos);

  SurfaceModel s = surfaceModel(f, 4, 5, 1.0, false, false, 1.0);
  s.alpha[2 * 5 + 1] = 1e-9;
  const auto wss = precisionWarnings(s);
  ASSERT_EQ(wss.size(), 1u);
  EXPECT_EQ(wss[0].field, "alpha[2][1]");
}

TEST(PrecisionWarnings, HugeTinyAndFarAwayNets) {
  FamilySpec f;
  f.construction = Construction::ExtendedBSpline;
  f.degree = 5;
  CurveModel huge = curveModel(f, wavyPoints(6, 1.0), false, 1.0);
  huge.points[4].y = -3e200;
  auto ws = precisionWarnings(huge);
  ASSERT_EQ(countFields(ws, "points[4][1]"), 1u) << (ws.empty() ? "" : ws[0].field);

  const auto tiny = precisionWarnings(curveModel(f, wavyPoints(6, 1e-200), false, 1.0));
  EXPECT_EQ(countFields(tiny, "points"), 1u);

  // A shape of size 1e-3 placed 1e20 from the origin keeps about 7 digits: warned.
  CurveModel far = curveModel(f, wavyPoints(6, 1e-3), false, 1.0);
  for (auto& p : far.points) p.x += 1e20;
  EXPECT_EQ(countFields(precisionWarnings(far), "points"), 1u);
}

TEST(PrecisionWarnings, NarrowKnotIntervalsAndHugeGBLambda) {
  FamilySpec f;
  f.construction = Construction::GB;
  f.lambda = 0.0;
  CurveModel m = curveModel(f, wavyPoints(6, 1.0), false, 1.0);
  m.knots = {0.0, 1.0, 1.0 + 1e-14, 3.0};
  validateCurve(m);
  auto ws = precisionWarnings(m);
  ASSERT_EQ(ws.size(), 1u);
  EXPECT_EQ(ws[0].field, "knots[2]");

  m.knots.clear();
  m.family.lambda = 1e20;
  ws = precisionWarnings(m);
  ASSERT_EQ(ws.size(), 1u);
  EXPECT_EQ(ws[0].field, "lambda");
}

}  // namespace
}  // namespace shapespline
