// Inputs found by the model fuzzer (tests/fuzz, scripts/fuzz.sh), kept as regression tests: each is
// the exact input text, parsed, built and evaluated the way the fuzz target does. The sanitizer
// build (scripts/sanitize.sh) is what turns a memory error among them into a failure.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <variant>

#include <shapespline/core/curve.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/model_json.h>

namespace shapespline {
namespace {

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// docs/math.md §2.3: C_j(0) = [(k-λ) P_{j-1} + 2(k(k-2)+λ) P_j + (k-λ) P_{j+1}] / (2k(k-1)).
glm::dvec3 spanStart(int k, double lambda, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return ((k - lambda) * (a + c) + 2.0 * (k * (k - 2) + lambda) * b) / (2.0 * k * (k - 1));
}

// crash-935b0da7: heap-buffer-overflow in Curve::create. node_{N-1} of an open α-EB curve was
// evaluated over 4 extended points, one past the N+2 of the extended polygon (the 4th weight is 0
// at t = 0, so the value was right unless the byte after the vector happened to hold NaN/Inf).
TEST(FuzzRegression, OpenAlphaEBCurveLastNodeStaysInsideTheExtendedPolygon) {
  const std::string input =
      R"({"alpha":1,"closed":false,"construction":"alpha_eb","degree":6,"kind":"curve","lambda":1,)"
      R"("points":[[0,0],[1,2],[3,3],[5,1],[6,4]]})";
  const Curve curve = Curve::create(std::get<CurveModel>(io::parseModelText(input)));
  const auto& p = curve.model().points;
  const size_t n = p.size();
  ASSERT_EQ(curve.alphaNodes().size(), n);
  const glm::dvec3 phantom = 2.0 * p[n - 1] - p[n - 2];  // P_N of §4.1
  const glm::dvec3 expected = spanStart(6, 1.0, p[n - 2], p[n - 1], phantom);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(curve.alphaNodes()[n - 1][a], expected[a], 1e-14) << "axis " << a;
  for (const auto& v : curve.alphaV()) EXPECT_TRUE(finite(v));
}

// The same rule for surfaces: node_ij of the last row / column of an open direction read a 4 x 4
// block, past the extended net (last row) or into the next row (last column).
TEST(FuzzRegression, OpenAlphaEBSurfaceLastNodesStayInsideTheExtendedNet) {
  const std::string input =
      R"({"kind":"surface","construction":"alpha_eb","degree":4,"lambda":-3,"alpha":0.5,)"
      R"("points":[[[0,0,0],[1,0,1],[2,0,0]],[[0,1,1],[1,1,2],[2,1,1]],[[0,2,0],[1,2,1],[2,2,3]]]})";
  const SurfaceModel m = std::get<SurfaceModel>(io::parseModelText(input));
  const Surface surface = Surface::create(m);
  // Open in both directions: the phantom rule of §5.1 per direction, P_{3,3} = 2 P_{2,·} - P_{1,·} etc.
  auto P = [&](int i, int j) {
    auto row = [&](int r) {
      if (j < m.cols) return m.at(r, j);
      return 2.0 * m.at(r, m.cols - 1) - m.at(r, m.cols - 2);
    };
    if (i < m.rows) return row(i);
    return 2.0 * row(m.rows - 1) - row(m.rows - 2);
  };
  const int k = 4, r = m.rows - 1, c = m.cols - 1;
  const double lambda = -3.0;
  glm::dvec3 rows[3];
  for (int a = 0; a < 3; ++a) rows[a] = spanStart(k, lambda, P(r - 1 + a, c - 1), P(r - 1 + a, c), P(r - 1 + a, c + 1));
  const glm::dvec3 expected = spanStart(k, lambda, rows[0], rows[1], rows[2]);
  const glm::dvec3 got = surface.alphaNode(r, c);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(got[a], expected[a], 1e-13) << "axis " << a;
  for (const auto& v : surface.alphaV()) EXPECT_TRUE(finite(v));
}

// crash-21b139ce (stop 45): an α = 5e-324 that the parser accepts makes V overflow fp64 (§4.2), so
// Curve::create refuses it with a ModelError naming the vertex; the fuzz target had counted every
// exception from create as a finding. The refusal itself is what the CLI reports (exit 2).
TEST(FuzzRegression, AnAlphaWhoseVOverflowsIsRefusedWhenTheCurveIsBuilt) {
  const std::string input = R"({"kind": "curve", "construction": "alpha_eb", "degree": 4, "alpha":5e-324, )"
                            R"("points": [[0,0],[1,2],[3,3],[5,1],[6,4]]})";
  const CurveModel model = std::get<CurveModel>(io::parseModelText(input));
  try {
    (void)Curve::create(model);
    FAIL() << "Curve::create accepted alpha = 5e-324";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "alpha[1]");
    EXPECT_EQ(e.value(), "5e-324");
    EXPECT_NE(e.rule().find("exceeds the fp64 range"), std::string::npos) << e.rule();
  }
}

}  // namespace
}  // namespace shapespline
