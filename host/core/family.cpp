#include <shapespline/core/family.h>

#include <shapespline/core/model.h>
#include <shapespline/core/span_basis.h>

#include <array>

namespace shapespline {

namespace {

SpanBasis xuWangBasis(const FamilySpec& f) { return xuWangSpanBasis(f.degree, f.lambda); }
SpanBasis gbBasis(const FamilySpec& f) { return gbSpanBasis(f.lambda); }
SpanBasis ubpBasis(const FamilySpec& f) { return ubpSpanBasis(f.order, f.lambda); }
SpanBasis gubpBasis(const FamilySpec& f) { return gubpSpanBasis(f.order, f.mu); }
SpanBasis bsplineBasis(const FamilySpec& f) { return uniformBSplineSpanBasis(f.order); }

// clang-format off
constexpr std::array<FamilyTraits, 6> kFamilies = {{
  //  construction                   name                degree order min  lambda mu    alpha  spanKn knotV  2ord  minPts basis
  {Construction::ExtendedBSpline, "extended_bspline", true,  false, 0, true,  false, false, true,  false, false, 4, xuWangBasis},
  {Construction::AlphaEB,         "alpha_eb",         true,  false, 0, true,  false, true,  false, false, false, 2, xuWangBasis},
  {Construction::GB,              "gb",               false, false, 0, true,  false, false, true,  false, false, 4, gbBasis},
  {Construction::UBP,             "ubp",              false, true,  3, true,  false, false, false, false, false, 0, ubpBasis},
  {Construction::GUBP,            "gubp",             false, true,  3, false, true,  false, false, false, false, 0, gubpBasis},
  {Construction::BSpline,         "bspline",          false, true,  2, false, false, false, false, true,  true,  0, bsplineBasis},
}};
// clang-format on

constexpr bool rowsInEnumOrder() {
  for (size_t i = 0; i < kFamilies.size(); ++i)
    if (static_cast<size_t>(kFamilies[i].construction) != i) return false;
  return true;
}
static_assert(rowsInEnumOrder(), "familyOf indexes kFamilies by the enum value");

}  // namespace

std::span<const FamilyTraits> families() { return kFamilies; }

const FamilyTraits& familyOf(Construction c) { return kFamilies[static_cast<size_t>(c)]; }

const FamilyTraits* familyNamed(std::string_view name) {
  for (const FamilyTraits& f : kFamilies)
    if (f.name == name) return &f;
  return nullptr;
}

std::string_view constructionName(Construction c) { return familyOf(c).name; }

Parameterization parameterizationOf(Construction c, bool hasKnotVector) {
  const FamilyTraits& f = familyOf(c);
  if (f.knotVectors && hasKnotVector) return Parameterization::KnotVector;
  return f.usesAlpha ? Parameterization::AlphaEB : Parameterization::LocalSpans;
}

}  // namespace shapespline
