// core/trim_classifier.h against a plain even-odd count over every edge (no slabs), on random loops
// and points, and the boundary rule on a square with a hole.
#include <shapespline/core/trim_classifier.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace shapespline {
namespace {

// The reference: every edge, a crossing test written the other way round (the ray's parameter).
bool referenceInside(const TrimLoops& trim, glm::dvec2 p) {
  bool odd = false;
  for (const auto& loop : trim.loops)
    for (size_t i = 0; i < loop.size(); ++i) {
      const glm::dvec2 a = loop[i], b = loop[(i + 1) % loop.size()];
      const double lo = std::min(a.y, b.y), hi = std::max(a.y, b.y);
      if (p.y < lo || p.y >= hi) continue;
      const double s = (p.y - a.y) / (b.y - a.y);
      if (a.x + s * (b.x - a.x) > p.x) odd = !odd;
    }
  return odd;
}

std::vector<glm::dvec2> circle(glm::dvec2 centre, double radius, int n, bool clockwise) {
  std::vector<glm::dvec2> loop;
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * M_PI * i / n * (clockwise ? -1.0 : 1.0);
    loop.push_back(centre + radius * glm::dvec2(std::cos(t), std::sin(t)));
  }
  return loop;
}

TEST(TrimClassifier, SquareWithAHole) {
  TrimLoops trim;
  trim.loops = {{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {{1, 1}, {1, 3}, {3, 3}, {3, 1}}};
  trim.tolerance = 0.01;
  const TrimClassifier c(trim);
  EXPECT_TRUE(c.inside({0.5, 0.5}));
  EXPECT_TRUE(c.inside({3.5, 2.0}));
  EXPECT_FALSE(c.inside({2.0, 2.0}));   // in the hole
  EXPECT_FALSE(c.inside({5.0, 2.0}));   // outside
  EXPECT_FALSE(c.inside({-1.0, -1.0}));
  EXPECT_TRUE(c.inside({4.005, 2.0}));  // on the outer boundary, within the tolerance
  EXPECT_TRUE(c.inside({2.0, 2.995}));  // on the hole's boundary, within the tolerance
  EXPECT_FALSE(c.inside({4.02, 2.0}));
  EXPECT_FALSE(c.inside({2.0, 2.98}));
  EXPECT_TRUE(c.inside({1.0, 0.5}));    // straight below a vertex of the hole
}

TEST(TrimClassifier, AgreesWithEveryEdgeEvenOddAwayFromTheLoops) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int shape = 0; shape < 20; ++shape) {
    TrimLoops trim;
    // A star-shaped outer loop and up to three small circular holes.
    std::vector<glm::dvec2> outer;
    const int n = 5 + shape * 17;
    for (int i = 0; i < n; ++i) {
      const double t = 2.0 * M_PI * i / n, r = 0.6 + 0.4 * unit(random);
      outer.push_back({5.0 + 4.0 * r * std::cos(t), 5.0 + 4.0 * r * std::sin(t)});
    }
    trim.loops.push_back(outer);
    for (int h = 0; h < shape % 4; ++h)
      trim.loops.push_back(circle({4.0 + h, 5.0}, 0.3, 8 + 40 * h, true));
    trim.tolerance = shape % 2 ? 0.0 : 1e-9;
    const TrimClassifier c(trim);
    for (int k = 0; k < 20000; ++k) {
      const glm::dvec2 p(10.0 * unit(random), 10.0 * unit(random));
      ASSERT_EQ(c.inside(p), referenceInside(trim, p)) << "shape " << shape << " at " << p.x << ", " << p.y;
    }
  }
}

}  // namespace
}  // namespace shapespline
