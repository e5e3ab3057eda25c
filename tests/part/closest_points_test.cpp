// Closest points (part/closest_points.h) against references written here: on free-form B-spline,
// NURBS and uniform-family surfaces, a dense grid followed by Newton from each of the 16 best grid
// points (the test's own Newton, on Surface::evaluateAt); on a trimmed face, every sample of the
// face inside its loops and on them; on a curve, dense samples and Newton; on the cube, the exact
// signed distance to a box.
#include <shapespline/core/field_error.h>
#include <shapespline/core/parallel_for.h>
#include <shapespline/core/trim_classifier.h>
#include <shapespline/part/closest_points.h>
#include <shapespline/part/part_model.h>

#include <support/temp_files.h>

#include "cube_part.h"
#include "projection_surfaces.h"
#include "wavy_face.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

namespace shapespline::part {
namespace {

// The count on the free-form NURBS; a fifth of it elsewhere. Under ASan the same checks on
// a twentieth (it runs the reference about ten times slower).
#if defined(__SANITIZE_ADDRESS__)
constexpr int kPoints = 5000;
#else
constexpr int kPoints = 100000;
#endif

// ---- the reference -------------------------------------------------------------------------------

// Newton on |S(U, V) - q|^2 over the whole domain from (U, V): Newton's step where its matrix is
// positive definite, else Gauss-Newton's with a Levenberg shift; a parameter on the domain's edge
// with the gradient pointing out stays there (one-dimensional Newton on the other); clamped; halved
// until it descends.
double referenceNewton(const Surface& s, const glm::dvec3& q, double& U, double& V) {
  const auto [u0, u1] = s.parameterRangeU();
  const auto [v0, v1] = s.parameterRangeV();
  SurfacePoint e = s.evaluateAt(U, V);
  double f = glm::dot(e.point - q, e.point - q);
  for (int it = 0; it < 100; ++it) {
    const glm::dvec3 r = e.point - q;
    const double gu = glm::dot(e.du, r), gv = glm::dot(e.dv, r);
    double a = glm::dot(e.du, e.du) + glm::dot(e.duu, r), b = glm::dot(e.du, e.dv) + glm::dot(e.duv, r),
           c = glm::dot(e.dv, e.dv) + glm::dot(e.dvv, r);
    if (!(a > 0 && a * c - b * b > 0)) {
      a = glm::dot(e.du, e.du) * 1.001 + 1e-300, b = glm::dot(e.du, e.dv), c = glm::dot(e.dv, e.dv) * 1.001 + 1e-300;
    }
    const bool fixU = (U <= u0 && gu > 0) || (U >= u1 && gu < 0), fixV = (V <= v0 && gv > 0) || (V >= v1 && gv < 0);
    double du = 0, dv = 0;
    if (fixU && fixV) break;
    if (fixU) {
      dv = -gv / c;
    } else if (fixV) {
      du = -gu / a;
    } else {
      const double det = a * c - b * b;
      du = -(c * gu - b * gv) / det, dv = -(a * gv - b * gu) / det;
    }
    bool moved = false;
    for (int h = 0; h < 60; ++h, du *= 0.5, dv *= 0.5) {
      const double Un = std::clamp(U + du, u0, u1), Vn = std::clamp(V + dv, v0, v1);
      const SurfacePoint en = s.evaluateAt(Un, Vn);
      const double fn = glm::dot(en.point - q, en.point - q);
      if (fn < f) {
        moved = std::abs(Un - U) + std::abs(Vn - V) > 1e-15 * (u1 - u0 + v1 - v0);
        U = Un, V = Vn, e = en, f = fn;
        break;
      }
    }
    if (!moved) break;
  }
  return std::sqrt(f);
}

struct DenseGrid {
  std::vector<glm::dvec3> points;
  std::vector<glm::dvec2> uv;
};

DenseGrid denseGrid(const Surface& s, int n) {
  DenseGrid g;
  const auto [u0, u1] = s.parameterRangeU();
  const auto [v0, v1] = s.parameterRangeV();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const glm::dvec2 uv(u0 + (u1 - u0) * i / (n - 1), v0 + (v1 - v0) * j / (n - 1));
      g.uv.push_back(uv);
      g.points.push_back(s.evaluateAt(uv.x, uv.y).point);
    }
  return g;
}

double referenceDistance(const Surface& s, const DenseGrid& grid, const glm::dvec3& q, glm::dvec2* where = nullptr) {
  std::vector<std::pair<double, int>> d(grid.points.size());
  for (size_t k = 0; k < d.size(); ++k) d[k] = {glm::dot(grid.points[k] - q, grid.points[k] - q), int(k)};
  std::partial_sort(d.begin(), d.begin() + 16, d.end());
  double best = std::sqrt(d.front().first);
  for (int k = 0; k < 16; ++k) {
    double U = grid.uv[d[k].second].x, V = grid.uv[d[k].second].y;
    const double d2 = referenceNewton(s, q, U, V);
    if (d2 < best) {
      best = d2;
      if (where) *where = {U, V};
    }
  }
  return best;
}

// ---- surfaces --------------------------------------------------------------------------------------

double diagonalOf(const ProjectionTree& tree) { return tree.diagonal(); }

void expectExactOnSurface(const Surface& s, const char* name, uint32_t seed, int points) {
  const ProjectionTree tree = ProjectionTree::ofFaces({{&s, 0, false}});
  const ClosestPoints closest(tree);
  const double diag = diagonalOf(tree);
  const Queries q = queriesFor(s, diag, points, seed);
  const auto [u0, u1] = s.parameterRangeU();
  const auto [v0, v1] = s.parameterRangeV();

  std::vector<FootPoint> on(q.on.size());
  closest.of(q.on, on, false, 0);
  int far = 0, moved = 0;
  for (size_t k = 0; k < on.size(); ++k) {
    if (on[k].distance > 1e-12 * diag) ++far;
    const SurfacePoint p = s.evaluateAt(q.onUV[k].x, q.onUV[k].y);
    const bool regular = glm::length(glm::cross(p.du, p.dv)) > 1e-6 * glm::length(p.du) * glm::length(p.dv);
    if (regular && (std::abs(on[k].u - q.onUV[k].x) > 1e-9 * (u1 - u0) || std::abs(on[k].v - q.onUV[k].y) > 1e-9 * (v1 - v0)))
      ++moved;
    // The foot is the surface's point at the (u, v) it gives.
    if (k % 97 == 0) {
      EXPECT_LE(glm::length(s.evaluateAt(on[k].u, on[k].v).point - on[k].point), 1e-12 * diag);
    }
  }
  EXPECT_EQ(far, 0) << name << ": points on the surface farther than 1e-12 of the diagonal";
  EXPECT_EQ(moved, 0) << name << ": points on the surface given other parameters";

  const DenseGrid grid = denseGrid(s, 64);
  std::vector<FootPoint> off(q.off.size());
  closest.of(q.off, off, false, 0);
  std::vector<double> reference(q.off.size());
  parallelFor(q.off.size(), 0, [&](size_t k) { reference[k] = referenceDistance(s, grid, q.off[k]); });
  int localMinima = 0, differ = 0;
  double worst = 0.0;
  for (size_t k = 0; k < off.size(); ++k) {
    const double gap = off[k].distance - reference[k];
    worst = std::max(worst, std::abs(gap));
    if (gap > 1e-9 * diag && ++localMinima <= 3)
      ADD_FAILURE() << name << ": q = (" << q.off[k].x << ", " << q.off[k].y << ", " << q.off[k].z << ") foot ("
                    << off[k].u << ", " << off[k].v << ") at " << off[k].distance << ", reference " << reference[k] << " at " << [&] {
                      glm::dvec2 w;
                      referenceDistance(s, grid, q.off[k], &w);
                      return std::to_string(w.x) + ", " + std::to_string(w.y);
                    }();
    if (std::abs(gap) > 1e-9 * diag) ++differ;
    EXPECT_NEAR(glm::length(off[k].point - q.off[k]), off[k].distance, 1e-12 * diag);
  }
  EXPECT_EQ(localMinima, 0) << name << ": feet farther than the reference's (local minima); worst gap " << worst;
  EXPECT_EQ(differ, 0) << name << ": distances off the reference by more than 1e-9 of the diagonal; worst " << worst;
}

TEST(ClosestPoints, WavyNurbsMatchesTheBruteForceReference) { expectExactOnSurface(wavyNurbs(), "wavy NURBS", 1, kPoints); }

// With a tolerance, every foot is within it of the exact one (and on the surface), never nearer.
TEST(ClosestPoints, ToleranceBoundsTheGapToTheExactFoot) {
  const Surface s = wavyNurbs();
  const ProjectionTree tree = ProjectionTree::ofFaces({{&s, 0, false}});
  const double diag = diagonalOf(tree);
  const Queries q = queriesFor(s, diag, kPoints / 10, 4);
  for (const double fraction : {1e-6, 1e-3}) {
    const double tolerance = fraction * diag;
    const ClosestPoints exact(tree), loose(tree, tolerance);
    for (const std::vector<glm::dvec3>* points : {&q.on, &q.off}) {
      std::vector<FootPoint> a(points->size()), b(points->size());
      exact.of(*points, a, true, 0);
      loose.of(*points, b, true, 0);
      int outside = 0;
      for (size_t k = 0; k < a.size(); ++k) {
        if (b[k].distance > a[k].distance + tolerance || b[k].distance < a[k].distance - 1e-12 * diag) ++outside;
        if (k % 97 == 0) {
          EXPECT_LE(glm::length(s.evaluateAt(b[k].u, b[k].v).point - b[k].point), 1e-12 * diag);
        }
      }
      EXPECT_EQ(outside, 0) << "tolerance " << fraction << " of the diagonal";
    }
  }
  EXPECT_THROW(ClosestPoints(tree, -1.0), std::invalid_argument);
  EXPECT_THROW(ClosestPoints(tree, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

TEST(ClosestPoints, HalfCylinderMatchesTheBruteForceReference) {
  expectExactOnSurface(halfCylinder(), "half cylinder", 2, kPoints / 5);
}

TEST(ClosestPoints, XuWangSurfaceMatchesTheBruteForceReference) {
  expectExactOnSurface(xuWangSurface(), "Xu-Wang degree 5", 3, kPoints / 5);
}

TEST(ClosestPoints, HalfCylinderAxisPointsAreAtTheRadius) {
  // Every point of the axis is at distance 1 from the whole half cylinder: a tie, and still 1.
  const Surface s = halfCylinder();
  const ProjectionTree tree = ProjectionTree::ofFaces({{&s, 0, false}});
  const ClosestPoints closest(tree);
  for (double z : {0.0, 0.3, 1.0, 2.0}) {
    const FootPoint f = closest.of({0.0, 0.0, z}, false);
    EXPECT_NEAR(f.distance, 1.0, 1e-12);
    EXPECT_NEAR(f.point.z, z, 1e-12);
  }
}

// ---- a trimmed face --------------------------------------------------------------------------------

TEST(ClosestPoints, TrimmedFaceCountsOnlyInsideItsLoops) {
  // The wavy face with a square hole: feet lie inside the loops or on them, and none is farther than
  // any sample of the face inside its loops or on them.
  const Surface s = wavyFace({{{0.05, 0.05}, {0.95, 0.05}, {0.95, 0.95}, {0.05, 0.95}},
                              {{0.3, 0.3}, {0.7, 0.3}, {0.7, 0.7}, {0.3, 0.7}}});
  const ProjectionTree tree = ProjectionTree::ofFaces({{&s, 7, false}});
  const ClosestPoints closest(tree);
  const double diag = tree.diagonal();
  const TrimClassifier inside(s.model().trim);
  std::vector<glm::dvec3> samples;
  for (int i = 0; i <= 200; ++i)
    for (int j = 0; j <= 200; ++j) {
      const glm::dvec2 uv(i / 200.0, j / 200.0);
      if (inside.inside(uv)) samples.push_back(s.evaluateAt(uv.x, uv.y).point);
    }
  for (const auto& loop : s.model().trim.loops)
    for (size_t k = 0; k < loop.size(); ++k)
      for (int t = 0; t < 400; ++t) {
        const glm::dvec2 uv = loop[k] + (t / 400.0) * (loop[(k + 1) % loop.size()] - loop[k]);
        samples.push_back(s.evaluateAt(uv.x, uv.y).point);
      }
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> x(-0.1, 1.1), z(-0.6, 0.6);
  const int count = kPoints / 10;
  std::vector<glm::dvec3> queries;
  for (int k = 0; k < count; ++k) queries.push_back({x(rng), x(rng), z(rng)});
  std::vector<FootPoint> feet(queries.size());
  closest.of(queries, feet, false, 0);
  std::vector<double> nearestSample(queries.size());
  parallelFor(queries.size(), 0, [&](size_t k) {
    double best = 1e300;
    for (const glm::dvec3& p : samples) best = std::min(best, glm::dot(p - queries[k], p - queries[k]));
    nearestSample[k] = std::sqrt(best);
  });
  int worse = 0, outside = 0, boundary = 0;
  for (size_t k = 0; k < feet.size(); ++k) {
    EXPECT_EQ(feet[k].face, 7);
    if (feet[k].distance > nearestSample[k] + 1e-12 * diag && ++worse <= 3)
      ADD_FAILURE() << "q = (" << queries[k].x << ", " << queries[k].y << ", " << queries[k].z << ") foot ("
                    << feet[k].u << ", " << feet[k].v << (feet[k].boundary ? ", boundary" : "") << ") at "
                    << feet[k].distance << ", a sample at " << nearestSample[k];
    if (feet[k].boundary) {
      ++boundary;
    } else if (!inside.inside({feet[k].u, feet[k].v})) {
      ++outside;
    }
    EXPECT_LE(glm::length(s.evaluateAt(feet[k].u, feet[k].v).point - feet[k].point), 1e-12 * diag);
  }
  EXPECT_EQ(worse, 0) << "feet farther than a sample of the trimmed face";
  EXPECT_EQ(outside, 0) << "inner feet outside the loops";
  EXPECT_GT(boundary, count / 20) << "some points (over the hole, beyond the border) have feet on the loops";
}

// ---- the cube: signed distance ---------------------------------------------------------------------

TEST(ClosestPoints, CubeGivesTheExactSignedDistance) {
  const std::filesystem::path dir = test::processTempFile("closest", "cube");
  writeCube(dir, 2.0);
  const Part part = loadPart(dir / "part.json");
  ASSERT_TRUE(part.closed());
  const ProjectionTree tree = ProjectionTree::ofPart(part);
  const ClosestPoints closest(tree);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> x(-1.0, 3.0);
  int wrongSign = 0, wrongDistance = 0;
  for (int k = 0; k < kPoints / 10; ++k) {
    const glm::dvec3 q(x(rng), x(rng), x(rng));
    const glm::dvec3 d = glm::abs(q - glm::dvec3(1.0)) - glm::dvec3(1.0);  // > 0: outside along that axis
    const double outside = glm::length(glm::max(d, glm::dvec3(0.0)));
    const double exact = outside > 0.0 ? outside : std::max({d.x, d.y, d.z});
    const FootPoint f = closest.of(q, true);
    if (std::abs(f.signedDistance - exact) > 1e-12 * 4.0) ++wrongDistance;
    if (std::abs(exact) > 1e-9 && (f.signedDistance > 0) != (exact > 0)) ++wrongSign;
    EXPECT_NEAR(glm::length(f.normal), 1.0, 1e-12);
  }
  EXPECT_EQ(wrongSign, 0);
  EXPECT_EQ(wrongDistance, 0);
  // A point straight out of a face's middle: that face, its outward normal, its parameters.
  const FootPoint f = closest.of({1.0, 1.0, 2.5}, true);
  EXPECT_NEAR(f.signedDistance, 0.5, 1e-12);
  EXPECT_NEAR(f.normal.z, 1.0, 1e-12);
  EXPECT_FALSE(f.boundary);
}

TEST(ClosestPoints, OpenPartIsNotClosed) {
  const std::filesystem::path dir = test::processTempFile("closest", "open_cube");
  writeCube(dir, 1.0);
  nlohmann::json manifest;
  std::ifstream(dir / "part.json") >> manifest;
  manifest["faces"].erase(manifest["faces"].begin());
  manifest["shells"][0]["faces"].erase(manifest["shells"][0]["faces"].begin());
  writeJson(dir / "part.json", manifest);
  EXPECT_FALSE(loadPart(dir / "part.json").closed());
}

// ---- a curve -----------------------------------------------------------------------------------------

TEST(ClosestPoints, NurbsCurveMatchesDenseSamplesAndNewton) {
  CurveModel m;
  m.family.construction = Construction::BSpline;
  m.family.order = 4;
  m.dimension = 3;
  m.knots = clampedKnots(4, 9);
  for (int i = 0; i < 12; ++i) {
    m.points.push_back({std::cos(0.6 * i), std::sin(0.6 * i), 0.2 * std::sin(1.9 * i)});
    m.weights.push_back(1.0 + 0.4 * std::cos(1.1 * i));
  }
  const Curve c = Curve::create(std::move(m));
  const ProjectionTree tree = ProjectionTree::ofCurve(c);
  const ClosestPoints closest(tree);
  const auto [t0, t1] = c.parameterRange();
  std::vector<std::pair<double, glm::dvec3>> samples;
  for (int k = 0; k <= 4000; ++k) {
    const double t = t0 + (t1 - t0) * k / 4000;
    samples.push_back({t, c.evaluateAt(t).point});
  }
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> x(-1.3, 1.3);
  int differ = 0;
  for (int k = 0; k < kPoints / 20; ++k) {
    const glm::dvec3 q(x(rng), x(rng), 0.5 * x(rng));
    // The reference: the best sample, then Newton (clamped) along t.
    double best = 1e300, t = t0;
    for (const auto& [ts, p] : samples)
      if (glm::dot(p - q, p - q) < best) best = glm::dot(p - q, p - q), t = ts;
    for (int it = 0; it < 50; ++it) {
      const CurvePoint e = c.evaluateAt(t);
      const double g = glm::dot(e.d1, e.point - q), h = glm::dot(e.d1, e.d1) + glm::dot(e.d2, e.point - q);
      const double tn = std::clamp(t - g / (h > 0 ? h : glm::dot(e.d1, e.d1)), t0, t1);
      const glm::dvec3 pn = c.evaluateAt(tn).point;
      if (glm::dot(pn - q, pn - q) >= best) break;
      best = glm::dot(pn - q, pn - q), t = tn;
    }
    const FootPoint f = closest.of(q, false);
    if (std::abs(f.distance - std::sqrt(best)) > 1e-9 * tree.diagonal()) ++differ;
    EXPECT_NEAR(glm::length(c.evaluateAt(f.u).point - f.point), 0.0, 1e-12 * tree.diagonal());
  }
  EXPECT_EQ(differ, 0);
}

TEST(ClosestPoints, AlphaEBIsRefusedByName) {
  SurfaceModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 4;
  m.rows = m.cols = 4;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m.points.push_back({double(i), double(j), 0.0});
  m.alpha.assign(16, 0.5);
  const Surface s = Surface::create(std::move(m));
  try {
    ProjectionTree::ofFaces({{&s, 0, false}});
    FAIL() << "an α-EB surface was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("construction"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not polynomials"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace shapespline::part
