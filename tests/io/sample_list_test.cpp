// io/sample_list.h (issue 12): `eval --at` sample lists read and checked against a curve or surface.
#include <shapespline/io/sample_list.h>

#include <gtest/gtest.h>

#include <string>
#include <variant>

#include <shapespline/io/input_file.h>
#include <shapespline/io/model_json.h>

namespace shapespline {
namespace {

using nlohmann::json;

Curve exampleCurve(const std::string& name) {
  return Curve::create(
      std::get<CurveModel>(io::loadModelFile(std::string(SHAPESPLINE_SOURCE_DIR) + "/examples/models/" + name)));
}
Surface exampleSurface() {
  return Surface::create(std::get<SurfaceModel>(
      io::loadModelFile(std::string(SHAPESPLINE_SOURCE_DIR) + "/examples/models/surface_aeb.json")));
}

// The ModelError of parsing `text` against the curve (or surface), as "field|rule".
std::string curveError(const std::string& text, const Curve& c) {
  try {
    io::parseCurveSamples(json::parse(text), c);
  } catch (const ModelError& e) {
    return e.field() + "|" + e.rule();
  }
  return "accepted";
}
std::string surfaceError(const std::string& text, const Surface& s) {
  try {
    io::parseSurfaceSamples(json::parse(text), s);
  } catch (const ModelError& e) {
    return e.field() + "|" + e.rule();
  }
  return "accepted";
}

TEST(SampleList, CurveSamples) {
  const Curve c = exampleCurve("open_aeb.json");
  const SpanRange r = c.spans();
  const auto s = io::parseCurveSamples(
      json::parse("{\"samples\": [{\"span\": " + std::to_string(r.last) + ", \"t\": 0.25}, {\"u\": 1.5}]}"), c);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_FALSE(s[0].global);
  EXPECT_EQ(s[0].span, r.last);
  EXPECT_EQ(s[0].t, 0.25);
  EXPECT_TRUE(s[1].global);
  EXPECT_EQ(s[1].u, 1.5);
  EXPECT_EQ(curveError("[]", c), "--at|expected an object {\"samples\": [...]}");
  EXPECT_EQ(curveError(R"({"samples": [1]})", c), "--at.samples[0]|must be an object");
  EXPECT_EQ(curveError(R"({"samples": [{"t": 0}]})", c), "--at.samples[0].span|missing");
  EXPECT_EQ(curveError(R"({"samples": [{"span": 0.5, "t": 0}]})", c), "--at.samples[0].span|must be an integer");
  EXPECT_EQ(curveError(R"({"samples": [{"span": 1e300, "t": 0}]})", c), "--at.samples[0].span|must be an integer");
  EXPECT_EQ(curveError(R"({"samples": [{"span": 99, "t": 0}]})", c),
            "--at.samples[0].span|must be in [" + std::to_string(r.first) + ", " + std::to_string(r.last) + "]");
  EXPECT_EQ(curveError(R"({"samples": [{"span": 0, "t": 1.5}]})", c), "--at.samples[0].t|must be in [0, 1]");
  EXPECT_EQ(curveError(R"({"samples": [{"span": 0, "t": "0"}]})", c), "--at.samples[0].t|must be a number");
  EXPECT_EQ(curveError(R"({"samples": [{"span": 0}]})", c), "--at.samples[0].t|missing");
}

TEST(SampleList, KnotVectorCurvesTakeGlobalParameters) {
  const Curve c = exampleCurve("clamped_bspline.json");
  ASSERT_TRUE(c.usesKnotVector());
  EXPECT_EQ(curveError(R"({"samples": [{"u": 0.5}]})", c), "accepted");
  EXPECT_EQ(curveError(R"({"samples": [{"span": 0, "t": 0}]})", c),
            "--at.samples[0]|a knot-vector B-spline takes {\"u\": value}");
}

TEST(SampleList, SurfaceSamples) {
  const Surface s = exampleSurface();
  const auto q = io::parseSurfaceSamples(json::parse(R"({"samples": [{"patch": [0, 0], "uv": [0.5, 1]}]})"), s);
  ASSERT_EQ(q.size(), 1u);
  EXPECT_EQ(q[0].patchU, 0);
  EXPECT_EQ(q[0].v, 1.0);
  EXPECT_EQ(surfaceError(R"({"samples": [{"uv": [0, 0]}]})", s), "--at.samples[0].patch|must be [i, j]");
  EXPECT_EQ(surfaceError(R"({"samples": [{"patch": [0, 0], "uv": [0]}]})", s), "--at.samples[0].uv|must be [u, v]");
  EXPECT_EQ(surfaceError(R"({"samples": [{"patch": [0, 99], "uv": [0, 0]}]})", s).substr(0, 31),
            "--at.samples[0].patch[1]|must b");
  EXPECT_EQ(surfaceError(R"({"samples": [{"patch": [0, 0], "uv": [0, -0.5]}]})", s),
            "--at.samples[0].uv[1]|must be a number in [0, 1]");
}

TEST(SampleList, ValuesInErrorsAreShort) {
  const Curve c = exampleCurve("open_aeb.json");
  std::string big = "[0";
  for (int i = 0; i < 100'000; ++i) big += ",0";
  try {
    io::parseCurveSamples(json::parse("{\"samples\": [" + big + "]]}"), c);
    FAIL() << "accepted";
  } catch (const ModelError& e) {
    EXPECT_LE(e.value().size(), io::kMaxValueChars);
  }
}

TEST(SampleList, CountLimit) {
  const Curve c = exampleCurve("open_aeb.json");
  json doc = {{"samples", json::array()}};
  for (size_t i = 0; i <= io::kMaxSamples; ++i) doc["samples"].push_back(json{{"u", 1.0}});
  try {
    io::parseCurveSamples(doc, c);
    FAIL() << "accepted";
  } catch (const ModelError& e) {
    EXPECT_EQ(e.field(), "--at");
    EXPECT_EQ(e.value(), "1000001 samples");
  }
}

}  // namespace
}  // namespace shapespline
