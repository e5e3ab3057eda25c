// The family table (core/family.h): one row per construction, found by name and by value, and the
// dispatch it drives (span bases, parameterizations, the model keys io reads) agrees with the
// per-construction functions it replaces.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include <shapespline/core/curve.h>
#include <shapespline/core/family.h>
#include <shapespline/core/model.h>
#include <shapespline/core/span_basis.h>
#include <shapespline/core/surface.h>

namespace shapespline {
namespace {

TEST(FamilyTable, EveryConstructionHasOneRowFoundByNameAndValue) {
  std::set<std::string> names;
  for (const FamilyTraits& f : families()) {
    EXPECT_EQ(&familyOf(f.construction), &f);
    ASSERT_NE(familyNamed(f.name), nullptr) << f.name;
    EXPECT_EQ(familyNamed(f.name)->construction, f.construction);
    EXPECT_EQ(constructionName(f.construction), f.name);
    EXPECT_TRUE(names.insert(std::string(f.name)).second) << "duplicate name " << f.name;
  }
  EXPECT_EQ(names.size(), 6u);
  EXPECT_EQ(familyNamed("nurbs"), nullptr);
  EXPECT_EQ(familyNamed(""), nullptr);
}

TEST(FamilyTable, SpanBasisDispatchEqualsTheDirectConstructors) {
  auto same = [](const SpanBasis& a, const SpanBasis& b) {
    ASSERT_EQ(a.count, b.count);
    ASSERT_EQ(a.degree, b.degree);
    for (int r = 0; r < a.count; ++r)
      for (int d = 0; d <= a.degree; ++d) EXPECT_EQ(a.coef[r][d], b.coef[r][d]) << r << "," << d;
  };
  FamilySpec f;
  f.construction = Construction::AlphaEB, f.degree = 5, f.lambda = -2.0;
  same(makeSpanBasis(f), xuWangSpanBasis(5, -2.0));
  f = {}, f.construction = Construction::GB, f.lambda = 3.0;
  same(makeSpanBasis(f), gbSpanBasis(3.0));
  f = {}, f.construction = Construction::UBP, f.order = 6, f.lambda = -4.0;
  same(makeSpanBasis(f), ubpSpanBasis(6, -4.0));
  f = {}, f.construction = Construction::GUBP, f.order = 4, f.mu = {0.25, 0.5, 0.5};
  same(makeSpanBasis(f), gubpSpanBasis(4, f.mu));
  f = {}, f.construction = Construction::BSpline, f.order = 3;
  same(makeSpanBasis(f), uniformBSplineSpanBasis(3));
}

TEST(FamilyTable, ParameterizationIsDecidedOnceByTheCoreObjects) {
  EXPECT_EQ(parameterizationOf(Construction::AlphaEB, false), Parameterization::AlphaEB);
  EXPECT_EQ(parameterizationOf(Construction::BSpline, true), Parameterization::KnotVector);
  EXPECT_EQ(parameterizationOf(Construction::BSpline, false), Parameterization::LocalSpans);
  // Span knots of extended_bspline/gb curves keep the span parameterization (docs/math.md §1).
  EXPECT_EQ(parameterizationOf(Construction::GB, true), Parameterization::LocalSpans);

  CurveModel c;
  c.family.construction = Construction::BSpline, c.family.order = 3;
  c.points = {{0, 0, 0}, {1, 1, 0}, {2, 0, 0}, {3, 1, 0}};
  EXPECT_EQ(Curve::create(c).parameterization(), Parameterization::LocalSpans);
  c.knots = {0, 0, 0, 0.4, 1, 1, 1};
  const Curve knotted = Curve::create(c);
  EXPECT_EQ(knotted.parameterization(), Parameterization::KnotVector);
  EXPECT_TRUE(knotted.usesKnotVector());

  SurfaceModel s;
  s.family.construction = Construction::AlphaEB, s.family.degree = 4;
  s.rows = s.cols = 3;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s.points.push_back({i, j, (i * j) % 2});
  s.alpha.assign(9, 0.5);
  EXPECT_EQ(Surface::create(s).parameterization(), Parameterization::AlphaEB);
}

}  // namespace
}  // namespace shapespline
