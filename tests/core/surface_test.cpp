// Identity tests of core/surface.h: α-EB surfaces over degree × λ × (closed_u, closed_v), plain
// tensor surfaces over the families, knot-vector B-spline surfaces, and the normal convention of
// docs/math.md §5.3 at α = 1 vertices.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include <shapespline/core/curve.h>
#include <shapespline/core/family.h>
#include <shapespline/core/grid_sampler.h>
#include <shapespline/core/surface.h>
#include <shapespline/core/validate.h>
#include "support/tolerances.h"

namespace shapespline {
namespace {

using glm::dvec3;
using test::kFp64Rel;

using test::kFdRel;  // finite differences (support/tolerances.h)
using test::kFdStep;
const double kInterior[] = {0.1, 0.3, 0.55, 0.9};
const double kEdges[] = {0.0, 0.2, 0.5, 0.8, 1.0};

std::vector<dvec3> randomNet(int rows, int cols, unsigned seed) {
  // A wavy cylinder-like sheet so that normals are well defined, plus noise.
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-0.6, 0.6);
  std::vector<dvec3> p(static_cast<size_t>(rows) * cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const double a = 6.283185307179586 * j / cols;
      p[static_cast<size_t>(i) * cols + j] =
          dvec3(3 * std::cos(a) + d(rng), 3 * std::sin(a) + d(rng), 1.5 * i + d(rng));
    }
  return p;
}

double bboxDiagonal(const std::vector<dvec3>& pts) {
  dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

::testing::AssertionResult near(const dvec3& a, const dvec3& b, double tol, const std::string& what) {
  const double e = glm::length(a - b);
  if (e <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << what << ": |" << a.x << "," << a.y << "," << a.z << " - " << b.x << ","
                                       << b.y << "," << b.z << "| = " << e << " > " << tol;
}

bool finiteUnit(const dvec3& n) { return std::isfinite(n.x + n.y + n.z) && std::abs(glm::length(n) - 1.0) < 1e-12; }

SurfaceModel makeSurface(const FamilySpec& f, int rows, int cols, bool cu, bool cv, std::vector<dvec3> pts) {
  SurfaceModel m;
  m.family = f;
  m.rows = rows;
  m.cols = cols;
  m.closedU = cu;
  m.closedV = cv;
  m.points = std::move(pts);
  return m;
}

FamilySpec family(Construction c, int degree, int order, double lambda) {
  FamilySpec f;
  f.construction = c;
  f.degree = degree;
  f.order = order;
  f.lambda = lambda;
  return f;
}

// All six partials of two evaluations agree (C² across a joint).
void expectSameJet(const SurfacePoint& a, const SurfacePoint& b, double tol, const std::string& where) {
  EXPECT_TRUE(near(a.point, b.point, tol, where + " point"));
  EXPECT_TRUE(near(a.du, b.du, tol * 10, where + " du"));
  EXPECT_TRUE(near(a.dv, b.dv, tol * 10, where + " dv"));
  EXPECT_TRUE(near(a.duu, b.duu, tol * 100, where + " duu"));
  EXPECT_TRUE(near(a.duv, b.duv, tol * 100, where + " duv"));
  EXPECT_TRUE(near(a.dvv, b.dvv, tol * 100, where + " dvv"));
}

void expectFiniteDifferences(const Surface& s, int i, int j, double u, double v, double scale,
                             const std::string& where) {
  const SurfacePoint p = s.evaluate(i, j, u, v);
  const SurfacePoint um = s.evaluate(i, j, u - kFdStep, v), up = s.evaluate(i, j, u + kFdStep, v);
  const SurfacePoint vm = s.evaluate(i, j, u, v - kFdStep), vp = s.evaluate(i, j, u, v + kFdStep);
  const double h2 = 2 * kFdStep;
  const double tol1 = kFdRel * (scale + glm::length(p.duu) + glm::length(p.dvv));
  const double tol2 = tol1 * 100;
  EXPECT_TRUE(near(p.du, (up.point - um.point) / h2, tol1, where + " du"));
  EXPECT_TRUE(near(p.dv, (vp.point - vm.point) / h2, tol1, where + " dv"));
  EXPECT_TRUE(near(p.duu, (up.du - um.du) / h2, tol2, where + " duu"));
  EXPECT_TRUE(near(p.dvv, (vp.dv - vm.dv) / h2, tol2, where + " dvv"));
  EXPECT_TRUE(near(p.duv, (vp.du - vm.du) / h2, tol2, where + " duv (from du)"));
  EXPECT_TRUE(near(p.duv, (up.dv - um.dv) / h2, tol2, where + " duv (from dv)"));
}

// ---- α-EB surfaces ------------------------------------------------------------------------------

// The surface keeps its points only inside its patch net (built in the points' own block): the
// net entry by entry against the §5.1 combinations of the model's points (extendedIndices, computed
// here apart from create), and the points, α and weights the surface gives back, bit for bit.
void expectNetAndPointsOf(const SurfaceModel& m, const Surface& s) {
  const bool phantom = m.family.construction == Construction::AlphaEB;
  int offset = 0;
  const auto eu = extendedIndices(m.rows, m.closedU, phantom, s.basisU().count, s.basisU().centre, offset);
  const auto ev = extendedIndices(m.cols, m.closedV, phantom, s.basisV().count, s.basisV().centre, offset);
  ASSERT_EQ(size_t(s.netRows()), eu.size());
  ASSERT_EQ(size_t(s.netCols()), ev.size());
  for (size_t a = 0; a < eu.size(); ++a)
    for (size_t b = 0; b < ev.size(); ++b) {
      auto rowPoint = [&](int i) {
        const ExtendedIndex& y = ev[b];
        return y.w1 == 0.0 ? m.at(i, y.i0) : y.w0 * m.at(i, y.i0) + y.w1 * m.at(i, y.i1);
      };
      const ExtendedIndex& x = eu[a];
      const dvec3 want = x.w1 == 0.0 ? rowPoint(x.i0) : x.w0 * rowPoint(x.i0) + x.w1 * rowPoint(x.i1);
      ASSERT_EQ(s.patchNet()[a * ev.size() + b], want) << "net entry (" << a << ", " << b << ")";
    }
  EXPECT_EQ(s.controlPoints(), m.points);
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) ASSERT_EQ(s.controlPoint(i, j), m.at(i, j)) << i << "," << j;
  EXPECT_TRUE(s.toModel() == m) << "toModel() is not the model the surface was made from";
}

// A model whose points have room for the net (io's readers reserve netCapacity) gives its block to
// the net: no second copy of a big net, ever.
template <class Make>
void expectTheNetTakesThePointsBlock(Make make) {
  SurfaceModel m = make();
  m.points.reserve(netCapacity(m.rows, m.cols));
  const dvec3* block = m.points.data();
  const Surface s = Surface::create(std::move(m));
  EXPECT_EQ(s.patchNet().data(), block);
}

struct AlphaParam {
  int degree;
  double lambda;
  bool closedU, closedV;
  friend void PrintTo(const AlphaParam& p, std::ostream* os) {
    *os << "k=" << p.degree << " λ=" << p.lambda << " closed=(" << p.closedU << "," << p.closedV << ")";
  }
};

class AlphaSurface : public ::testing::TestWithParam<AlphaParam> {
 protected:
  static constexpr int kRows = 5, kCols = 6;
  SurfaceModel model(unsigned seed, bool withOnes = false) {
    const auto& p = GetParam();
    SurfaceModel m = makeSurface(family(Construction::AlphaEB, p.degree, 0, p.lambda), kRows, kCols, p.closedU,
                                 p.closedV, randomNet(kRows, kCols, seed));
    std::mt19937 rng(seed + 77);
    std::uniform_real_distribution<double> d(0.05, 0.95);
    for (int k = 0; k < kRows * kCols; ++k) m.alpha.push_back(withOnes && k % 7 == 3 ? 1.0 : d(rng));
    alphaMin_ = *std::min_element(m.alpha.begin(), m.alpha.end());
    scale_ = bboxDiagonal(m.points);
    return m;
  }
  double tol() const { return kFp64Rel * scale_ / alphaMin_ * 10; }
  double alphaMin_ = 1.0, scale_ = 1.0;
};

TEST_P(AlphaSurface, InterpolatesTheNet) {
  const SurfaceModel m = model(1);
  const Surface s = Surface::create(m);
  const PatchRange r = s.patches();
  EXPECT_EQ(r.u.first, 0);
  EXPECT_EQ(r.u.last, m.closedU ? m.rows - 1 : m.rows - 2);
  EXPECT_EQ(r.v.last, m.closedV ? m.cols - 1 : m.cols - 2);
  for (int i = r.u.first; i <= r.u.last; ++i)
    for (int j = r.v.first; j <= r.v.last; ++j)
      for (int cu = 0; cu <= 1; ++cu)
        for (int cv = 0; cv <= 1; ++cv) {
          const dvec3& P = m.at((i + cu) % m.rows, (j + cv) % m.cols);
          EXPECT_TRUE(near(s.evaluate(i, j, cu, cv).point, P, tol(),
                           "corner (" + std::to_string(cu) + "," + std::to_string(cv) + ") of patch " +
                               std::to_string(i) + "," + std::to_string(j)));
        }
}

TEST_P(AlphaSurface, IsC2AcrossPatchBoundaries) {
  const SurfaceModel m = model(2);
  const Surface s = Surface::create(m);
  const PatchRange r = s.patches();
  for (int i = r.u.first; i <= r.u.last; ++i) {
    for (int j = r.v.first; j <= r.v.last; ++j) {
      const bool hasU = i < r.u.last || m.closedU, hasV = j < r.v.last || m.closedV;
      const int i1 = i == r.u.last ? 0 : i + 1, j1 = j == r.v.last ? 0 : j + 1;
      for (double t : kEdges) {
        if (hasU) expectSameJet(s.evaluate(i, j, 1.0, t), s.evaluate(i1, j, 0.0, t), tol(), "u joint");
        if (hasV) expectSameJet(s.evaluate(i, j, t, 1.0), s.evaluate(i, j1, t, 0.0), tol(), "v joint");
      }
    }
  }
}

TEST_P(AlphaSurface, DerivativesMatchFiniteDifferences) {
  const Surface s = Surface::create(model(3));
  const PatchRange r = s.patches();
  for (int i = r.u.first; i <= r.u.last; i += 2)
    for (int j = r.v.first; j <= r.v.last; j += 2)
      for (double u : kInterior)
        for (double v : kInterior) expectFiniteDifferences(s, i, j, u, v, scale_ / alphaMin_, "patch");
}

TEST_P(AlphaSurface, BoundaryRowIsTheAlphaEBCurveOfTheBoundaryPolygon) {
  // docs/math.md §5.4: on an open boundary the base surface's boundary curve is the extended B-spline
  // curve of the boundary polygon with its own phantom points. Because the boundary nodes and V
  // then coincide with the curve's, the whole α-EB boundary row is the α-EB curve of that
  // polygon with the boundary α (checked for the u = 0 row and, if v is open, the v = 0 column).
  const SurfaceModel m = model(4);
  const Surface s = Surface::create(m);
  const SpanBasis basis = xuWangSpanBasis(GetParam().degree, GetParam().lambda);
  auto check = [&](bool alongV, int line, bool closed) {
    CurveModel c;
    c.family = m.family;
    c.closed = closed;
    c.dimension = 3;
    const int n = alongV ? m.cols : m.rows;
    for (int k = 0; k < n; ++k) {
      const int i = alongV ? line : k, j = alongV ? k : line;
      c.points.push_back(m.at(i, j));
      c.alpha.push_back(m.alpha[static_cast<size_t>(i) * m.cols + j]);
    }
    const Curve curve = Curve::create(c);
    for (int span = curve.spans().first; span <= curve.spans().last; ++span) {
      for (double t : kEdges) {
        const int pi = alongV ? (line == 0 ? 0 : s.patches().u.last) : span;
        const int pj = alongV ? span : (line == 0 ? 0 : s.patches().v.last);
        const double edge = line == 0 ? 0.0 : 1.0;
        const SurfacePoint q = alongV ? s.evaluate(pi, pj, edge, t) : s.evaluate(pi, pj, t, edge);
        const CurvePoint k = curve.evaluate(span, t);
        EXPECT_TRUE(near(q.point, k.point, tol(), "boundary point"));
        EXPECT_TRUE(near(alongV ? q.dv : q.du, k.d1, tol() * 10, "boundary tangent"));
        EXPECT_TRUE(near(alongV ? q.dvv : q.duu, k.d2, tol() * 100, "boundary d2"));
        // Base surface boundary = extended B-spline curve on the phantom-extended polygon.
        PatchDerivs base;
        const int stride = s.netCols();
        const int a = alongV ? (line == 0 ? 0 : s.patches().u.last) : span;
        const int b = alongV ? span : (line == 0 ? 0 : s.patches().v.last);
        evalTensorPatch(basis, basis, &s.extendedNet()[static_cast<size_t>(a) * stride + b], stride,
                        alongV ? edge : t, alongV ? t : edge, base);
        CurvePoint baseCurve;
        evalLocalSpan(basis, &curve.extendedPoints()[span], t, 1.0, baseCurve);
        EXPECT_TRUE(near(base.p, baseCurve.point, kFp64Rel * scale_ * 10, "base boundary point"));
        EXPECT_TRUE(near(alongV ? base.v : base.u, baseCurve.d1, kFp64Rel * scale_ * 100, "base boundary d1"));
      }
    }
  };
  if (!m.closedU) {
    check(true, 0, m.closedV);
    check(true, m.rows - 1, m.closedV);
  }
  if (!m.closedV) {
    check(false, 0, m.closedU);
    check(false, m.cols - 1, m.closedU);
  }
}

TEST_P(AlphaSurface, ExtendedNetFollowsThePhantomRule) {
  const SurfaceModel m = model(5);
  const Surface s = Surface::create(m);
  const auto& E = s.extendedNet();
  const int cols = s.netCols();
  EXPECT_EQ(s.netRows(), m.closedU ? m.rows + 3 : m.rows + 2);
  EXPECT_EQ(cols, m.closedV ? m.cols + 3 : m.cols + 2);
  // ext(a,b) = P_{a-1,b-1}: interior entries are the net itself.
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) EXPECT_EQ(E[static_cast<size_t>(i + 1) * cols + j + 1], m.at(i, j));
  const dvec3 corner = E[0];
  dvec3 expected;
  if (!m.closedU && !m.closedV)
    expected = 4.0 * m.at(0, 0) - 2.0 * m.at(0, 1) - 2.0 * m.at(1, 0) + m.at(1, 1);
  else if (m.closedU && !m.closedV)
    expected = 2.0 * m.at(m.rows - 1, 0) - m.at(m.rows - 1, 1);
  else if (!m.closedU && m.closedV)
    expected = 2.0 * m.at(0, m.cols - 1) - m.at(1, m.cols - 1);
  else
    expected = m.at(m.rows - 1, m.cols - 1);
  EXPECT_TRUE(near(corner, expected, kFp64Rel * scale_, "corner P_{-1,-1} (§5.1)"));
}

TEST_P(AlphaSurface, KeepsItsPointsOnlyInsideItsExtendedNet) {
  const SurfaceModel m = model(7);
  expectNetAndPointsOf(m, Surface::create(m));
  expectTheNetTakesThePointsBlock([&] { return model(7); });
}

TEST_P(AlphaSurface, NormalsAreFiniteUnitVectorsEverywhere) {
  const Surface s = Surface::create(model(6, /*withOnes=*/true));
  const PatchRange r = s.patches();
  for (int i = r.u.first; i <= r.u.last; ++i)
    for (int j = r.v.first; j <= r.v.last; ++j)
      for (double u : kEdges)
        for (double v : kEdges) {
          const SurfacePoint p = s.evaluate(i, j, u, v);
          EXPECT_TRUE(finiteUnit(p.normal)) << i << "," << j << " at " << u << "," << v;
          if (p.normalRule == NormalRule::Regular) {
            EXPECT_TRUE(near(p.normal, glm::normalize(glm::cross(p.du, p.dv)), 1e-12, "regular normal"));
          }
        }
}

std::vector<AlphaParam> alphaParams() {
  std::vector<AlphaParam> out;
  for (int k = 4; k <= 6; ++k) {
    const double lmin = -k * (k - 2.0);
    for (double lambda : {lmin, 0.0, 1.0})
      for (bool cu : {false, true})
        for (bool cv : {false, true}) out.push_back({k, lambda, cu, cv});
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(DegreeLambdaClosure, AlphaSurface, ::testing::ValuesIn(alphaParams()),
                         [](const ::testing::TestParamInfo<AlphaParam>& info) {
                           std::string s = "k" + std::to_string(info.param.degree) + "_l" +
                                           std::to_string(static_cast<int>(info.param.lambda)) + "_" +
                                           (info.param.closedU ? "cu" : "ou") + (info.param.closedV ? "cv" : "ov");
                           std::replace(s.begin(), s.end(), '-', 'm');
                           return s;
                         });

// ---- α = 1 vertices: the normal convention of §5.3 ----------------------------------------------

// An open 4x4 net with α = 1 at the interior vertex (1,1) and at the boundary corner (0,3).
SurfaceModel alphaOneModel(bool allOnes) {
  SurfaceModel m = makeSurface(family(Construction::AlphaEB, 5, 0, -2.0), 4, 4, false, false, {});
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> d(-0.3, 0.3);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      m.points.push_back(dvec3(i + d(rng), j + d(rng), 0.3 * std::sin(1.0 * i + 0.7 * j) + d(rng)));
  for (int k = 0; k < 16; ++k) m.alpha.push_back(allOnes ? 1.0 : 0.3 + 0.04 * k);
  if (!allOnes) {
    m.alpha[1 * 4 + 1] = 1.0;
    m.alpha[0 * 4 + 3] = 1.0;
  }
  return m;
}

double angle(const dvec3& a, const dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

TEST(SurfaceAlphaOneVertex, NormalIsTheDiagonalLimitInEveryAdjacentPatch) {
  const SurfaceModel m = alphaOneModel(false);
  const Surface s = Surface::create(m);
  // Every patch around vertex (1,1): patches (0,0), (0,1), (1,0), (1,1) with the vertex at their
  // corners (1,1), (1,0), (0,1), (0,0).
  for (int pi = 0; pi <= 1; ++pi) {
    for (int pj = 0; pj <= 1; ++pj) {
      const int cu = 1 - pi, cv = 1 - pj;
      const SurfacePoint p = s.evaluate(pi, pj, cu, cv);
      EXPECT_EQ(glm::length(p.du), 0.0) << "α = 1: Q_u vanishes at the vertex";
      EXPECT_EQ(glm::length(p.dv), 0.0);
      ASSERT_TRUE(finiteUnit(p.normal));
      EXPECT_EQ(p.normalRule, NormalRule::CornerLimit);
      EXPECT_TRUE(near(p.normal, s.limitNormal(pi, pj, cu, cv), 0.0, "limitNormal()"));
      // Independent formula from the accessors: A_u = V_{p',q} - P + (1-α_{p',q})(node - P).
      const int vp = 1, vq = 1, np = pi + (1 - cu), nq = pj + (1 - cv);
      const dvec3 P = m.at(vp, vq), node = s.alphaNode(vp, vq);
      const dvec3 au = s.alphaVertex(np, vq) - P + (1 - m.alpha[np * 4 + vq]) * (node - P);
      const dvec3 av = s.alphaVertex(vp, nq) - P + (1 - m.alpha[vp * 4 + nq]) * (node - P);
      const dvec3 expected = glm::normalize(glm::cross((cu == 0 ? 1.0 : -1.0) * au, (cv == 0 ? 1.0 : -1.0) * av));
      EXPECT_TRUE(near(p.normal, expected, 1e-14, "diagonal-limit formula"));
      // Approaching the vertex along the patch diagonal, the regular normal tends to the limit.
      double previous = INFINITY;
      for (double e : {1e-1, 1e-2, 1e-3, 1e-4}) {
        const double u = cu == 0 ? e : 1 - e, v = cv == 0 ? e : 1 - e;
        const SurfacePoint q = s.evaluate(pi, pj, u, v);
        ASSERT_EQ(q.normalRule, NormalRule::Regular) << "near the vertex the normal is regular";
        const double a = angle(q.normal, p.normal);
        EXPECT_LE(a, previous * 1.01 + 1e-12) << "angle must shrink as ε → 0 (ε = " << e << ")";
        previous = a;
      }
      EXPECT_LT(previous, 1e-2) << "normal at ε = 1e-4 on the diagonal vs the limit";
    }
  }
  // The boundary corner vertex (0,3) of patch (0,2).
  const SurfacePoint c = s.evaluate(0, 2, 0.0, 1.0);
  EXPECT_EQ(c.normalRule, NormalRule::CornerLimit);
  EXPECT_TRUE(finiteUnit(c.normal));
  EXPECT_LT(angle(s.evaluate(0, 2, 1e-4, 1 - 1e-4).normal, c.normal), 1e-2);
  // Through evaluateAt: the global vertex (1,1) resolves to patch (1,1) corner (0,0).
  EXPECT_TRUE(near(s.evaluateAt(1.0, 1.0).normal, s.limitNormal(1, 1, 0, 0), 0.0, "evaluateAt"));
  EXPECT_THROW(s.limitNormal(0, 0, 0, 0), std::logic_error);  // vertex (0,0) has α < 1
}

TEST(SurfaceAlphaOneVertex, AllOnesReduceToTheBilinearCornerNormal) {
  // All α = 1: V = P, A_u = P_{p',q} - P, so n ∥ (P_10 - P_00) x (P_01 - P_00) at corner (0,0).
  const SurfaceModel m = alphaOneModel(true);
  const Surface s = Surface::create(m);
  for (int i = 0; i <= 2; ++i)
    for (int j = 0; j <= 2; ++j) {
      const SurfacePoint p = s.evaluate(i, j, 0.0, 0.0);
      const dvec3 expected = glm::normalize(glm::cross(m.at(i + 1, j) - m.at(i, j), m.at(i, j + 1) - m.at(i, j)));
      EXPECT_TRUE(near(p.normal, expected, 1e-14, "bilinear corner normal"));
      // Along an edge whose two end α are 1 the cross-edge partial Q_v vanishes (up to the
      // rounding of a = (1-S) + S); the normal is still a finite unit vector and agrees with the
      // normal just inside the patch.
      const SurfacePoint e = s.evaluate(i, j, 0.5, 0.0);
      EXPECT_LT(glm::length(e.dv), 1e-14 * glm::length(e.du)) << "cross-edge partial vanishes on an α = 1 edge";
      EXPECT_TRUE(finiteUnit(e.normal));
      EXPECT_LT(angle(e.normal, s.evaluate(i, j, 0.5, kNormalShift).normal), 1e-2);
    }
}

TEST(SurfaceNormals, DegenerateEverywhereFallsBackToTheFixedAxis) {
  // A net collapsed to one point: every partial is 0; the normal is the fixed axis, never NaN.
  SurfaceModel m = makeSurface(family(Construction::ExtendedBSpline, 4, 0, 0.0), 4, 4, false, false,
                               std::vector<dvec3>(16, dvec3(1.0, 2.0, 3.0)));
  const Surface s = Surface::create(m);
  const SurfacePoint p = s.evaluate(1, 1, 0.5, 0.5);
  EXPECT_EQ(p.normalRule, NormalRule::FixedAxis);
  EXPECT_EQ(p.normal, dvec3(0.0, 0.0, 1.0));
}

// ---- Plain tensor surfaces ----------------------------------------------------------------------

struct PlainParam {
  std::string name;
  FamilySpec family;
  int orderV;  // bspline only
  bool c2;
  bool closedU = false, closedV = false;
  friend void PrintTo(const PlainParam& p, std::ostream* os) {
    *os << p.name << " closed=(" << p.closedU << "," << p.closedV << ")";
  }
};

class PlainSurface : public ::testing::TestWithParam<PlainParam> {
 protected:
  Surface make(unsigned seed) {
    const auto& p = GetParam();
    const int mu = p.family.construction == Construction::ExtendedBSpline || p.family.construction == Construction::GB
                       ? 4
                       : p.family.order;
    const int mv = p.orderV > 0 ? p.orderV : mu;
    const int rows = mu + 2, cols = mv + 3;
    SurfaceModel m = makeSurface(p.family, rows, cols, p.closedU, p.closedV, randomNet(rows, cols, seed));
    m.orderV = p.orderV;
    scale_ = bboxDiagonal(m.points);
    return Surface::create(m);
  }
  double scale_ = 1.0;
};

TEST_P(PlainSurface, DerivativesMatchFiniteDifferences) {
  const Surface s = make(31);
  const PatchRange r = s.patches();
  for (int i = r.u.first; i <= r.u.last; ++i)
    for (int j = r.v.first; j <= r.v.last; ++j)
      for (double u : {0.3, 0.8})
        for (double v : {0.2, 0.65}) expectFiniteDifferences(s, i, j, u, v, scale_, "plain");
}

TEST_P(PlainSurface, KeepsItsPointsOnlyInsideItsPatchNet) {
  const SurfaceModel m = make(35).toModel();
  expectNetAndPointsOf(m, Surface::create(m));
  expectTheNetTakesThePointsBlock([&] { return m; });
}

TEST_P(PlainSurface, PatchJointsAreContinuous) {
  const Surface s = make(32);
  const auto& m = s.model();
  const PatchRange r = s.patches();
  const double tol = kFp64Rel * scale_ * 10;
  for (int i = r.u.first; i <= r.u.last; ++i)
    for (int j = r.v.first; j <= r.v.last; ++j)
      for (double t : kEdges) {
        const int i1 = i == r.u.last ? r.u.first : i + 1, j1 = j == r.v.last ? r.v.first : j + 1;
        if (i < r.u.last || m.closedU) {
          const SurfacePoint a = s.evaluate(i, j, 1.0, t), b = s.evaluate(i1, j, 0.0, t);
          EXPECT_TRUE(near(a.point, b.point, tol, "C0 u"));
          EXPECT_TRUE(near(a.du, b.du, tol * 10, "C1 u"));
          EXPECT_TRUE(near(a.dv, b.dv, tol * 10, "tangential u"));
          if (GetParam().c2) {
            EXPECT_TRUE(near(a.duu, b.duu, tol * 100, "C2 u"));
            EXPECT_TRUE(near(a.duv, b.duv, tol * 100, "mixed u"));
          }
        }
        if (j < r.v.last || m.closedV) {
          const SurfacePoint a = s.evaluate(i, j, t, 1.0), b = s.evaluate(i, j1, t, 0.0);
          EXPECT_TRUE(near(a.point, b.point, tol, "C0 v"));
          EXPECT_TRUE(near(a.dv, b.dv, tol * 10, "C1 v"));
          if (GetParam().c2) {
            EXPECT_TRUE(near(a.dvv, b.dvv, tol * 100, "C2 v"));
            EXPECT_TRUE(near(a.duv, b.duv, tol * 100, "mixed v"));
          }
        }
      }
}

TEST_P(PlainSurface, RowsAreCurvesOfTheSameFamily) {
  // At a v on a patch edge... more simply: the tensor product with a net that is constant along u
  // is the curve of one column in v (partition of unity in u).
  const auto& p = GetParam();
  const Surface s0 = make(33);
  const SurfaceModel m0 = s0.toModel();
  SurfaceModel m = m0;
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) m.points[static_cast<size_t>(i) * m.cols + j] = m0.at(0, j);
  const Surface s = Surface::create(m);
  CurveModel c;
  c.family = p.family;
  if (p.orderV > 0) c.family.order = p.orderV;
  c.closed = p.closedV;
  c.dimension = 3;
  for (int j = 0; j < m.cols; ++j) c.points.push_back(m0.at(0, j));
  const Curve curve = Curve::create(c);
  const PatchRange r = s.patches();
  ASSERT_EQ(r.v.first, curve.spans().first);
  ASSERT_EQ(r.v.last, curve.spans().last);
  for (int j = r.v.first; j <= r.v.last; ++j)
    for (double t : kEdges) {
      const SurfacePoint q = s.evaluate(r.u.first, j, 0.37, t);
      const CurvePoint k = curve.evaluate(j, t);
      EXPECT_TRUE(near(q.point, k.point, kFp64Rel * scale_ * 10, "row = curve"));
      EXPECT_TRUE(near(q.dv, k.d1, kFp64Rel * scale_ * 100, "row tangent"));
      EXPECT_TRUE(near(q.du, dvec3(0.0), kFp64Rel * scale_ * 100, "no u dependence"));
    }
}

TEST_P(PlainSurface, PlanarNetGivesThePlaneAndItsNormal) {
  const auto& p = GetParam();
  const Surface s0 = make(34);
  SurfaceModel m = s0.toModel();
  const dvec3 n = glm::normalize(dvec3(0.3, -0.5, 0.8));
  const dvec3 e1 = glm::normalize(glm::cross(n, dvec3(1, 0, 0))), e2 = glm::cross(n, e1);
  // An affine image of the parameter grid: rows along e1, columns along e2 (so du x dv ∥ n),
  // plus in-plane noise.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-0.2, 0.2);
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j)
      m.points[static_cast<size_t>(i) * m.cols + j] = dvec3(1, 2, 3) + (i + d(rng)) * e1 + (j + d(rng)) * e2;
  if (m.closedU || m.closedV) return;  // a closed direction cannot stay planar and regular
  const Surface s = Surface::create(m);
  const PatchRange r = s.patches();
  for (int i = r.u.first; i <= r.u.last; ++i)
    for (int j = r.v.first; j <= r.v.last; ++j)
      for (double u : kEdges)
        for (double v : kEdges) {
          const SurfacePoint q = s.evaluate(i, j, u, v);
          EXPECT_LT(std::abs(glm::dot(q.point - dvec3(1, 2, 3), n)), kFp64Rel * 100) << p.name;
          EXPECT_TRUE(near(q.normal, n, 1e-10, "plane normal"));
        }
}

TEST_P(PlainSurface, GlobalParametersAndRanges) {
  const Surface s = make(35);
  const PatchRange r = s.patches();
  EXPECT_EQ(s.parameterRangeU().first, r.u.first);
  EXPECT_EQ(s.parameterRangeV().second, r.v.last + 1);
  const SurfacePoint a = s.evaluate(r.u.first, r.v.last, 0.25, 0.5);
  const SurfacePoint b = s.evaluateAt(r.u.first + 0.25, r.v.last + 0.5);
  EXPECT_TRUE(near(a.point, b.point, 1e-14 * scale_, "evaluateAt"));
  EXPECT_THROW(s.evaluate(r.u.last + 1, r.v.first, 0.0, 0.0), std::out_of_range);
  EXPECT_THROW(s.evaluate(r.u.first, r.v.first - 1, 0.0, 0.0), std::out_of_range);
  EXPECT_THROW(s.evaluate(r.u.first, r.v.first, 1.5, 0.0), std::out_of_range);
  EXPECT_THROW(s.evaluate(r.u.first, r.v.first, 0.0, std::numeric_limits<double>::quiet_NaN()), std::out_of_range);
  EXPECT_THROW(s.evaluateAt(s.parameterRangeU().second + 0.5, s.parameterRangeV().first), std::out_of_range);
}

std::vector<PlainParam> plainParams() {
  std::vector<PlainParam> base = {
      {"ext4", family(Construction::ExtendedBSpline, 4, 0, -8.0), 0, true},
      {"ext5", family(Construction::ExtendedBSpline, 5, 0, 0.5), 0, true},
      {"ext6", family(Construction::ExtendedBSpline, 6, 0, -2.0), 0, true},
      {"gb", family(Construction::GB, 0, 0, 2.5), 0, false},
      {"ubp3", family(Construction::UBP, 0, 3, -2.0), 0, false},
      {"ubp5", family(Construction::UBP, 0, 5, 0.5), 0, true},
      {"ubp8", family(Construction::UBP, 0, 8, -12.0), 0, true},
      {"bspline3x5", family(Construction::BSpline, 0, 3, 0.0), 5, false},
      {"bspline4x4", family(Construction::BSpline, 0, 4, 0.0), 4, true},
  };
  FamilySpec g = family(Construction::GUBP, 0, 5, 0.0);
  g.mu = {0.25, 0.5, 0.25};
  base.push_back({"gubp5", g, 0, true});
  std::vector<PlainParam> out;
  for (auto p : base)
    for (bool cu : {false, true})
      for (bool cv : {false, true}) {
        p.closedU = cu;
        p.closedV = cv;
        out.push_back(p);
      }
  return out;
}

INSTANTIATE_TEST_SUITE_P(Families, PlainSurface, ::testing::ValuesIn(plainParams()),
                         [](const ::testing::TestParamInfo<PlainParam>& info) {
                           return info.param.name + "_" + (info.param.closedU ? "cu" : "ou") +
                                  (info.param.closedV ? "cv" : "ov");
                         });

// ---- Knot-vector B-spline surfaces --------------------------------------------------------------

TEST(KnotVectorSurface, MatchesItsCurvesAndFiniteDifferences) {
  SurfaceModel m = makeSurface(family(Construction::BSpline, 0, 3, 0.0), 5, 6, false, false, randomNet(5, 6, 41));
  m.orderV = 4;
  m.knotsU = {0, 0, 0, 0.3, 0.7, 1, 1, 1};       // 5 + 3
  m.knotsV = {0, 0, 0, 0, 0.5, 1.5, 2, 2, 2, 2};  // 6 + 4
  const Surface s = Surface::create(m);
  ASSERT_TRUE(s.usesKnotVector());
  EXPECT_EQ(s.parameterRangeU(), std::make_pair(0.0, 1.0));
  EXPECT_EQ(s.parameterRangeV(), std::make_pair(0.0, 2.0));
  const double scale = bboxDiagonal(m.points);
  // Clamped corners interpolate the net corners.
  EXPECT_TRUE(near(s.evaluateAt(0.0, 0.0).point, m.at(0, 0), 1e-14 * scale * 10, "corner"));
  EXPECT_TRUE(near(s.evaluateAt(1.0, 2.0).point, m.at(4, 5), 1e-14 * scale * 10, "corner"));
  // The u = 0 boundary is the knot-vector curve of row 0.
  CurveModel c;
  c.family = family(Construction::BSpline, 0, 4, 0.0);
  c.dimension = 3;
  for (int j = 0; j < 6; ++j) c.points.push_back(m.at(0, j));
  c.knots = m.knotsV;
  const Curve row = Curve::create(c);
  for (double v : {0.0, 0.25, 0.9, 1.7, 2.0}) {
    EXPECT_TRUE(near(s.evaluateAt(0.0, v).point, row.evaluateAt(v).point, 1e-14 * scale * 10, "row 0"));
    EXPECT_TRUE(near(s.evaluateAt(0.0, v).dv, row.evaluateAt(v).d1, 1e-13 * scale * 10, "row 0 d1"));
  }
  for (int i = s.patches().u.first; i <= s.patches().u.last; ++i)
    for (int j = s.patches().v.first; j <= s.patches().v.last; ++j) {
      const auto [u0, v0] = s.parameterOf(i, j, 0.4, 0.6);
      EXPECT_TRUE(near(s.evaluate(i, j, 0.4, 0.6).point, s.evaluateAt(u0, v0).point, 1e-14 * scale * 10, "patch"));
      // Finite differences in the knot parameters.
      const double h = 1e-5;
      const SurfacePoint p = s.evaluateAt(u0, v0);
      const dvec3 fdu = (s.evaluateAt(u0 + h, v0).point - s.evaluateAt(u0 - h, v0).point) / (2 * h);
      const dvec3 fdv = (s.evaluateAt(u0, v0 + h).point - s.evaluateAt(u0, v0 - h).point) / (2 * h);
      const dvec3 fduv = (s.evaluateAt(u0, v0 + h).du - s.evaluateAt(u0, v0 - h).du) / (2 * h);
      EXPECT_TRUE(near(p.du, fdu, kFdRel * (scale + glm::length(p.duu)) * 10, "du"));
      EXPECT_TRUE(near(p.dv, fdv, kFdRel * (scale + glm::length(p.dvv)) * 10, "dv"));
      EXPECT_TRUE(near(p.duv, fduv, kFdRel * (scale + glm::length(p.duv)) * 100, "duv"));
      EXPECT_TRUE(finiteUnit(p.normal));
    }
}

TEST(KnotVectorSurface, KeepsItsPointsAndWeightsOnce) {
  SurfaceModel m = makeSurface(family(Construction::BSpline, 0, 3, 0.0), 5, 6, false, false, randomNet(5, 6, 43));
  m.orderV = 4;
  m.knotsU = {0, 0, 0, 0.3, 0.7, 1, 1, 1};
  m.knotsV = {0, 0, 0, 0, 0.5, 1.5, 2, 2, 2, 2};
  for (int k = 0; k < 30; ++k) m.weights.push_back(0.5 + 0.05 * k);
  SurfaceModel moved = m;
  const dvec3* points = moved.points.data();
  const double* weights = moved.weights.data();
  const Surface s = Surface::create(std::move(moved));
  EXPECT_EQ(s.knotData().points.data(), points);
  EXPECT_EQ(s.knotData().weights.data(), weights);
  EXPECT_EQ(s.weights(), m.weights);
  EXPECT_EQ(s.controlPoints(), m.points);
  EXPECT_EQ(s.toModel().knotsV, m.knotsV);
  EXPECT_EQ(s.toModel().weights, m.weights);
}

// create checks the V rule of §4.2 (V within fp64) with a bound over the whole net first and vertex
// by vertex only where the bound cannot clear the net: both ways the first vertex that breaks the
// rule is named.
TEST(SurfaceCreate, RefusesTheFirstVertexWhoseVLeavesFp64) {
  SurfaceModel m = makeSurface(family(Construction::AlphaEB, 5, 0, 0.0), 6, 7, false, false, randomNet(6, 7, 51));
  m.alpha.assign(42, 0.5);
  EXPECT_NO_THROW(Surface::create(m));
  m.alpha[2 * 7 + 3] = 1e-310;  // (1-α)/α overflows: only this vertex's V leaves fp64
  try {
    Surface::create(m);
    ADD_FAILURE() << "accepted a V beyond fp64";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "alpha[2][3]");
  }
  // Large coordinates: a checkerboard of z = ±1e307 with α = 1e-3 makes V about 1e310 wherever P and
  // its node differ; the expected vertex is the first whose V overflows, from the nodes of the same
  // net with a harmless α (a node does not depend on α).
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 7; ++j) m.points[static_cast<size_t>(i) * 7 + j] = dvec3(i, j, (i + j) % 2 ? 1e307 : -1e307);
  m.alpha.assign(42, 0.5);
  const Surface harmless = Surface::create(m);
  std::string first;
  for (int i = 0; i < 6 && first.empty(); ++i)
    for (int j = 0; j < 7 && first.empty(); ++j) {
      const dvec3 p = m.at(i, j), v = p + ((1.0 - 1e-3) / 1e-3) * (p - harmless.alphaNode(i, j));
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        first = "alpha[" + std::to_string(i) + "][" + std::to_string(j) + "]";
    }
  ASSERT_FALSE(first.empty()) << "the test net should make some V overflow";
  m.alpha.assign(42, 1e-3);
  try {
    Surface::create(m);
    ADD_FAILURE() << "accepted a net whose V are beyond fp64";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), first);
  }
  m.alpha.assign(42, 0.5);  // V = 2P - node: inside fp64 at this scale
  EXPECT_NO_THROW(Surface::create(m));
}

TEST(SurfaceCreate, ValidatesTheModel) {
  SurfaceModel m = makeSurface(family(Construction::AlphaEB, 4, 0, 0.0), 3, 3, false, false, randomNet(3, 3, 51));
  m.alpha.assign(9, 1.5);  // α > 1 is outside the model (§11)
  EXPECT_THROW(Surface::create(m), ModelError);
}

}  // namespace
}  // namespace shapespline

namespace shapespline {
namespace {

// The layout of a job comes from the shape alone when the net is not built (a streamed shard with
// no items, issue 31): patchRangeOf and surfaceGridItems(shape) must be the built surface's.
TEST(SurfaceShape, PatchRangeIsTheBuiltSurfaces) {
  std::vector<SurfaceModel> models;
  for (Construction c :
       {Construction::AlphaEB, Construction::ExtendedBSpline, Construction::UBP, Construction::BSpline}) {
    for (bool closedU : {false, true}) {
      for (bool closedV : {false, true}) {
        if (c == Construction::BSpline && (closedU || closedV)) continue;
        SurfaceModel m;
        m.family.construction = c;
        m.family.degree = c == Construction::UBP || c == Construction::BSpline ? 0 : 5;
        m.family.order = c == Construction::UBP ? 5 : c == Construction::BSpline ? 3 : 0;
        m.orderV = c == Construction::BSpline ? 4 : 0;
        m.closedU = closedU, m.closedV = closedV;
        m.rows = 9, m.cols = 7;
        for (int i = 0; i < m.rows; ++i)
          for (int j = 0; j < m.cols; ++j) m.points.push_back({i, j, std::sin(0.5 * i + 0.3 * j)});
        if (c == Construction::AlphaEB) m.alpha.assign(m.points.size(), 0.5);
        models.push_back(m);
      }
    }
  }
  // Knot vectors, one with an empty interior interval (skipped by the grid items).
  SurfaceModel k = models.back();
  k.knotsU = {0, 0, 0, 0.1, 0.2, 0.2, 0.5, 0.7, 0.9, 1, 1, 1};
  k.knotsV = {0, 0, 0, 0, 0.3, 0.6, 0.8, 1, 1, 1, 1};
  models.push_back(k);
  for (const SurfaceModel& m : models) {
    SCOPED_TRACE(std::string(constructionName(m.family.construction)) + (m.closedU ? " closed u" : "") +
                 (m.closedV ? " closed v" : "") + (m.knotsU.empty() ? "" : " knots"));
    validateSurfaceShape(m, {m.points.size(), m.alpha.size(), m.weights.size()});
    const Surface s = Surface::create(m);
    const PatchRange shape = patchRangeOf(m), built = s.patches();
    EXPECT_EQ(shape.u.first, built.u.first);
    EXPECT_EQ(shape.u.last, built.u.last);
    EXPECT_EQ(shape.v.first, built.v.first);
    EXPECT_EQ(shape.v.last, built.v.last);
    EXPECT_EQ(parameterizationOf(SurfaceShape(m)), s.parameterization());
    const SurfaceGridItems a = surfaceGridItems(SurfaceShape(m)), b = surfaceGridItems(s);
    EXPECT_EQ(a.u, b.u);
    EXPECT_EQ(a.v, b.v);
  }
  // The shape rules need no values: a count that does not match the shape is refused by name.
  SurfaceModel bad = models.front();
  EXPECT_THROW(validateSurfaceShape(bad, {bad.points.size() - 1, bad.alpha.size(), 0}), ModelError);
  EXPECT_THROW(validateSurfaceShape(bad, {bad.points.size(), 0, 0}), ModelError);  // α-EB without α
}

}  // namespace
}  // namespace shapespline
