// `render part.json` and `render FACE.json` of a trimmed face (docs/cad.md "Pictures of a part"):
// read back from the PNG, seen from above, the hole of the handmade faces' trim loops is background
// where the same surface without its loops is drawn; --edges adds dark edge pixels; options that
// belong to models or to meshes are refused (exit 2) for the other, as are bad deflections and a
// mesh over the triangle budget, and nothing is written. `render --deviation CLOUD` colours a cloud by
// its distance to the part: points far above it dark red, points near it pale.
#include "cli_runner.h"
#include "handmade_part.h"
#include "one_patch_models.h"
#include "output_checks.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <utility>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

bool backgroundPixel(const uint8_t* p) { return p[0] >= 250 && p[1] >= 250 && p[2] >= 250; }
bool darkPixel(const uint8_t* p) { return p[0] < 60 && p[1] < 60 && p[2] < 60; }

int countPixels(const Rgb& image, bool (*which)(const uint8_t*)) {
  int n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) n += which(image.at(x, y));
  return n;
}

class PartRender : public ::testing::Test {
 protected:
  void SetUp() override {
    writeHandmadePart(dir_ / "part", {{2, 2}, {3, 1}}, true);
    std::string untrimmed = handmadeFace(2, 2, 0.0);
    const size_t from = untrimmed.find("\"trim\""), to = untrimmed.find("\"points\"");
    untrimmed.erase(from, to - from);
    writeText(dir_ / "untrimmed.json", untrimmed);
  }
  CliResult render(const std::string& model, const std::string& out, const std::string& extra = "") {
    return runCli("render " + quote((dir_ / model).string()) + " --view 0,90 --size 160x120 -o " +
                      quote((dir_ / out).string()) + " " + extra,
                  dir_.path());
  }
  ScratchDir dir_{"part_render"};
};

TEST_F(PartRender, TheTrimLoopsHoleIsBackgroundWhereTheUntrimmedSurfaceIsDrawn) {
  REQUIRE_VULKAN();
  CliResult r = render("part/face_0.json", "face.png");
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "1 faces")) << r.err;
  ASSERT_EQ(render("untrimmed.json", "untrimmed.png").rc, 0);
  const Rgb face = readPng(dir_ / "face.png"), whole = readPng(dir_ / "untrimmed.png");
  ASSERT_EQ(face.width, 160);
  ASSERT_EQ(whole.width, 160);
  // The hole, [0.4, 0.6]^2 of the face's parameters, is around the picture's centre.
  for (const auto& [x, y] : {std::pair{80, 60}, std::pair{76, 57}, std::pair{84, 63}}) {
    EXPECT_TRUE(backgroundPixel(face.at(x, y))) << x << "," << y;
    EXPECT_FALSE(backgroundPixel(whole.at(x, y))) << x << "," << y;
  }
  // The ring around it is drawn: most of the picture is covered, less than the whole surface.
  const int covered = face.width * face.height - countPixels(face, backgroundPixel);
  const int wholeCovered = whole.width * whole.height - countPixels(whole, backgroundPixel);
  EXPECT_GT(covered, wholeCovered / 2);
  EXPECT_LT(covered, wholeCovered);
}

TEST_F(PartRender, APartIsDrawnWithItsEdgesWhenAsked) {
  REQUIRE_VULKAN();
  CliResult plain = render("part/part.json", "plain.png");
  ASSERT_EQ(plain.rc, 0) << plain.err;
  EXPECT_TRUE(contains(plain.err, "2 faces")) << plain.err;
  CliResult edged = render("part/part.json", "edges.png", "--edges");
  ASSERT_EQ(edged.rc, 0) << edged.err;
  const Rgb a = readPng(dir_ / "plain.png"), b = readPng(dir_ / "edges.png");
  ASSERT_GT(a.width, 0);
  ASSERT_GT(b.width, 0);
  // The outer square and the hole of the upper face, about 4 * 110 + 4 * 25 pixels of outline.
  EXPECT_GT(countPixels(b, darkPixel), countPixels(a, darkPixel) + 300);
  EXPECT_TRUE(backgroundPixel(b.at(80, 60)));
}

TEST_F(PartRender, OptionsOfTheOtherKindAndBadDeflectionsExitTwoAndWriteNothing) {
  REQUIRE_VULKAN();
  const struct {
    std::string model, extra, named;
  } cases[] = {
      {"part/part.json", "--rate 8", "--rate"},
      {"part/part.json", "--sweep lambda=0,1", "--sweep"},
      {"part/part.json", "--control-net", "--control-net"},
      {"untrimmed.json", "--deflection 0.01", "--deflection"},
      {"untrimmed.json", "--edges", "--edges"},
      {"part/part.json", "--deflection 0", "--deflection"},
      {"part/part.json", "--deflection nan", "--deflection"},
      {"part/part.json", "--relative-deflection -1", "--relative-deflection"},
      {"part/part.json", "--angle 4", "--angle"},
      {"part/part.json", "--max-triangles 10", "--relative-deflection"},
  };
  for (const auto& c : cases) {
    const CliResult r = render(c.model, "bad.png", c.extra);
    EXPECT_EQ(r.rc, 2) << c.extra << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, c.named)) << c.extra << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "bad.png")) << c.extra;
  }
}

// A CSV cloud over the handmade part (x, y in [0, 1]; the upper face at z 1 to 1.4): a block at
// x < 0.3 at height `leftZ` and a block at x > 0.7 at height `rightZ`.
void writeDeviationCloud(const fs::path& path, double leftZ, double rightZ) {
  std::string text = "x,y,z\n";
  char row[96];
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 40; ++j) {
      const double y = 0.05 + 0.9 * j / 39.0, dx = 0.25 * i / 11.0;
      std::snprintf(row, sizeof row, "%.6f,%.6f,%.6f\n%.6f,%.6f,%.6f\n", 0.05 + dx, y, leftZ, 0.7 + dx, y, rightZ);
      text += row;
    }
  writeText(path, text);
}

// heatColour from 0.8 up (dark red) and up to 0.25 (light yellow to orange); the grey shading has neither.
bool deepRedPixel(const uint8_t* p) { return p[0] > 100 && p[1] < 60 && p[2] < 80; }
bool warmLightPixel(const uint8_t* p) { return p[0] > 230 && p[1] > 150 && p[0] - p[2] > 60; }

// How many pixels from row y0 down are `which`, and their mean position.
std::pair<int, glm::dvec2> pixelsBelow(const Rgb& image, int y0, bool (*which)(const uint8_t*)) {
  int n = 0;
  glm::dvec2 sum(0.0);
  for (int y = y0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (which(image.at(x, y))) ++n, sum += glm::dvec2(x, y);
  return {n, n ? sum / double(n) : sum};
}

TEST_F(PartRender, ADeviationCloudIsColouredByItsDistanceToThePart) {
  REQUIRE_VULKAN();
  auto renderCloud = [&](const std::string& name, double leftZ, double rightZ) {
    writeDeviationCloud(dir_ / (name + ".csv"), leftZ, rightZ);
    const CliResult r = render("part/part.json", name + ".png", "--deviation " + quote((dir_ / (name + ".csv")).string()));
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "960 points")) << r.err;
    return readPng(dir_ / (name + ".png"));
  };
  // The upper face lies at z 1 to 1.4: the far block is 1.6 to 2 from it, the near one 0.1 to 0.5.
  const Rgb farLeft = renderCloud("far_left", 3.0, 1.5), farRight = renderCloud("far_right", 1.5, 3.0);
  ASSERT_EQ(render("part/part.json", "plain.png").rc, 0);
  const Rgb plain = readPng(dir_ / "plain.png");
  ASSERT_EQ(farLeft.width, 160);
  ASSERT_EQ(farRight.width, 160);
  EXPECT_EQ(pixelsBelow(plain, 0, deepRedPixel).first, 0);
  EXPECT_EQ(pixelsBelow(plain, 0, warmLightPixel).first, 0);
  // Below the header (whose colour bar holds both colours too) each block shows in its colour, and
  // the colours change places with the heights.
  const int below = farLeft.height / 4;
  const auto [redA, redAt] = pixelsBelow(farLeft, below, deepRedPixel);
  const auto [lightA, lightAt] = pixelsBelow(farLeft, below, warmLightPixel);
  const auto [redB, redBt] = pixelsBelow(farRight, below, deepRedPixel);
  const auto [lightB, lightBt] = pixelsBelow(farRight, below, warmLightPixel);
  EXPECT_GT(std::min({redA, lightA, redB, lightB}), 300);
  EXPECT_GT(glm::length(redAt - lightAt), 30.0);
  EXPECT_LT(glm::dot(redAt - lightAt, redBt - lightBt), 0.0);
}

TEST_F(PartRender, BadDeviationCloudsExitTwoAndWriteNothing) {
  REQUIRE_VULKAN();
  writeDeviationCloud(dir_ / "cloud.csv", 5.0, 1.7);
  writeText(dir_ / "nan.csv", "1,2,3\n4,nan,6\n");
  writeText(dir_ / "curve.json", kOneSpan);
  const std::string cloud = "--deviation " + quote((dir_ / "cloud.csv").string());
  const struct {
    std::string model, extra, named, rule;
  } cases[] = {
      {"part/part.json", "--deviation " + quote((dir_ / "absent.csv").string()), "--deviation", "absent.csv"},
      {"part/part.json", "--deviation " + quote((dir_ / "nan.csv").string()), "--deviation point 1", "finite"},
      {"curve.json", cloud, "--deviation", "not a curve"},
      {"untrimmed.json", cloud + " --sweep lambda=0,1", "--sweep", "deviation map"},
      {"untrimmed.json", cloud + " --distance", "--distance", "deviation map"},
  };
  for (const auto& c : cases) {
    const CliResult r = render(c.model, "bad.png", c.extra);
    EXPECT_EQ(r.rc, 2) << c.extra << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, c.named)) << c.extra << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, c.rule)) << c.extra << "\n" << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "bad.png")) << c.extra;
  }
}

}  // namespace
}  // namespace shapespline::test
