// `render part.json` and `render FACE.json` of a trimmed face (docs/cad.md "Pictures of a part"):
// read back from the PNG, seen from above, the hole of the handmade faces' trim loops is background
// where the same surface without its loops is drawn; --edges adds dark edge pixels; options that
// belong to models or to meshes are refused (exit 2) for the other, as are bad deflections and a
// mesh over the triangle budget, and nothing is written.
#include "cli_runner.h"
#include "handmade_part.h"
#include "output_checks.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace shapespline::test
