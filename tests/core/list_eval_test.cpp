// The lean list kernel (core/list_eval.h) against the full evaluation: for every construction
// family, open and closed, plain and rational, each field it computes has the bits of
// Curve/Surface::evaluate and evaluateAt, in lists laid out in rows (intervals and bases reused)
// and shuffled (every lookup fresh); and a query outside the model is named by its index.
#include <gtest/gtest.h>

#include <shapespline/core/list_eval.h>

#include "support/test_models.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace shapespline {
namespace {

using glm::dvec3;

// The same bits, where a NaN counts as itself whatever its sign: a derivative of a knot interval
// near 1e-310 overflows into inf - inf on both paths, and the sign of that NaN depends on how the
// compiler arranged a negation, not on the arithmetic.
bool sameOrBothNaN(const dvec3& a, const dvec3& b) {
  for (int k = 0; k < 3; ++k)
    if (!(std::isnan(a[k]) && std::isnan(b[k])) && std::memcmp(&a[k], &b[k], sizeof(double)) != 0) return false;
  return true;
}

std::string listText(const dvec3& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g)", v.x, v.y, v.z);
  return buf;
}

// Parameters of one direction: both ends, every interval's interior and the interval ends.
std::vector<double> listSweep(double lo, double hi, int intervals) {
  std::vector<double> t;
  const int n = 4 * intervals + 1;
  for (int k = 0; k <= n; ++k) t.push_back(lo + (hi - lo) * k / n);
  for (int k = 0; k <= intervals; ++k) t.push_back(lo + (hi - lo) * k / intervals);
  return t;
}

template <class Q>
std::vector<Q> listShuffled(std::vector<Q> q) {
  std::mt19937 rng(11);
  std::shuffle(q.begin(), q.end(), rng);
  return q;
}

void expectSurfaceLean(const Surface& s, const std::string& label) {
  std::vector<SurfaceQuery> queries;
  const PatchRange r = s.patches();
  const double local[] = {0.0, 1.0 / 3.0, 0.5, 0.75, 1.0};
  for (int i = r.u.first; i <= r.u.last; ++i)
    for (int j = r.v.first; j <= r.v.last; ++j) {
      if (s.usesKnotVector() && (!(s.knotData().knotsU[i + 1] > s.knotData().knotsU[i]) ||
                                 !(s.knotData().knotsV[j + 1] > s.knotData().knotsV[j])))
        continue;  // empty knot intervals are refused (below)
      for (double u : local)
        for (double v : local) queries.push_back({false, i, j, u, v});
    }
  const auto [u0, u1] = s.parameterRangeU();
  const auto [v0, v1] = s.parameterRangeV();
  for (double U : listSweep(u0, u1, r.u.last - r.u.first + 1))
    for (double V : listSweep(v0, v1, r.v.last - r.v.first + 1)) queries.push_back({true, 0, 0, U, V});
  for (const auto& list : {queries, listShuffled(queries)}) {
    std::vector<SurfaceFirst> first(list.size()), point(list.size());
    evaluateList(s, list, ListFields::FirstDerivatives, first);
    evaluateList(s, list, ListFields::Point, point);
    for (size_t k = 0; k < list.size(); ++k) {
      const SurfaceQuery& q = list[k];
      const SurfacePoint full = q.global ? s.evaluateAt(q.u, q.v) : s.evaluate(q.i, q.j, q.u, q.v);
      const std::string at = label + (q.global ? " at (U, V) = (" : " at patch (" + std::to_string(q.i) + ", " +
                                                                       std::to_string(q.j) + "), (u, v) = (") +
                             std::to_string(q.u) + ", " + std::to_string(q.v) + ")";
      ASSERT_TRUE(sameOrBothNaN(first[k].point, full.point)) << at << ": " << listText(first[k].point) << " vs " << listText(full.point);
      ASSERT_TRUE(sameOrBothNaN(first[k].du, full.du)) << at << " du: " << listText(first[k].du) << " vs " << listText(full.du);
      ASSERT_TRUE(sameOrBothNaN(first[k].dv, full.dv)) << at << " dv: " << listText(first[k].dv) << " vs " << listText(full.dv);
      ASSERT_TRUE(sameOrBothNaN(point[k].point, full.point)) << at << " (point alone)";
      EXPECT_TRUE(sameOrBothNaN(point[k].du, dvec3(0.0))) << at << ": du was not asked for";
    }
  }
}

void expectCurveLean(const Curve& c, const std::string& label) {
  std::vector<CurveQuery> queries;
  const SpanRange r = c.spans();
  for (int j = r.first; j <= r.last; ++j) {
    if (c.usesKnotVector() && !(c.knotData().knots[j + 1] > c.knotData().knots[j])) continue;
    for (double t : {0.0, 0.2, 0.5, 0.9, 1.0}) queries.push_back({false, j, t, 0.0});
  }
  const auto [lo, hi] = c.parameterRange();
  for (double u : listSweep(lo, hi, r.last - r.first + 1)) queries.push_back({true, 0, 0.0, u});
  for (const auto& list : {queries, listShuffled(queries)}) {
    std::vector<CurveFirst> first(list.size()), point(list.size());
    evaluateList(c, list, ListFields::FirstDerivatives, first);
    evaluateList(c, list, ListFields::Point, point);
    for (size_t k = 0; k < list.size(); ++k) {
      const CurveQuery& q = list[k];
      const CurvePoint full = q.global ? c.evaluateAt(q.u) : c.evaluate(q.span, q.t);
      const std::string at = label + (q.global ? " at u = " + std::to_string(q.u)
                                               : " at span " + std::to_string(q.span) + ", t = " + std::to_string(q.t));
      ASSERT_TRUE(sameOrBothNaN(first[k].point, full.point)) << at << ": " << listText(first[k].point) << " vs " << listText(full.point);
      ASSERT_TRUE(sameOrBothNaN(first[k].d1, full.d1)) << at << " d1: " << listText(first[k].d1) << " vs " << listText(full.d1);
      ASSERT_TRUE(sameOrBothNaN(point[k].point, full.point)) << at << " (point alone)";
    }
  }
}

struct SurfaceCase {
  FamilySpec family;
  bool alpha;
};

TEST(ListEval, SurfacesOfEveryFamilyHaveTheFullPathsBits) {
  const SurfaceCase cases[] = {
      {{Construction::ExtendedBSpline, 4, 0, 0.0, {}}, false}, {{Construction::ExtendedBSpline, 6, 0, -3.0, {}}, false},
      {{Construction::GB, 0, 0, 7.0, {}}, false},               {{Construction::UBP, 0, 5, -4.0, {}}, false},
      {{Construction::GUBP, 0, 5, 0.0, {0.1, 0.6, 0.3}}, false}, {{Construction::AlphaEB, 5, 0, -2.0, {}}, true},
      {{Construction::AlphaEB, 4, 0, 1.0, {}}, true},           {{Construction::BSpline, 0, 4, 0.0, {}}, false},
  };
  for (const SurfaceCase& c : cases) {
    const SurfaceModel m = test::wavyNet(c.family, 7, c.alpha);
    expectSurfaceLean(Surface::create(m), std::string(constructionName(c.family.construction)));
  }
  expectSurfaceLean(Surface::create(test::alphaEBTube(6, 8)), "closed alpha-EB tube");
  expectSurfaceLean(Surface::create(test::nurbsTorus(2.0, 0.5)), "NURBS torus (repeated knots)");
}

TEST(ListEval, KnotVectorSurfacesWithTinyIntervalsAndRepeatedKnots) {
  SurfaceModel m = test::wavyNet({Construction::BSpline, 0, 3, 0.0, {}}, 7, false);
  m.orderV = 4;
  m.knotsU = {0, 0, 0, 1e-320, 0.25, 0.25, 0.7, 1, 1, 1};             // order 3, 7 points; a subnormal interval
  m.knotsV = {-2, -2, -2, -2, -1, -1, 0.5, 3, 3, 3, 3};               // order 4, 7 points; a double knot
  expectSurfaceLean(Surface::create(m), "B-spline, tiny and repeated knots");
  m.weights.assign(m.points.size(), 1.0);
  for (size_t k = 0; k < m.weights.size(); ++k) m.weights[k] = 0.5 + 0.1 * static_cast<double>(k % 7);
  expectSurfaceLean(Surface::create(m), "NURBS, tiny and repeated knots");
}

TEST(ListEval, CurvesOfEveryFamilyHaveTheFullPathsBits) {
  struct Case {
    FamilySpec family;
    bool closed, knots, rational;
  };
  const Case cases[] = {
      {{Construction::ExtendedBSpline, 5, 0, -3.0, {}}, false, false, false},
      {{Construction::ExtendedBSpline, 6, 0, 0.5, {}}, true, false, false},
      {{Construction::GB, 0, 0, 7.0, {}}, false, true, false},
      {{Construction::UBP, 0, 7, -4.0, {}}, false, false, false},
      {{Construction::GUBP, 0, 5, 0.0, {0.1, 0.6, 0.3}}, true, false, false},
      {{Construction::AlphaEB, 4, 0, -2.0, {}}, false, false, false},
      {{Construction::AlphaEB, 6, 0, 1.0, {}}, true, false, false},
      {{Construction::BSpline, 0, 4, 0.0, {}}, false, true, false},
      {{Construction::BSpline, 0, 4, 0.0, {}}, false, true, true},
  };
  for (const Case& c : cases) {
    CurveModel m;
    m.family = c.family;
    m.closed = c.closed;
    m.dimension = 3;
    for (int i = 0; i < 9; ++i) m.points.emplace_back(i + 0.3 * std::sin(3.0 * i), std::cos(1.7 * i), 0.2 * i * i);
    if (c.family.construction == Construction::AlphaEB)
      for (int i = 0; i < 9; ++i) m.alpha.push_back(0.1 + 0.1 * i);
    if (c.knots && c.family.construction == Construction::BSpline)
      m.knots = {0, 0, 0, 0, 0.1, 0.3, 0.3, 0.5, 0.8, 1, 1, 1, 1};
    else if (c.knots)
      m.knots = {0, 0.5, 2, 2.25, 4, 4.5, 7};
    if (c.rational)
      for (int i = 0; i < 9; ++i) m.weights.push_back(0.4 + 0.15 * i);
    expectCurveLean(Curve::create(m), std::string(constructionName(c.family.construction)) +
                                          (c.closed ? " closed" : "") + (c.rational ? " rational" : ""));
  }
  expectCurveLean(Curve::create(test::nurbsCircle(2.0)), "NURBS circle");
}

TEST(ListEval, TheIntervalHintNeverChangesTheSpan) {
  const std::vector<double> knots = {0, 0, 0, 0.5, 0.5, 1, 2, 2, 3, 3, 3};  // order 3, 8 points
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> t(-0.5, 3.5);
  std::vector<double> ts = {0, 0.5, 1, 2, 3, std::nextafter(0.5, 0.0), std::nextafter(2.0, 3.0), -1, 4};
  for (int k = 0; k < 200; ++k) ts.push_back(t(rng));
  for (double x : ts)
    for (int hint = -1; hint <= 9; ++hint)
      EXPECT_EQ(findKnotSpanFrom(hint, 3, knots, 8, x), findKnotSpan(3, knots, 8, x)) << "t = " << x << ", hint " << hint;
}

TEST(ListEval, AQueryOutsideTheModelIsNamedByItsIndex) {
  const Surface s = Surface::create(test::nurbsTorus(2.0, 0.5));
  const std::vector<SurfaceQuery> q = {{true, 0, 0, 0.5, 0.5}, {false, 2, 2, 0.5, 1.5}, {true, 0, 0, 2.0, 0.0}};
  std::vector<SurfaceFirst> out(q.size());
  try {
    evaluateList(s, q, ListFields::FirstDerivatives, out);
    FAIL() << "expected QueryRangeError";
  } catch (const QueryRangeError& e) {
    EXPECT_EQ(e.index(), 1u);
    EXPECT_NE(std::string(e.what()).find("v = 1.5"), std::string::npos) << e.what();
  }
  const std::vector<SurfaceQuery> global = {{true, 0, 0, 0.5, 0.5}, {true, 0, 0, 2.0, 0.0}};
  std::vector<SurfaceFirst> two(2);
  try {
    evaluateList(s, global, ListFields::Point, two);
    FAIL() << "expected QueryRangeError";
  } catch (const QueryRangeError& e) {
    EXPECT_EQ(e.index(), 1u);
  }
  std::vector<SurfaceFirst> wrongSize(1);
  EXPECT_THROW(evaluateList(s, global, ListFields::Point, wrongSize), std::invalid_argument);
}

// Which list evaluation serves a field mask, and back: only the point and first derivatives.
TEST(ListFieldsFor, ThePointAndFirstDerivativesAtMost) {
  EXPECT_EQ(listFieldsFor(fieldBit(Field::Point), false), ListFields::Point);
  EXPECT_EQ(listFieldsFor(fieldBit(Field::Point) | fieldBit(Field::D1), false), ListFields::FirstDerivatives);
  EXPECT_EQ(listFieldsFor(fieldBit(Field::Point) | fieldBit(Field::D2), false), std::nullopt);
  EXPECT_EQ(listFieldsFor(fieldBit(Field::Point) | fieldBit(Field::Dv), true), ListFields::FirstDerivatives);
  EXPECT_EQ(listFieldsFor(fieldBit(Field::Point) | fieldBit(Field::Normal), true), std::nullopt);
  EXPECT_EQ(listFieldsFor(fieldBit(Field::Duv), true), std::nullopt);
  EXPECT_EQ(listFieldsFor(fieldBit(Field::D1), true), std::nullopt);  // a curve's field on a surface
  for (bool surface : {false, true})
    for (ListFields f : {ListFields::Point, ListFields::FirstDerivatives})
      EXPECT_EQ(listFieldsFor(fieldMaskOf(f, surface), surface), f);
  const SurfacePoint p = pointOf(SurfaceFirst{glm::dvec3(1.0), glm::dvec3(2.0), glm::dvec3(3.0)});
  EXPECT_EQ(p.dv, glm::dvec3(3.0));
  EXPECT_EQ(p.duu, glm::dvec3(0.0));
  EXPECT_EQ(p.normal, glm::dvec3(0.0));
}

}  // namespace
}  // namespace shapespline
