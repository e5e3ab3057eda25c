#pragma once
// The closed set of constructions (docs/math.md §1–§10) and, in one table, what each one is: its
// name in model files, the model keys it reads, how many points a direction needs, and how its span
// basis is built. Layers ask this table (and Curve/Surface::parameterization()) instead of testing
// constructions one by one, so adding a family is one row here plus its basis.
#include <span>
#include <string_view>

namespace shapespline {

enum class Construction { ExtendedBSpline, AlphaEB, GB, UBP, GUBP, BSpline };

// How a model's parameter reaches its spans or patches; decided once, by Curve/Surface::create.
enum class Parameterization {
  LocalSpans,  // a local basis on unit spans (global u = span + t; curves may carry span knots)
  AlphaEB,     // the Xu–Wang basis blended towards the V points (docs/math.md §4, §5)
  KnotVector,  // a B-spline on a full knot vector (docs/math.md §10.1)
};

struct FamilySpec;
struct SpanBasis;

struct FamilyTraits {
  Construction construction;
  std::string_view name;      // as spelled in model files
  bool usesDegree;            // Xu–Wang degree 4..6
  bool usesOrder;             // an order k (minOrder..10)
  int minOrder;
  bool usesLambda;
  bool usesMu;                // GUBP's half vector μ
  bool usesAlpha;             // one tension α per point
  bool spanKnots;             // curves may carry span boundaries (docs/math.md §1, R3)
  bool knotVectors;           // curves and surfaces may carry full knot vectors
  bool twoOrders;             // surfaces take [order_u, order_v]
  int minOpenPoints;          // fewest points of an open direction (0: the order); closed: 3
  SpanBasis (*spanBasis)(const FamilySpec&);
};

// Every construction, in enum order.
std::span<const FamilyTraits> families();
const FamilyTraits& familyOf(Construction c);
// The row whose name is `name`, or nullptr.
const FamilyTraits* familyNamed(std::string_view name);
// "extended_bspline", "alpha_eb", ... as spelled in model files.
std::string_view constructionName(Construction c);
// The parameterization of a model of construction c (hasKnotVector: it carries full knot vectors).
Parameterization parameterizationOf(Construction c, bool hasKnotVector);

}  // namespace shapespline
