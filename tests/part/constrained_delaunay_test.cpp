// The constrained Delaunay triangulation and its exact predicates: every check is made with the
// exact predicates themselves or against exact integer arithmetic, never against stored results.
#include <shapespline/part/constrained_delaunay.h>
#include <shapespline/part/exact_predicates.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <tuple>
#include <vector>

namespace shapespline::part {
namespace {

using Segments = std::vector<std::array<int, 2>>;

// Appends a closed loop through `loop` to points and segments.
void addLoop(std::vector<glm::dvec2>& points, Segments& segments, const std::vector<glm::dvec2>& loop) {
  const int first = int(points.size());
  for (size_t i = 0; i < loop.size(); ++i) {
    points.push_back(loop[i]);
    segments.push_back({first + int(i), first + int((i + 1) % loop.size())});
  }
}

// A rectangle's boundary with `perSide` points on each side, counter-clockwise or not.
std::vector<glm::dvec2> rectangle(glm::dvec2 lo, glm::dvec2 hi, int perSide, bool ccw) {
  std::vector<glm::dvec2> loop;
  const glm::dvec2 corners[4] = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
  for (int c = 0; c < 4; ++c) {
    for (int k = 0; k < perSide; ++k) {
      const double t = double(k) / perSide;
      loop.push_back(corners[c] + t * (corners[(c + 1) % 4] - corners[c]));
    }
  }
  if (!ccw) std::reverse(loop.begin(), loop.end());
  return loop;
}

double signedArea(const std::vector<glm::dvec2>& loop) {
  double twice = 0.0;
  for (size_t i = 0; i < loop.size(); ++i) {
    const glm::dvec2 a = loop[i], b = loop[(i + 1) % loop.size()];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * twice;
}

struct Checked {
  double area = 0.0;
  int triangles = 0;
  std::set<int> vertices;
};

// Checks what every result must satisfy: counter-clockwise non-degenerate triangles (exact orient),
// each edge used at most once per direction, every constraint an edge, and every edge between two
// triangles that is not a constraint locally Delaunay (exact in-circle). Returns area and counts.
Checked checkTriangulation(const ConstrainedDelaunay& cdt, const Segments& segments) {
  Checked out;
  const auto& p = cdt.points();
  const auto triangles = cdt.triangles();
  std::map<std::pair<int, int>, int> opposite;  // directed edge -> the vertex across it
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(cdt.vertexOf(t[k]), t[k]) << "triangle uses a duplicate point " << t[k];
      out.vertices.insert(t[k]);
    }
    EXPECT_EQ(orient2d(p[t[0]], p[t[1]], p[t[2]]), 1)
        << "triangle " << t[0] << " " << t[1] << " " << t[2] << " not counter-clockwise";
    out.area += 0.5 * ((p[t[1]].x - p[t[0]].x) * (p[t[2]].y - p[t[0]].y) -
                       (p[t[1]].y - p[t[0]].y) * (p[t[2]].x - p[t[0]].x));
    for (int k = 0; k < 3; ++k) {
      const bool fresh = opposite.emplace(std::pair(t[k], t[(k + 1) % 3]), t[(k + 2) % 3]).second;
      EXPECT_TRUE(fresh) << "edge " << t[k] << "-" << t[(k + 1) % 3] << " used twice";
    }
  }
  std::set<std::pair<int, int>> constrained;
  for (size_t s = 0; s < segments.size(); ++s) {
    const int a = cdt.vertexOf(segments[s][0]), b = cdt.vertexOf(segments[s][1]);
    if (a == b) continue;
    constrained.emplace(std::min(a, b), std::max(a, b));
    EXPECT_TRUE(opposite.count({a, b}) || opposite.count({b, a}))
        << "constraint segment " << s << " (" << a << "-" << b << ") is no edge";
  }
  for (const auto& [edge, c] : opposite) {
    const auto [a, b] = edge;
    if (a > b || constrained.count({a, b})) continue;
    const auto across = opposite.find({b, a});
    if (across == opposite.end()) continue;
    EXPECT_LE(incircle(p[a], p[b], p[c], p[across->second]), 0)
        << "edge " << a << "-" << b << " not locally Delaunay";
  }
  out.triangles = int(triangles.size());
  return out;
}

// A square with two square holes (one clockwise, one counter-clockwise: the even-odd rule decides)
// and random points inside, away from the loops.
struct HoledSquare {
  std::vector<glm::dvec2> points;
  Segments segments;
  std::vector<glm::dvec2> interior;
  double area = 0.0;
  int loopPoints = 0;
  static constexpr int kHoles = 2;

  explicit HoledSquare(int interiorCount) {
    const auto outer = rectangle({0.0, 0.0}, {1.0, 1.0}, 25, true);
    const auto hole1 = rectangle({0.2, 0.2}, {0.4, 0.4}, 7, false);
    const auto hole2 = rectangle({0.6, 0.5}, {0.8, 0.9}, 9, true);
    addLoop(points, segments, outer);
    addLoop(points, segments, hole1);
    addLoop(points, segments, hole2);
    loopPoints = int(points.size());
    area = std::fabs(signedArea(outer)) - std::fabs(signedArea(hole1)) - std::fabs(signedArea(hole2));
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> u(0.01, 0.99);
    auto nearHole = [](glm::dvec2 q, glm::dvec2 lo, glm::dvec2 hi) {
      return q.x > lo.x - 0.01 && q.x < hi.x + 0.01 && q.y > lo.y - 0.01 && q.y < hi.y + 0.01;
    };
    while (int(interior.size()) < interiorCount) {
      const glm::dvec2 q(u(random), u(random));
      if (nearHole(q, {0.2, 0.2}, {0.4, 0.4}) || nearHole(q, {0.6, 0.5}, {0.8, 0.9})) continue;
      interior.push_back(q);
    }
  }
};

// Triangle count of a triangulated polygonal domain with h holes, Vb loop and Vi interior
// vertices (Euler's formula): 2 Vi + Vb - 2 + 2 h.
int expectedTriangles(int interior, int boundary, int holes) { return 2 * interior + boundary - 2 + 2 * holes; }

TEST(ConstrainedDelaunay, SquareWithTwoHolesAndInteriorPoints) {
  HoledSquare domain(2000);
  auto points = domain.points;
  points.insert(points.end(), domain.interior.begin(), domain.interior.end());
  const ConstrainedDelaunay cdt(points, domain.segments);
  const Checked c = checkTriangulation(cdt, domain.segments);
  EXPECT_NEAR(c.area, domain.area, 1e-12 * domain.area);
  EXPECT_EQ(c.triangles, expectedTriangles(2000, domain.loopPoints, HoledSquare::kHoles));
  EXPECT_EQ(int(c.vertices.size()), int(points.size()));
  // No triangle inside a hole.
  for (const auto& t : cdt.triangles()) {
    const glm::dvec2 g = (points[t[0]] + points[t[1]] + points[t[2]]) / 3.0;
    EXPECT_FALSE(g.x > 0.2 && g.x < 0.4 && g.y > 0.2 && g.y < 0.4) << "triangle in hole 1";
    EXPECT_FALSE(g.x > 0.6 && g.x < 0.8 && g.y > 0.5 && g.y < 0.9) << "triangle in hole 2";
  }
}

TEST(ConstrainedDelaunay, IncrementalInsertionGivesAValidTriangulationOfTheSameArea) {
  HoledSquare domain(1000);
  ConstrainedDelaunay cdt(domain.points, domain.segments);
  const Checked before = checkTriangulation(cdt, domain.segments);
  EXPECT_NEAR(before.area, domain.area, 1e-12 * domain.area);
  EXPECT_EQ(before.triangles, expectedTriangles(0, domain.loopPoints, HoledSquare::kHoles));
  for (size_t i = 0; i < domain.interior.size(); ++i) {
    EXPECT_EQ(cdt.insert(domain.interior[i]), domain.loopPoints + int(i));
  }
  // A point again is the vertex it already is.
  EXPECT_EQ(cdt.insert(domain.interior[5]), domain.loopPoints + 5);
  const Checked after = checkTriangulation(cdt, domain.segments);
  EXPECT_NEAR(after.area, domain.area, 1e-12 * domain.area);
  EXPECT_EQ(after.triangles, expectedTriangles(1000, domain.loopPoints, HoledSquare::kHoles));
  // A point outside the loops and one inside a hole: accepted, and no triangle of the domain changes count.
  cdt.insert({1.5, 0.5});
  cdt.insert({0.3, 0.3});
  const Checked outside = checkTriangulation(cdt, domain.segments);
  EXPECT_EQ(outside.triangles, after.triangles);
  EXPECT_NEAR(outside.area, domain.area, 1e-12 * domain.area);
}

TEST(ConstrainedDelaunay, APointOnAConstraintSplitsIt) {
  std::vector<glm::dvec2> points;
  Segments segments;
  addLoop(points, segments, rectangle({0.0, 0.0}, {1.0, 1.0}, 1, true));
  ConstrainedDelaunay cdt(points, segments);
  cdt.insert({0.5, 0.5});
  const int m = cdt.insert({0.5, 0.0});  // on segment 0 (point 0 to point 1)
  const int q = cdt.insert({0.5, 0.25});
  EXPECT_EQ(q, m + 1);
  // The halves are constraints: checked as segments; the whole is no edge any more.
  const Segments halves = {{0, m}, {m, 1}, {1, 2}, {2, 3}, {3, 0}};
  const Checked c = checkTriangulation(cdt, halves);
  EXPECT_NEAR(c.area, 1.0, 1e-15);
  EXPECT_EQ(c.triangles, expectedTriangles(2, 5, 0));
  for (const auto& t : cdt.triangles()) {
    for (int k = 0; k < 3; ++k) {
      const std::set<int> e = {t[k], t[(k + 1) % 3]};
      EXPECT_NE(e, (std::set<int>{0, 1})) << "the split segment is still an edge";
    }
  }
  // Points near the split constraint that would flip it away if it were not a constraint: the
  // circle through (0, 0), (1, 0) and the inserted points would take the split vertex.
  const int below = cdt.insert({0.5, 1e-3});
  (void)below;
  checkTriangulation(cdt, halves);
}

TEST(ConstrainedDelaunay, GridPointsManyCollinearAndCocircular) {
  constexpr int kN = 40;
  std::vector<glm::dvec2> loop;
  for (int i = 0; i < kN; ++i) loop.push_back({i * 0.1, 0.0});
  for (int j = 0; j < kN; ++j) loop.push_back({kN * 0.1, j * 0.1});
  for (int i = kN; i > 0; --i) loop.push_back({i * 0.1, kN * 0.1});
  for (int j = kN; j > 0; --j) loop.push_back({0.0, j * 0.1});
  std::vector<glm::dvec2> points;
  Segments segments;
  addLoop(points, segments, loop);
  for (int i = 1; i < kN; ++i)
    for (int j = 1; j < kN; ++j) points.push_back({i * 0.1, j * 0.1});
  const ConstrainedDelaunay cdt(points, segments);
  const Checked c = checkTriangulation(cdt, segments);
  const double area = signedArea(loop);
  EXPECT_NEAR(c.area, area, 1e-12 * area);
  EXPECT_EQ(c.triangles, expectedTriangles((kN - 1) * (kN - 1), int(loop.size()), 0));
}

TEST(ConstrainedDelaunay, PointsOnCircles) {
  std::vector<glm::dvec2> loop, points;
  Segments segments;
  constexpr int kLoop = 256;
  for (int i = 0; i < kLoop; ++i) {
    const double a = 2.0 * std::numbers::pi * i / kLoop;
    loop.push_back({std::cos(a), std::sin(a)});
  }
  addLoop(points, segments, loop);
  int inner = 0;
  for (const double r : {0.25, 0.5, 0.75}) {
    for (int i = 0; i < 64; ++i, ++inner) {
      const double a = 2.0 * std::numbers::pi * i / 64;
      points.push_back({r * std::cos(a), r * std::sin(a)});
    }
  }
  points.push_back({0.0, 0.0});
  ++inner;
  const ConstrainedDelaunay cdt(points, segments);
  const Checked c = checkTriangulation(cdt, segments);
  EXPECT_NEAR(c.area, signedArea(loop), 1e-12);
  EXPECT_EQ(c.triangles, expectedTriangles(inner, kLoop, 0));
}

TEST(ConstrainedDelaunay, NearlyCollinearPoints) {
  std::vector<glm::dvec2> points;
  Segments segments;
  addLoop(points, segments, rectangle({0.0, -1.0}, {1.0, 1.0}, 2, true));
  std::mt19937_64 random(3);
  std::uniform_int_distribution<int> offset(-3, 3);
  constexpr int kLine = 500;
  for (int i = 1; i < kLine; ++i) points.push_back({double(i) / kLine, offset(random) * 1e-17});
  for (int i = 1; i < kLine; ++i) points.push_back({double(i) / kLine, 0.5 + offset(random) * 0x1p-53});
  const ConstrainedDelaunay cdt(points, segments);
  const Checked c = checkTriangulation(cdt, segments);
  EXPECT_NEAR(c.area, 2.0, 2e-12);
  EXPECT_EQ(c.triangles, expectedTriangles(2 * (kLine - 1), 8, 0));
}

TEST(ConstrainedDelaunay, DuplicatePointsAreOneVertex) {
  std::vector<glm::dvec2> points;
  Segments segments;
  const auto loop = rectangle({0.0, 0.0}, {2.0, 1.0}, 3, true);
  const int n = int(loop.size());
  // Each loop point twice; the segments use the second copies every other time.
  for (const auto& q : loop) points.push_back(q);
  for (const auto& q : loop) points.push_back(q);
  for (int i = 0; i < n; ++i) segments.push_back({i + (i % 2) * n, (i + 1) % n});
  points.push_back({1.0, 0.5});
  points.push_back({1.0, 0.5});
  const ConstrainedDelaunay cdt(points, segments);
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(cdt.vertexOf(i), i);
    EXPECT_EQ(cdt.vertexOf(i + n), i);
  }
  EXPECT_EQ(cdt.vertexOf(2 * n + 1), 2 * n);
  const Checked c = checkTriangulation(cdt, segments);
  EXPECT_NEAR(c.area, 2.0, 1e-15);
  EXPECT_EQ(c.triangles, expectedTriangles(1, n, 0));
  EXPECT_THROW(cdt.vertexOf(2 * n + 2), std::invalid_argument);
}

TEST(ConstrainedDelaunay, CrossingConstraintsNameBothSegments) {
  std::vector<glm::dvec2> points;
  Segments segments;
  addLoop(points, segments, rectangle({0.0, 0.0}, {1.0, 1.0}, 1, true));
  points.insert(points.end(), {{0.1, 0.1}, {0.9, 0.9}, {0.1, 0.9}, {0.9, 0.1}});
  segments.push_back({4, 5});
  segments.push_back({6, 7});
  try {
    ConstrainedDelaunay cdt(points, segments);
    FAIL() << "crossing constraints accepted";
  } catch (const CrossingConstraints& e) {
    EXPECT_EQ(std::set<int>({e.first(), e.second()}), std::set<int>({4, 5}));
    EXPECT_NE(std::string(e.what()).find("cross at ("), std::string::npos) << e.what();
  }
}

TEST(ConstrainedDelaunay, CollinearOverlapAndAPointOnASegmentAreCrossings) {
  std::vector<glm::dvec2> points;
  Segments segments;
  addLoop(points, segments, rectangle({0.0, 0.0}, {1.0, 1.0}, 1, true));
  // A segment along the bottom side from a new point (0.5, 0) to (2, 0): overlaps segment 0.
  auto overlap = points;
  overlap.insert(overlap.end(), {{0.5, 0.0}, {2.0, 0.0}});
  auto overlapSegments = segments;
  overlapSegments.push_back({4, 5});
  try {
    ConstrainedDelaunay cdt(overlap, overlapSegments);
    FAIL() << "overlapping constraints accepted";
  } catch (const CrossingConstraints& e) {
    EXPECT_EQ(std::set<int>({e.first(), e.second()}), std::set<int>({0, 4})) << e.what();
  }
  // A free point exactly on segment 1 (x = 1).
  auto onSegment = points;
  onSegment.push_back({1.0, 0.25});
  try {
    ConstrainedDelaunay cdt(onSegment, segments);
    FAIL() << "a point on a constraint accepted";
  } catch (const CrossingConstraints& e) {
    EXPECT_EQ(e.first(), 1);
    EXPECT_EQ(e.second(), -1 - 4);
    EXPECT_NE(std::string(e.what()).find("point 4"), std::string::npos) << e.what();
  }
}

TEST(ConstrainedDelaunay, BadInputNamesIndexAndValue) {
  std::vector<glm::dvec2> points = {{0, 0}, {1, 0}, {std::nan(""), 1}};
  try {
    ConstrainedDelaunay cdt(points, {});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("point 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nan"), std::string::npos) << e.what();
  }
  points[2] = {0, 1};
  try {
    ConstrainedDelaunay cdt(points, {{0, 1}, {1, 3}});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("constraint segment 1 names point 3"), std::string::npos) << e.what();
  }
  ConstrainedDelaunay cdt(points, {{0, 1}, {1, 2}, {2, 0}});
  EXPECT_THROW(cdt.insert({INFINITY, 0.0}), std::invalid_argument);
  EXPECT_THROW(cdt.insert({1e9, 0.0}), std::invalid_argument);
  EXPECT_EQ(cdt.triangles().size(), 1u);
}

// A circle's polygon with random points inside: valid, and its time printed (not asserted).
void checkCircle(int kLoop, int kInside) {
  std::vector<glm::dvec2> loop, points;
  Segments segments;
  for (int i = 0; i < kLoop; ++i) {
    const double a = 2.0 * std::numbers::pi * i / kLoop;
    loop.push_back({std::cos(a), std::sin(a)});
  }
  addLoop(points, segments, loop);
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> u(-0.999, 0.999);
  while (int(points.size()) < kLoop + kInside) {
    const glm::dvec2 q(u(random), u(random));
    if (q.x * q.x + q.y * q.y < 0.99) points.push_back(q);
  }
  const auto start = std::chrono::steady_clock::now();
  const ConstrainedDelaunay cdt(points, segments);
  const auto triangles = cdt.triangles();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::printf("[ timing ] %d loop + %d interior points: %.2f ms (construction and triangles())\n", kLoop, kInside, ms);
  const Checked c = checkTriangulation(cdt, segments);
  EXPECT_NEAR(c.area, signedArea(loop), 1e-12 * signedArea(loop));
  EXPECT_EQ(c.triangles, expectedTriangles(kInside, kLoop, 0));
}

TEST(ConstrainedDelaunay, CircleOfTenThousandPointsWithTenThousandInside) { checkCircle(10000, 10000); }

TEST(ConstrainedDelaunay, CircleOfThreeHundredPointsWithTenThousandInside) { checkCircle(300, 9700); }

// Coordinates that are integers below 2^24 (times a power of two) make the determinants exact in
// 128-bit integers: the predicates must agree with them, also where double arithmetic cannot.
TEST(ExactPredicates, AgreeWithIntegerArithmeticNearDegeneracy) {
  std::mt19937_64 random(5);
  std::uniform_int_distribution<int64_t> coordinate(-(1 << 23), 1 << 23);
  std::uniform_int_distribution<int64_t> nudge(-1, 1);
  auto sign = [](__int128 v) { return int(v > 0) - int(v < 0); };
  const double scale = 0x1p-20;  // exact, and far from integers as doubles go
  int zeros = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // c on the line through a and b (then nudged): a + k (b - a) with a small integer k.
    const int64_t ax = coordinate(random) / 4, ay = coordinate(random) / 4;
    const int64_t dx = coordinate(random) / 8, dy = coordinate(random) / 8;
    const int64_t k = 1 + trial % 3;
    const int64_t bx = ax + dx, by = ay + dy, cx = ax + k * dx + nudge(random), cy = ay + k * dy + nudge(random);
    const __int128 det = __int128(ax - cx) * (by - cy) - __int128(ay - cy) * (bx - cx);
    const glm::dvec2 a(ax * scale + 1.0, ay * scale), b(bx * scale + 1.0, by * scale), c(cx * scale + 1.0, cy * scale);
    // The shift by 1.0 is exact here (all values are multiples of 2^-20 below 2^5).
    ASSERT_EQ(orient2d(a, b, c), sign(det)) << trial;
    zeros += det == 0;
  }
  EXPECT_GT(zeros, 1000);
  // Near (0.5, 0.5), (12, 12), (24, 24), a point moved by ulps (Kettner et al., "Classroom examples of
  // robustness problems"): the differences round in doubles; every value is an integer times 2^-53.
  auto units = [](double v) { return int64_t(std::ldexp(v, 53)); };
  const glm::dvec2 b(12.0, 12.0), c(24.0, 24.0);
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 64; ++j) {
      const glm::dvec2 a(0.5 + std::ldexp(i, -53), 0.5 + std::ldexp(j, -53));
      const __int128 det = __int128(units(a.x) - units(c.x)) * (units(b.y) - units(c.y)) -
                           __int128(units(a.y) - units(c.y)) * (units(b.x) - units(c.x));
      ASSERT_EQ(orient2d(a, b, c), sign(det)) << i << " " << j;
    }
  }
  // In-circle: lattice points of the circle x^2 + y^2 = 5^22 (the Gaussian integers (1 + 2i)^k
  // (1 - 2i)^(22 - k)), times 2^-26, the fourth point nudged by a unit or not. Lifted squares of
  // 27-bit differences round in doubles; the integers stay below 2^120.
  std::vector<std::pair<int64_t, int64_t>> lattice;
  for (int k = 0; k <= 22; ++k) {
    int64_t re = 1, im = 0;
    for (int m = 0; m < 22; ++m) {
      const int64_t s = m < k ? 2 : -2;  // times (1 + 2i) or (1 - 2i)
      const int64_t r = re - s * im, t = im + s * re;
      re = r;
      im = t;
    }
    for (const auto& [x, y] : {std::pair(re, im), std::pair(-im, re), std::pair(-re, -im), std::pair(im, -re)})
      lattice.emplace_back(x, y);
  }
  std::uniform_int_distribution<size_t> pick(0, lattice.size() - 1);
  int cocircular = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    int64_t q[4][2];
    for (auto& v : q) std::tie(v[0], v[1]) = lattice[pick(random)];
    q[3][0] += nudge(random);
    auto rel = [&](int i, int axis) { return __int128(q[i][axis] - q[3][axis]); };
    auto lift = [&](int i) { return rel(i, 0) * rel(i, 0) + rel(i, 1) * rel(i, 1); };
    auto cross = [&](int i, int j) { return rel(i, 0) * rel(j, 1) - rel(i, 1) * rel(j, 0); };
    const __int128 det = lift(0) * cross(1, 2) + lift(1) * cross(2, 0) + lift(2) * cross(0, 1);
    auto at = [&](int i) { return glm::dvec2(std::ldexp(double(q[i][0]), -26), std::ldexp(double(q[i][1]), -26)); };
    ASSERT_EQ(incircle(at(0), at(1), at(2), at(3)), sign(det)) << trial;
    cocircular += det == 0 && cross(0, 1) != 0;
  }
  EXPECT_GT(cocircular, 1000);
}

}  // namespace
}  // namespace shapespline::part
