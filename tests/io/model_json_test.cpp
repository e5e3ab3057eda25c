// Model file reading/writing (docs/format.md) and typed validation (docs/math.md §11): every entry of the bad-model
// catalog is rejected naming the right field, every docs/format.md example and boundary value is accepted,
// and toJson round-trips exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string>

#include <shapespline/core/span_basis.h>
#include <shapespline/core/validate.h>
#include <shapespline/io/model_json.h>
#include "support/bad_models.h"
#include "support/golden.h"

namespace shapespline {
namespace {

using nlohmann::json;
using test::BadModel;
using test::badModelCatalog;

// ---------------------------------------------------------------------------------------------------
// Rejections

class BadModelTest : public ::testing::TestWithParam<BadModel> {};

TEST_P(BadModelTest, RejectedNamingField) {
  const BadModel& bad = GetParam();
  try {
    io::parseModelText(bad.json_text);
    FAIL() << bad.name << " was accepted: " << bad.json_text;
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), bad.field) << bad.name << ": " << e.what();
    EXPECT_FALSE(e.rule().empty()) << bad.name;
    EXPECT_NE(std::string(e.what()).find(e.field()), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Catalog, BadModelTest, ::testing::ValuesIn(badModelCatalog()),
                         [](const ::testing::TestParamInfo<BadModel>& info) { return info.param.name; });

TEST(BadModelCatalog, LargeAndUniquelyNamed) {
  const auto& catalog = badModelCatalog();
  EXPECT_GE(catalog.size(), 30u);
  std::set<std::string> names;
  for (const auto& b : catalog) EXPECT_TRUE(names.insert(b.name).second) << "duplicate name " << b.name;
}

TEST(ModelErrors, NameFieldValueAndRule) {
  try {
    io::parseModelText(R"({"kind":"curve","construction":"gb","lambda":-10,"points":[[0,0],[1,2],[3,3],[5,1]]})");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "lambda");
    EXPECT_EQ(e.value(), "-10");
    EXPECT_NE(e.rule().find("-8"), std::string::npos) << e.rule();
  }
}

TEST(ModelErrors, MalformedTextReportsPosition) {
  try {
    io::parseModelText("{\"kind\": \"curve\",\n \"points\": [1, 2,, 3]}");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "(document)");
    EXPECT_NE(e.rule().find("line 2"), std::string::npos) << e.rule();
  }
}

// nlohmann cannot read NaN from text, but a document built in code can carry one.
TEST(ModelErrors, NonFiniteNumbersInBuiltJson) {
  json doc = json::parse(R"({"kind":"curve","construction":"gb","points":[[0,0],[1,2],[3,3],[5,1]]})");
  doc["points"][2][1] = std::numeric_limits<double>::quiet_NaN();
  try {
    io::parseModel(doc);
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "points[2][1]");
  }
  doc["points"][2][1] = 3.0;
  doc["lambda"] = std::numeric_limits<double>::infinity();
  try {
    io::parseModel(doc);
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "lambda");
  }
}

// Typed validation on hand-built models (no JSON involved).
TEST(TypedValidation, RejectsWhatTheParserCannotProduce) {
  CurveModel c;
  c.family.construction = Construction::GB;
  c.points = {{0, 0, 0}, {1, 2, 0}, {3, 3, 0}, {5, 1, 0}};
  EXPECT_NO_THROW(validateCurve(c));
  c.dimension = 4;
  EXPECT_THROW(validateCurve(c), ModelError);
  c.dimension = 2;
  c.points[1].z = 1.0;
  try {
    validateCurve(c);
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "points[1]");
  }
  c.points[1].z = 0.0;
  c.family.mu = {0.5};
  try {
    validateCurve(c);
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "mu");
  }

  SurfaceModel s;
  s.family.construction = Construction::AlphaEB;
  s.family.degree = 4;
  s.rows = 2;
  s.cols = 2;
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  s.alpha = {0.5, 0.5, 0.5, 1.0};
  EXPECT_NO_THROW(validateSurface(s));
  s.alpha[3] = 1.5;
  try {
    validateSurface(s);
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "alpha[1][1]");
  }
  s.alpha[3] = 1.0;
  s.points.pop_back();
  EXPECT_THROW(validateSurface(s), ModelError);
}

TEST(TypedValidation, UbpLambdaMinTable) {
  EXPECT_EQ(ubpLambdaMin(3), -6.0);
  EXPECT_EQ(ubpLambdaMin(4), -8.0);
  EXPECT_EQ(ubpLambdaMin(5), -1150.0 / 107.0);
  EXPECT_NEAR(ubpLambdaMin(7), -15.731628173316, 1e-12);
  EXPECT_NEAR(ubpLambdaMin(10), -23.246018752791, 1e-12);
}

// ---------------------------------------------------------------------------------------------------
// Acceptance

void expectSameModel(const io::Model& a, const io::Model& b);  // defined with the round-trip tests

// By value: the callers pass the temporary parseModelText returns.
CurveModel asCurve(const io::Model& m) { return std::get<CurveModel>(m); }
SurfaceModel asSurface(const io::Model& m) { return std::get<SurfaceModel>(m); }

// The examples of docs/format.md, verbatim.
const char* const kFormatExamples[] = {
    R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, "lambda": -2.5, "closed": false,
 "points": [[0,0],[1,2],[3,3],[5,1],[6,4],[8,3]],
 "alpha": [0.5, 0.25, 1, 0.75, 0.5, 0.625]})",
    R"({"kind": "surface", "construction": "alpha_eb", "degree": 4, "lambda": 0, "closed": [false, true],
 "points": [[[3,0,0],[0,3,0],[-3,0,0],[0,-3,0]],
            [[3,0,2],[0,3,2],[-3,0,2],[0,-3,2]]],
 "alpha": 0.5})",
    R"({"kind": "curve", "construction": "gubp", "order": 5, "mu": [0.25, 0.5, 0.25], "closed": false,
 "points": [[0,0],[1,2],[3,3],[5,1],[6,4],[8,3],[9,0]]})",
    R"({"kind": "curve", "construction": "bspline", "order": 4, "closed": false,
 "points": [[0,0],[1,2],[3,3],[5,1],[6,4],[8,3]],
 "knots": [0,0,0,0,0.25,0.5,1,1,1,1]})",
    R"({"kind": "curve", "construction": "gb", "lambda": 2.5, "closed": false,
 "points": [[0,0],[1,2],[3,3],[5,1],[6,4]], "knots": [0, 1, 2.5]})",
};

TEST(FormatExamples, AlphaEbCurve) {
  const auto c = asCurve(io::parseModelText(kFormatExamples[0]));
  EXPECT_EQ(c.family.construction, Construction::AlphaEB);
  EXPECT_EQ(c.family.degree, 5);
  EXPECT_EQ(c.family.lambda, -2.5);
  EXPECT_EQ(c.dimension, 2);
  ASSERT_EQ(c.points.size(), 6u);
  EXPECT_EQ(c.points[4], glm::dvec3(6, 4, 0));
  EXPECT_EQ(c.alpha, (std::vector<double>{0.5, 0.25, 1, 0.75, 0.5, 0.625}));
}

TEST(FormatExamples, AlphaEbSurfaceScalarAlpha) {
  const auto s = asSurface(io::parseModelText(kFormatExamples[1]));
  EXPECT_EQ(s.rows, 2);
  EXPECT_EQ(s.cols, 4);
  EXPECT_FALSE(s.closedU);
  EXPECT_TRUE(s.closedV);
  EXPECT_EQ(s.at(1, 2), glm::dvec3(-3, 0, 2));
  EXPECT_EQ(s.alpha, std::vector<double>(8, 0.5));
}

TEST(FormatExamples, GubpCurve) {
  const auto c = asCurve(io::parseModelText(kFormatExamples[2]));
  EXPECT_EQ(c.family.order, 5);
  EXPECT_EQ(c.family.mu, (std::vector<double>{0.25, 0.5, 0.25}));
  EXPECT_EQ(c.family.lambda, 0.0);
}

TEST(FormatExamples, BSplineWithKnots) {
  const auto c = asCurve(io::parseModelText(kFormatExamples[3]));
  EXPECT_EQ(c.family.construction, Construction::BSpline);
  EXPECT_EQ(c.knots.size(), 10u);
}

TEST(FormatExamples, GbWithSpanKnots) {
  const auto c = asCurve(io::parseModelText(kFormatExamples[4]));
  EXPECT_EQ(c.family.lambda, 2.5);
  EXPECT_EQ(c.knots, (std::vector<double>{0, 1, 2.5}));
}

std::string curveText(const std::string& construction, const std::string& rest) {
  return R"({"kind": "curve", "construction": ")" + construction + "\", " + rest + "}";
}
const std::string kP5 = R"("points": [[0,0],[1,2],[3,3],[5,1],[6,4]])";
const std::string kP8 = R"("points": [[0,0],[1,2],[3,3],[5,1],[6,4],[8,3],[9,0],[11,1]])";
const std::string kNet4 =
    R"("points": [[[0,0,0],[1,0,0],[2,0,1],[3,0,0]],[[0,1,0],[1,1,1],[2,1,1],[3,1,0]],)"
    R"([[0,2,0],[1,2,1],[2,2,1],[3,2,0]],[[0,3,0],[1,3,0],[2,3,1],[3,3,0]]])";

std::string num17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Boundary values and tolerated forms that must be accepted.
std::vector<std::string> acceptedModels() {
  std::vector<std::string> v(std::begin(kFormatExamples), std::end(kFormatExamples));
  for (int k = 4; k <= 6; ++k) {
    v.push_back(curveText("extended_bspline", "\"degree\": " + std::to_string(k) +
                                                   ", \"lambda\": " + std::to_string(-k * (k - 2)) + ", " + kP5));
    v.push_back(curveText("alpha_eb", "\"degree\": " + std::to_string(k) + R"(, "lambda": 1, "alpha": 1, )" + kP5));
  }
  v.push_back(curveText("gb", R"("lambda": -8, )" + kP5));
  v.push_back(curveText("gb", R"("lambda": 1e6, "closed": true, )" + kP5));
  v.push_back(curveText("gb", kP5));  // lambda defaults to 0
  for (int k = 3; k <= 10; ++k) {
    v.push_back(curveText("ubp", "\"order\": " + std::to_string(k) + ", \"lambda\": " + num17(ubpLambdaMin(k)) +
                                     ", \"closed\": true, " + kP8));
    v.push_back(curveText("ubp", "\"order\": " + std::to_string(k) + R"(, "lambda": 1, "closed": true, )" + kP8));
  }
  v.push_back(curveText("ubp", R"("order": 8, )" + kP8));  // open, N = order
  v.push_back(curveText("gubp", R"("order": 3, "mu": [0.25, 0.75], )" + kP5));
  v.push_back(curveText("gubp", R"("order": 4, "mu": [0.25, 0.5, 0.5], )" + kP5));
  v.push_back(curveText("gubp", R"("order": 6, "mu": [0.25, 0.25, 0.25, 0.5], "closed": true, )" + kP5));
  v.push_back(curveText("gubp", R"("order": 3, "mu": [0, 1], )" + kP5));  // mu at both ends of [0,1]
  v.push_back(curveText("extended_bspline", R"("degree": 5.0, )" + kP5));  // 5.0 is tolerated
  v.push_back(curveText("ubp", R"("order": 4.0, "lambda": -8.0, )" + kP5));
  v.push_back(curveText("alpha_eb", R"("degree": 4, "alpha": [1e-9, 1], "points": [[0,0],[1,1]])"));  // open N = 2
  v.push_back(curveText("alpha_eb", R"("degree": 4, "alpha": 0.5, "closed": true, "points": [[0,0],[1,0],[0,1]])"));
  v.push_back(curveText("extended_bspline", R"("degree": 4, "closed": true, "knots": [0,1,2,3.5], "points": [[0,0],[1,0],[0,1]])"));
  v.push_back(curveText("extended_bspline", R"("degree": 6, "points": [[0,0,1],[1,2,1],[3,3,2],[5,1,0]], "knots": [-1, 0.5])"));
  v.push_back(curveText("bspline", R"("order": 2, "knots": [0,0,1,1], "points": [[0,0],[1,1]])"));
  v.push_back(curveText("bspline", R"("order": 3, "knots": [0,0,0,1,1,1,2,2], "points": [[0,0],[1,2],[3,3],[5,1],[6,4]])"));
  v.push_back(curveText("bspline", R"("order": 4, "knots": [0,1,2,3,4,5,6,7,8], )" + kP5));  // unclamped
  v.push_back(curveText("bspline", R"("order": 4, "closed": true, )" + kP5));  // periodic uniform, no knots
  v.push_back(curveText("bspline", R"("order": 2, "points": [[0,0],[1,1]])"));
  v.push_back(curveText("gb", R"("name": "a curve", "comment": "ignored", )" + kP5));
  v.push_back(R"({"kind": "surface", "construction": "extended_bspline", "degree": 4, "lambda": -8, )" + kNet4 + "}");
  v.push_back(R"({"kind": "surface", "construction": "gb", "closed": [true, true], )" + kNet4 + "}");
  v.push_back(R"({"kind": "surface", "construction": "ubp", "order": 4, "lambda": -8, )" + kNet4 + "}");
  v.push_back(R"({"kind": "surface", "construction": "gubp", "order": 3, "mu": [0.5, 0.5], )" + kNet4 + "}");
  v.push_back(R"({"kind": "surface", "construction": "bspline", "order": [4, 3], "knots": [[0,0,0,0,1,1,1,1],[0,0,0,0.5,1,1,1]], )" +
              kNet4 + "}");
  v.push_back(R"({"kind": "surface", "construction": "bspline", "order": [2, 4], "closed": [true, false], )" + kNet4 + "}");
  v.push_back(R"({"kind": "surface", "construction": "alpha_eb", "degree": 6, "lambda": -24, "alpha": [[1,0.5,0.25,0.125],[1,1,1,1],[0.5,0.5,0.5,0.5],[0.75,0.75,0.75,0.75]], )" +
              kNet4 + "}");
  return v;
}

TEST(Acceptance, BoundaryAndToleratedForms) {
  for (const auto& text : acceptedModels()) {
    EXPECT_NO_THROW({
      try {
        io::parseModelText(text);
      } catch (const ModelError& e) {
        ADD_FAILURE() << e.what() << "\n  in " << text;
        throw;
      }
    });
  }
}

// Every model of the golden files (other than the validation family) is valid and round-trips.
TEST(Acceptance, EveryGoldenModel) {
  int models = 0;
  for (const auto& file : test::loadGoldenFiles()) {
    for (const auto& c : file.doc.at("cases")) {
      if (!c.contains("model") || c.value("family", "") == "validation") continue;
      ++models;
      try {
        const io::Model m = io::parseModel(c.at("model"));
        expectSameModel(m, io::parseModel(io::toJson(m)));
      } catch (const ModelError& e) {
        ADD_FAILURE() << file.name << " " << c.value("id", "?") << ": " << e.what();
      }
    }
  }
  EXPECT_GT(models, 0);
}

TEST(Acceptance, IntegerValuedFloatsAreIntegers) {
  const auto c = asCurve(io::parseModelText(curveText("extended_bspline", R"("degree": 5.0, )" + kP5)));
  EXPECT_EQ(c.family.degree, 5);
}

TEST(Acceptance, ThreeDimensionalCurve) {
  const auto c = asCurve(io::parseModelText(curveText("gb", R"("points": [[0,0,1],[1,2,3],[3,3,3],[5,1,-1]])")));
  EXPECT_EQ(c.dimension, 3);
  EXPECT_EQ(c.points[1], glm::dvec3(1, 2, 3));
}

// Every UBP's Theorem-1 coefficient vector is an admissible GUBP mu (docs/math.md §9: UBP is a special case).
TEST(Acceptance, UbpCoefficientsAreAdmissibleMu) {
  for (int k = 3; k <= 10; ++k) {
    for (double lambda : {-5.0, 0.0, 0.3, 1.0}) {
      const auto full = ubpDoubledKnotCoefficients(k, lambda);
      CurveModel c;
      c.family.construction = Construction::GUBP;
      c.family.order = k;
      c.family.mu.assign(full.begin(), full.begin() + (k / 2 + 1));
      c.closed = true;
      c.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
      EXPECT_NO_THROW(validateCurve(c)) << "k=" << k << " lambda=" << lambda;
    }
  }
}

TEST(Acceptance, LoadModelFile) {
  const auto path = std::filesystem::temp_directory_path() / ("shapespline_model_json_test_" +
                                                              std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                                              ".json");
  {
    std::ofstream out(path);
    out << kFormatExamples[4];
  }
  const auto m = io::loadModelFile(path);
  EXPECT_EQ(asCurve(m).family.construction, Construction::GB);
  std::filesystem::remove(path);
  EXPECT_THROW(io::loadModelFile(path), std::runtime_error);
}

// ---------------------------------------------------------------------------------------------------
// Round trip

void expectSame(const FamilySpec& a, const FamilySpec& b) {
  EXPECT_EQ(a.construction, b.construction);
  EXPECT_EQ(a.degree, b.degree);
  EXPECT_EQ(a.order, b.order);
  EXPECT_EQ(a.lambda, b.lambda);
  EXPECT_EQ(a.mu, b.mu);
}

void expectSameModel(const io::Model& a, const io::Model& b) {
  ASSERT_EQ(a.index(), b.index());
  if (const auto* ca = std::get_if<CurveModel>(&a)) {
    const auto& cb = std::get<CurveModel>(b);
    expectSame(ca->family, cb.family);
    EXPECT_EQ(ca->closed, cb.closed);
    EXPECT_EQ(ca->dimension, cb.dimension);
    EXPECT_EQ(ca->points, cb.points);
    EXPECT_EQ(ca->alpha, cb.alpha);
    EXPECT_EQ(ca->knots, cb.knots);
  } else {
    const auto& sa = std::get<SurfaceModel>(a);
    const auto& sb = std::get<SurfaceModel>(b);
    expectSame(sa.family, sb.family);
    EXPECT_EQ(sa.orderV, sb.orderV);
    EXPECT_EQ(sa.closedU, sb.closedU);
    EXPECT_EQ(sa.closedV, sb.closedV);
    EXPECT_EQ(sa.rows, sb.rows);
    EXPECT_EQ(sa.cols, sb.cols);
    EXPECT_EQ(sa.points, sb.points);
    EXPECT_EQ(sa.alpha, sb.alpha);
    EXPECT_EQ(sa.knotsU, sb.knotsU);
    EXPECT_EQ(sa.knotsV, sb.knotsV);
  }
}

TEST(RoundTrip, EveryAcceptedModel) {
  for (const auto& text : acceptedModels()) {
    SCOPED_TRACE(text);
    const io::Model m = io::parseModelText(text);
    const json j = io::toJson(m);
    // Through text as well, the way a file would go.
    const io::Model back = io::parseModelText(j.dump());
    expectSameModel(m, back);
    EXPECT_EQ(io::toJson(back), j);
  }
}

TEST(RoundTrip, FullPrecisionDoubles) {
  CurveModel c;
  c.family.construction = Construction::AlphaEB;
  c.family.degree = 5;
  c.family.lambda = -1.0 / 3.0;
  c.dimension = 3;
  c.points = {{0.1, 1.0 / 3.0, -0.0}, {1e-300, 2.0 / 7.0, 123456789.123456789}, {std::nextafter(1.0, 2.0), -5e-324, 0.7}};
  c.alpha = {1.0 / 3.0, 1.0, std::nextafter(0.0, 1.0)};
  const auto back = io::parseModelText(io::toJson(c).dump());
  expectSameModel(io::Model(c), back);
}

TEST(RoundTrip, TwoDimensionalCurvesWrittenAsPairs) {
  const json j = io::toJson(io::parseModelText(kFormatExamples[0]));
  EXPECT_EQ(j.at("points")[0].size(), 2u);
  EXPECT_TRUE(j.at("alpha").is_array());
  const json s = io::toJson(io::parseModelText(kFormatExamples[1]));
  EXPECT_EQ(s.at("alpha").size(), 2u);       // rows
  EXPECT_EQ(s.at("alpha")[0].size(), 4u);    // cols
  EXPECT_EQ(s.at("closed"), json::array({false, true}));
}

// docs/format.md "Trim": the loops and the tolerance come back exactly through toJson, and a
// model without trim writes no key.
TEST(TrimLoops, RoundTripThroughJson) {
  const std::string text = R"({"kind": "surface", "construction": "bspline", "order": [2, 2],
    "knots": [[0, 0, 2, 2], [1, 1, 3, 3]], "points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]],
    "trim": {"loops": [[[0, 1], [2, 1], [2, 3], [0.5, 2.75]], [[0.5, 1.5], [0.75, 2.0], [1.0, 1.5]]],
             "tolerance": 1e-7}})";
  const SurfaceModel m = std::get<SurfaceModel>(io::parseModelText(text));
  ASSERT_EQ(m.trim.loops.size(), 2u);
  EXPECT_EQ(m.trim.loops[0].size(), 4u);
  EXPECT_EQ(m.trim.loops[0][3], glm::dvec2(0.5, 2.75));
  EXPECT_EQ(m.trim.tolerance, 1e-7);
  const SurfaceModel back = std::get<SurfaceModel>(io::parseModel(io::toJson(m)));
  EXPECT_EQ(back.trim.loops, m.trim.loops);
  EXPECT_EQ(back.trim.tolerance, m.trim.tolerance);
  SurfaceModel plain = m;
  plain.trim = {};
  EXPECT_FALSE(io::toJson(plain).contains("trim"));
}

}  // namespace
}  // namespace shapespline
