// The CPU grid sampler against the reference evaluators, and its determinism across thread
// counts, chunk sizes and item ranges.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/knot_table.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include "support/tolerances.h"

namespace shapespline {
namespace {

using glm::dvec3;

std::vector<dvec3> randomPoints(int n, unsigned seed, bool planar) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  std::vector<dvec3> p;
  for (int i = 0; i < n; ++i) p.emplace_back(i + 0.3 * d(rng), 2.0 * d(rng), planar ? 0.0 : d(rng));
  return p;
}

SurfaceModel gridSurface(FamilySpec family, int rows, int cols, bool cu, bool cv, unsigned seed) {
  SurfaceModel m;
  m.family = family;
  m.orderV = family.order;
  m.rows = rows, m.cols = cols, m.closedU = cu, m.closedV = cv;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-0.3, 0.3), al(0.05, 1.0);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const double a = 2 * M_PI * j / cols, b = 2 * M_PI * i / rows;
      dvec3 p = cv ? dvec3(std::cos(a) * 3, std::sin(a) * 3, i) : dvec3(i, j, 0.0);
      if (cu) p = dvec3(p.x + 3 * std::cos(b), p.y, 3 * std::sin(b));
      m.points.push_back(p + dvec3(d(rng), d(rng), d(rng)));
      if (family.construction == Construction::AlphaEB) m.alpha.push_back(al(rng));
    }
  return m;
}

double boxDiagonal(const std::vector<dvec3>& pts) {
  dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

// Collects every chunk's doubles, field by field, for byte comparisons.
struct Collected {
  std::vector<double> data[kFieldCount];
  size_t items = 0;      // items completed
  size_t itemPoint = 0;  // next point of item `items` (an item larger than a chunk comes in rows)
  ChunkConsumer consumer() {
    return [this](const GridChunk& c) {
      EXPECT_EQ(c.firstItem, items) << "chunks must arrive in item order";
      EXPECT_EQ(c.firstItemPoint(), itemPoint) << "row ranges must arrive in row order";
      if (c.endsItem()) {
        items += c.itemCount, itemPoint = 0;
      } else {
        itemPoint = c.firstItemPoint() + c.pointCount();
      }
      for (int f = 0; f < kFieldCount; ++f)
        if (c.planes[f]) {
          const auto* p = static_cast<const double*>(c.planes[f]);
          data[f].insert(data[f].end(), p, p + c.pointCount() * 3);
        }
    };
  }
};

void expectSameBytes(const Collected& a, const Collected& b) {
  for (int f = 0; f < kFieldCount; ++f) {
    ASSERT_EQ(a.data[f].size(), b.data[f].size()) << "field " << f;
    // memcmp on the null data() of an empty vector is undefined behaviour (UBSan).
    if (a.data[f].empty()) continue;
    EXPECT_EQ(0, std::memcmp(a.data[f].data(), b.data[f].data(), a.data[f].size() * sizeof(double))) << "field " << f;
  }
}

TEST(GridSampler, CurvesMatchReferenceEvaluator) {
  struct Case { FamilySpec family; bool closed; bool knots; };
  std::vector<Case> cases = {
      {{Construction::ExtendedBSpline, 5, 0, -3.0, {}}, false, false},
      {{Construction::ExtendedBSpline, 6, 0, 0.5, {}}, true, false},
      {{Construction::GB, 0, 0, 7.0, {}}, false, true},
      {{Construction::UBP, 0, 7, -4.0, {}}, false, false},
      {{Construction::GUBP, 0, 5, 0.0, {0.1, 0.6, 0.3}}, true, false},
      {{Construction::AlphaEB, 4, 0, -2.0, {}}, false, false},
      {{Construction::AlphaEB, 6, 0, 1.0, {}}, true, false},
      {{Construction::BSpline, 0, 4, 0.0, {}}, false, true},
  };
  for (const auto& c : cases) {
    CurveModel m;
    m.family = c.family;
    m.closed = c.closed;
    m.dimension = 3;
    m.points = randomPoints(9, 7, false);
    if (c.family.construction == Construction::AlphaEB)
      for (int i = 0; i < 9; ++i) m.alpha.push_back(0.1 + 0.1 * i);
    if (c.knots && c.family.construction == Construction::BSpline)
      m.knots = {0, 0, 0, 0, 0.1, 0.3, 0.3, 0.5, 0.8, 1, 1, 1, 1};
    else if (c.knots)
      m.knots = {0, 0.5, 2, 2.25, 4, 4.5, 7};  // 9 points, open 4-function family: 6 spans
    const Curve curve = Curve::create(m);
    const double scale = boxDiagonal(m.points);
    const int S = 7;
    double maxErr = 0.0;
    Collected got;
    sampleCurveGrid(curve, {S, 1, 0, 0}, kCurveFields, got.consumer(), {2, 10});
    const auto items = curveGridItems(curve);
    ASSERT_EQ(got.data[0].size(), items.size() * S * 3);
    size_t pt = 0;
    for (int span : items)
      for (int a = 0; a < S; ++a, ++pt) {
        const CurvePoint ref = curve.evaluate(span, double(a) / (S - 1));
        const dvec3 vals[3] = {ref.point, ref.d1, ref.d2};
        const Field fs[3] = {Field::Point, Field::D1, Field::D2};
        for (int k = 0; k < 3; ++k)
          for (int ax = 0; ax < 3; ++ax) {
            // Same formulas, other summation order: a few ulps of the field's magnitude.
            const double err = std::abs(got.data[int(fs[k])][pt * 3 + ax] - vals[k][ax]);
            const double tol = test::kFp64Rel * (scale + glm::length(vals[k]));
            maxErr = std::max(maxErr, err);
            EXPECT_LE(err, tol) << constructionName(c.family.construction) << " span " << span << " a " << a << " field " << k;
          }
      }
    std::printf("curve %-16s max |fast - reference| %.3e\n", std::string(constructionName(c.family.construction)).c_str(), maxErr);
  }
}

// The sampled grid of `surface` (every field, Su x Sv per patch, chunks of 64 points on two
// threads) against Surface::evaluate at every point: each field within fieldUlps ulps of its
// magnitude (the net's size plus the value's), unit normals within 100 ulps of 1 (amplified by
// 1/sin of the partials' angle, which the smooth test nets keep above ~0.05). Returns the largest
// relative difference.
double expectGridMatchesEvaluate(const Surface& surface, int Su, int Sv, double fieldUlps, const std::string& what,
                                 FieldMask fields = kSurfaceFields) {
  const double scale = boxDiagonal(surface.controlPoints());
  Collected got;
  sampleSurfaceGrid(surface, {Su, Sv, 0, 0}, fields, got.consumer(), {2, 64});
  const auto items = surfaceGridItems(surface);
  EXPECT_EQ(got.data[0].size(), items.size() * Su * Sv * 3) << what;
  if (got.data[0].size() != items.size() * Su * Sv * 3) return INFINITY;
  double maxErr = 0.0;
  size_t pt = 0;
  for (auto [i, j] : items)
    for (int a = 0; a < Su; ++a)
      for (int b = 0; b < Sv; ++b, ++pt) {
        const SurfacePoint ref = surface.evaluate(i, j, double(a) / (Su - 1), double(b) / (Sv - 1));
        const dvec3 vals[7] = {ref.point, ref.du, ref.dv, ref.duu, ref.duv, ref.dvv, ref.normal};
        const Field fs[7] = {Field::Point, Field::Du, Field::Dv, Field::Duu, Field::Duv, Field::Dvv, Field::Normal};
        for (int k = 0; k < 7; ++k)
          for (int ax = 0; ax < 3; ++ax) {
            if (!(fields & fieldBit(fs[k]))) continue;
            const double v = got.data[int(fs[k])][pt * 3 + ax];
            const double mag = k == 6 ? 1.0 : scale + glm::length(vals[k]);
            const double err = std::abs(v - vals[k][ax]);
            maxErr = std::max(maxErr, err / mag);
            if (!(err <= (k == 6 ? 100 : fieldUlps) * test::kFp64Rel * mag)) {
              ADD_FAILURE() << what << " S " << Su << "x" << Sv << " patch " << i << "," << j << " a " << a << " b "
                            << b << " field " << k << ": " << v << " vs " << vals[k][ax];
              return maxErr;
            }
          }
      }
  return maxErr;
}

TEST(GridSampler, SurfacesMatchReferenceEvaluator) {
  struct Case { FamilySpec family; bool cu, cv; };
  std::vector<Case> cases = {
      {{Construction::ExtendedBSpline, 4, 0, 0.0, {}}, false, false},
      {{Construction::UBP, 0, 5, -6.0, {}}, false, true},
      {{Construction::AlphaEB, 5, 0, -1.0, {}}, false, false},
      {{Construction::AlphaEB, 4, 0, 0.5, {}}, true, false},
      {{Construction::AlphaEB, 6, 0, -10.0, {}}, false, true},
      {{Construction::AlphaEB, 5, 0, 1.0, {}}, true, true},
  };
  for (const auto& c : cases) {
    SurfaceModel m = gridSurface(c.family, 6, 7, c.cu, c.cv, 11);
    if (!m.alpha.empty()) m.alpha[8] = 1.0;  // one α = 1 vertex exercises the corner-limit normal
    const Surface surface = Surface::create(m);
    const double maxErr = expectGridMatchesEvaluate(surface, 5, 6, 1, std::string(constructionName(c.family.construction)));
    std::printf("surface %-16s closed %d%d max relative |fast - reference| %.3e\n",
                std::string(constructionName(c.family.construction)).c_str(), c.cu, c.cv, maxErr);
  }
}

// One thread in one chunk, two threads in chunks of 200 points and of 1 point: the same bytes.
// Returns the one-thread result.
Collected expectThreadAndChunkInvariant(const Surface& surface) {
  Collected one, two, tiny;
  sampleSurfaceGrid(surface, {9, 8, 0, 0}, kSurfaceFields, one.consumer(), {1, size_t{1} << 20});
  sampleSurfaceGrid(surface, {9, 8, 0, 0}, kSurfaceFields, two.consumer(), {2, 200});
  sampleSurfaceGrid(surface, {9, 8, 0, 0}, kSurfaceFields, tiny.consumer(), {2, 1});
  expectSameBytes(one, two);
  expectSameBytes(one, tiny);
  return one;
}

TEST(GridSampler, ByteIdenticalAcrossThreadsChunksAndShards) {
  const Surface surface = Surface::create(gridSurface({Construction::AlphaEB, 5, 0, -2.0, {}}, 7, 6, false, true, 3));
  const Collected one = expectThreadAndChunkInvariant(surface);

  // Three shards of the item range concatenate to the whole.
  const size_t n = surfaceGridItems(surface).size();
  Collected shards;
  for (size_t k = 0; k < 3; ++k) {
    const size_t b = n * k / 3, e = n * (k + 1) / 3;
    Collected part;
    part.items = b;
    sampleSurfaceGrid(surface, {9, 8, b, e - b}, kSurfaceFields, part.consumer(), {2, 100});
    for (int f = 0; f < kFieldCount; ++f) shards.data[f].insert(shards.data[f].end(), part.data[f].begin(), part.data[f].end());
  }
  expectSameBytes(one, shards);
}

// A knot-vector B-spline surface (docs/math.md §10.1) on a rows x cols net.
SurfaceModel knotSurface(int orderU, int orderV, std::vector<double> knotsU, std::vector<double> knotsV, unsigned seed) {
  SurfaceModel m = gridSurface({Construction::BSpline, 0, orderU, 0.0, {}}, int(knotsU.size()) - orderU,
                               int(knotsV.size()) - orderV, false, false, seed);
  m.orderV = orderV;
  m.knotsU = std::move(knotsU);
  m.knotsV = std::move(knotsV);
  return m;
}

// The tabulated knot-vector path (core/knot_table.h) against Surface::evaluate at every grid
// point: uniform and non-uniform knots, clamped or not, interior knots of every multiplicity (C2
// down to a break, where the last sample of an interval lies on the next span), mixed orders.
TEST(GridSampler, KnotSurfacesMatchReferenceEvaluator) {
  struct Case {
    const char* name;
    SurfaceModel model;
  };
  std::vector<double> uniform;
  for (int k = 0; k < 12; ++k) uniform.push_back(k);
  const std::vector<Case> cases = {
      {"uniform bicubic", knotSurface(4, 4, uniform, uniform, 1)},
      {"clamped non-uniform", knotSurface(4, 3, {0, 0, 0, 0, 0.1, 0.35, 0.4, 0.9, 1, 1, 1, 1}, {0, 0, 0, 0.2, 0.25, 0.7, 1, 1, 1}, 2)},
      {"multiplicities", knotSurface(4, 4, {0, 0, 0, 0, 1, 1, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4}, {0, 0, 0, 0, 1, 2, 2, 2, 3, 3, 3, 3}, 3)},
      {"orders 2 and 6", knotSurface(2, 6, {0, 0, 0.5, 1, 1.5, 1.5, 2, 2}, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13}, 4)},
  };
  for (const Case& c : cases) {
    const Surface surface = Surface::create(c.model);
    for (auto [Su, Sv] : {std::pair{5, 6}, std::pair{2, 2}, std::pair{9, 3}}) {
      // Same bases, the net contracted u first instead of v first: a few ulps.
      const double maxErr = expectGridMatchesEvaluate(surface, Su, Sv, 4, c.name);
      std::printf("knot surface %-20s %dx%d max relative |fast - reference| %.3e\n", c.name, Su, Sv, maxErr);
    }
  }
}

// Rational knot-vector surfaces (random weights in [0.5, 2]) against Surface::evaluate for the field
// sets that take different row kernels: point + du + dv of bicubic rows in one pass with the
// quotient rule, with the normal too, the point alone, and every field (second partials: the
// homogeneous rows, then the quotient rule). "multiplicities" puts the last sample of some rows on
// the next span, a run of one sample.
TEST(GridSampler, RationalKnotSurfacesMatchReferenceEvaluator) {
  std::vector<double> uniform;
  for (int k = 0; k < 12; ++k) uniform.push_back(k);
  const FieldMask firstPartials = fieldBit(Field::Point) | fieldBit(Field::Du) | fieldBit(Field::Dv);
  const std::pair<const char*, SurfaceModel> cases[] = {
      {"uniform bicubic", knotSurface(4, 4, uniform, uniform, 6)},
      {"multiplicities", knotSurface(4, 4, {0, 0, 0, 0, 1, 1, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4},
                                     {0, 0, 0, 0, 1, 2, 2, 2, 3, 3, 3, 3}, 7)},
      {"orders 4 and 3",
       knotSurface(4, 3, {0, 0, 0, 0, 0.1, 0.35, 0.4, 0.9, 1, 1, 1, 1}, {0, 0, 0, 0.2, 0.25, 0.7, 1, 1, 1}, 8)},
  };
  for (auto [name, model] : cases) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> weight(0.5, 2.0);
    for (size_t k = 0; k < model.points.size(); ++k) model.weights.push_back(weight(rng));
    const Surface surface = Surface::create(model);
    for (FieldMask fields : {firstPartials, firstPartials | fieldBit(Field::Normal), fieldBit(Field::Point),
                             kSurfaceFields}) {
      const double maxErr = expectGridMatchesEvaluate(surface, 7, 6, 4, name, fields);
      std::printf("rational knot surface %-16s fields %#04x max relative |fast - reference| %.3e\n", name,
                  unsigned(fields), maxErr);
    }
  }
}

TEST(GridSampler, KnotSurfacesByteIdenticalAcrossThreadsAndChunks) {
  const Surface surface = Surface::create(
      knotSurface(4, 3, {0, 0, 0, 0, 0.1, 0.35, 0.35, 0.9, 1, 1, 1, 1}, {0, 0, 0, 0.2, 0.25, 0.7, 1, 1, 1}, 5));
  expectThreadAndChunkInvariant(surface);
}

// Over its budget a job tabulates each interval into the worker's scratch table: the same table.
TEST(KnotTables, ScratchTablesEqualTheJobsTables) {
  const std::vector<double> knots = {0, 0, 0, 0.5, 0.5, 1, 2, 2, 2};
  const KnotTables whole(3, knots, 6, 7), perItem(3, knots, 6, 7, 0);
  KnotTable scratchA, scratchB;
  for (int i : {2, 4, 5, 4}) {
    const KnotTable& a = whole.of(i, scratchA);
    const KnotTable& b = perItem.of(i, scratchB);
    EXPECT_EQ(&a == &scratchA, false) << "within the budget the job's own tables are used";
    EXPECT_EQ(&b, &scratchB);
    EXPECT_EQ(a.span, b.span) << i;
    for (int d = 0; d < 3; ++d) EXPECT_EQ(a.b[d], b.b[d]) << i << " derivative " << d;
  }
  // The last sample of interval 2 ([0, 0.5)) lies on the next non-empty interval, 4: the quadratic
  // is only C0 at the double knot 0.5, so its first derivative jumps there.
  EXPECT_EQ(whole.of(2, scratchA).span, (std::vector<int>{2, 2, 2, 2, 2, 2, 4}));
}

TEST(GridSampler, RejectsBadRequests) {
  CurveModel m;
  m.family = {Construction::ExtendedBSpline, 4, 0, 0.0, {}};
  m.points = randomPoints(6, 1, true);
  const Curve curve = Curve::create(m);
  auto sink = [](const GridChunk&) {};
  EXPECT_THROW(sampleCurveGrid(curve, {1, 1, 0, 0}, kCurveFields, sink), std::invalid_argument);
  EXPECT_THROW(sampleCurveGrid(curve, {4, 1, 0, 0}, fieldBit(Field::Normal), sink), std::invalid_argument);
  EXPECT_THROW(sampleCurveGrid(curve, {4, 1, 2, 5}, kCurveFields, sink), std::invalid_argument);
}

TEST(GridSampler, ConsumerExceptionStopsCleanly) {
  const Surface surface = Surface::create(gridSurface({Construction::ExtendedBSpline, 4, 0, 0.0, {}}, 8, 8, false, false, 5));
  int calls = 0;
  auto failing = [&](const GridChunk&) {
    if (++calls == 2) throw std::runtime_error("disk full");
  };
  EXPECT_THROW(sampleSurfaceGrid(surface, {4, 4, 0, 0}, fieldBit(Field::Point), failing, {2, 16}), std::runtime_error);
  EXPECT_EQ(calls, 2);
}

}  // namespace
}  // namespace shapespline
