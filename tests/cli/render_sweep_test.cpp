// `render --sweep` contact sheets, read back from the PNG: every tile carries its parameter value as
// text in the band at its top (dark grey label pixels there, different pixels for different
// values, the same for the same value), the model fills the tile below the label (the bounding box
// of its pixels spans at least kMinFill of the tile's width or height) and stays clear of every
// tile edge; a single render fills its image and has no label. Surfaces and curves, and the
// contact sheet `demo` writes.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

constexpr double kMinFill = 0.85;  // of the tile's width or height, in the tighter direction
constexpr int kMinEdgeGap = 2;     // pixels between the model and a tile edge
constexpr int kMinLabelPixels = 30;

struct Rgb {
  int width = 0, height = 0;
  std::vector<uint8_t> px;
  const uint8_t* at(int x, int y) const { return px.data() + (size_t(y) * width + x) * 3; }
};

Rgb readPng(const fs::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  Rgb out;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return out;
  image.format = PNG_FORMAT_RGB;
  out.px.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, out.px.data(), 0, nullptr)) return {};
  out.width = int(image.width);
  out.height = int(image.height);
  return out;
}

// Label text is grey (ink blended over the background: r = g = b); nothing the model draws is (the
// surface is blue or brown, curves blue, the net blue-grey, points red).
bool labelPixel(const uint8_t* p) { return p[0] < 200 && p[0] == p[1] && p[1] == p[2]; }
bool background(const uint8_t* p) { return p[0] >= 250 && p[1] >= 250 && p[2] >= 250; }

struct TileFacts {
  int labelPixels = 0;
  int labelBottom = -1;  // last row holding a label pixel
  std::vector<uint8_t> labelArea;
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;  // the model's pixels, inclusive
};

// The label area: the top-left of the tile (the band the label is drawn in lies inside it).
TileFacts tileFacts(const Rgb& sheet, int tx, int ty, int w, int h) {
  TileFacts f;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = sheet.at(tx * w + x, ty * h + y);
      const bool inLabelArea = y < h / 6 && x < w / 2;
      if (inLabelArea) f.labelArea.insert(f.labelArea.end(), p, p + 3);
      if (labelPixel(p)) {
        f.labelPixels += inLabelArea;
        f.labelBottom = std::max(f.labelBottom, y);
      } else if (!background(p)) {
        f.x0 = std::min(f.x0, x);
        f.x1 = std::max(f.x1, x);
        f.y0 = std::min(f.y0, y);
        f.y1 = std::max(f.y1, y);
      }
    }
  return f;
}

// Checks each of a sheet's `count` tiles on cols x rows (`what` names the sheet in failures);
// returns their facts (row-major). A sheet's tiles past the last value stay blank.
std::vector<TileFacts> sheetTiles(const Rgb& sheet, const std::string& what, int count, int cols, int rows, int w,
                                  int h) {
  EXPECT_EQ(sheet.width, cols * w);
  EXPECT_EQ(sheet.height, rows * h);
  std::vector<TileFacts> tiles;
  if (sheet.width != cols * w || sheet.height != rows * h) return tiles;
  for (int ty = 0; ty < rows; ++ty)
    for (int tx = 0; tx < cols; ++tx) {
      const TileFacts f = tileFacts(sheet, tx, ty, w, h);
      const std::string name = what + ": tile " + std::to_string(ty * cols + tx + 1);
      if (ty * cols + tx >= count) {
        EXPECT_TRUE(f.x1 < 0 && f.labelBottom < 0) << name << ": a tile past the last value is not blank";
        continue;
      }
      EXPECT_GE(f.x1, 0) << name << ": no model drawn";
      if (f.x1 < 0) continue;
      const double fillX = double(f.x1 - f.x0 + 1) / w, fillY = double(f.y1 - f.y0 + 1) / h;
      std::printf("%s: model fills %.3f of the width, %.3f of the height; %d label pixels\n", name.c_str(), fillX,
                  fillY, f.labelPixels);
      EXPECT_GE(std::max(fillX, fillY), kMinFill) << name << ": the model leaves the tile mostly empty";
      EXPECT_GE(f.x0, kMinEdgeGap) << name;
      EXPECT_GE(f.y0, kMinEdgeGap) << name;
      EXPECT_LT(f.x1, w - kMinEdgeGap) << name;
      EXPECT_LT(f.y1, h - kMinEdgeGap) << name;
      tiles.push_back(f);
    }
  return tiles;
}

// Renders `args` as a sheet of `count` tiles of w x h on cols x rows and checks each.
std::vector<TileFacts> renderSheet(const std::string& args, int count, int cols, int rows, int w, int h,
                                   std::string* err = nullptr) {
  ScratchDir dir("render_sweep");
  const CliResult r = runCli(args + " --size " + std::to_string(w) + "x" + std::to_string(h) + " -o sheet.png",
                             dir.path(), dir.path());
  EXPECT_EQ(r.rc, 0) << r.err;
  if (err) *err = r.err;
  return sheetTiles(readPng(dir / "sheet.png"), args, count, cols, rows, w, h);
}

void expectLabelled(const std::vector<TileFacts>& tiles, const std::string& what) {
  for (size_t k = 0; k < tiles.size(); ++k) {
    EXPECT_GE(tiles[k].labelPixels, kMinLabelPixels) << what << ": tile " << k + 1 << " has no label";
    EXPECT_LT(tiles[k].labelBottom, tiles[k].y0) << what << ": tile " << k + 1 << ": the model runs into the label";
  }
}

TEST(RenderSweepCli, SurfaceTilesAreLabelledAndFilled) {
  REQUIRE_VULKAN();
  const std::string model = quote(examplesDir() + "/surface_aeb.json");
  std::string err;
  // Four values: a 4 x 1 sheet; 0.50 and 0.5 are the same value, so the same label.
  const auto tiles = renderSheet("render " + model + " --sweep lambda=-2,0.50,1,0.5", 4, 4, 1, 400, 300, &err);
  ASSERT_EQ(tiles.size(), 4u);
  expectLabelled(tiles, "surface sweep");
  EXPECT_NE(tiles[0].labelArea, tiles[1].labelArea) << "lambda -2 and 0.5 carry the same label";
  EXPECT_NE(tiles[1].labelArea, tiles[2].labelArea) << "lambda 0.5 and 1 carry the same label";
  EXPECT_EQ(tiles[1].labelArea, tiles[3].labelArea) << "lambda 0.50 and 0.5 are labelled differently";
  // The label's text, as stderr says it: the shortest decimal of each value.
  for (const char* text : {"tile 1: lambda = -2\n", "tile 2: lambda = 0.5\n", "tile 3: lambda = 1\n"})
    EXPECT_TRUE(contains(err, text)) << err;
}

TEST(RenderSweepCli, CurveTilesAreLabelledAndFilled) {
  REQUIRE_VULKAN();
  const std::string model = quote(examplesDir() + "/butterfly_aeb.json");
  std::string err;
  // Five values: a 3 x 2 sheet with one empty tile.
  const auto tiles = renderSheet("render " + model + " --sweep alpha=0.3,0.7,1,0.125,0.9", 5, 3, 2, 320, 240, &err);
  ASSERT_EQ(tiles.size(), 5u);
  expectLabelled(tiles, "curve sweep");
  for (size_t i = 0; i < tiles.size(); ++i)
    for (size_t j = i + 1; j < tiles.size(); ++j)
      EXPECT_NE(tiles[i].labelArea, tiles[j].labelArea) << "tiles " << i + 1 << " and " << j + 1 << " share a label";
  EXPECT_TRUE(contains(err, "tile 4: alpha = 0.125\n")) << err;
}

TEST(RenderSweepCli, ControlNetIsFramedWithTheSurface) {
  REQUIRE_VULKAN();
  const std::string model = quote(examplesDir() + "/surface_aeb.json");
  const auto tiles = renderSheet("render " + model + " --control-net --sweep lambda=0,1", 2, 2, 1, 400, 300);
  ASSERT_EQ(tiles.size(), 2u);
  expectLabelled(tiles, "surface sweep with its net");
}

TEST(RenderSweepCli, SingleRenderFillsTheImageWithoutALabel) {
  REQUIRE_VULKAN();
  for (const char* model : {"surface_aeb.json", "torus_aeb.json", "butterfly_aeb.json", "open_aeb.json", "nurbs_torus.json",
                            "bspline_surface.json"}) {
    const auto tiles = renderSheet("render " + quote(examplesDir() + "/" + model), 1, 1, 1, 400, 300);
    ASSERT_EQ(tiles.size(), 1u) << model;
    EXPECT_EQ(tiles[0].labelPixels, 0) << model << ": a single render has no label";
  }
}

// `demo` ends with a contact sheet of its α-EB surface at λ = -2, 0, 1 (three labelled 480 x 360
// tiles) and says to look there first.
TEST(DemoContactSheet, ThreeLabelledTilesOfTheSurface) {
  REQUIRE_VULKAN();
  ScratchDir dir("demo_sheet");
  const CliResult r = runCli("demo", dir.path(), dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "  shapespline-demo/contact_sheet.png\n")) << r.out;
  EXPECT_TRUE(contains(r.out, "Look first at shapespline-demo/contact_sheet.png")) << r.out;
  const auto tiles = sheetTiles(readPng(dir / "shapespline-demo" / "contact_sheet.png"), "demo", 3, 3, 1, 480, 360);
  ASSERT_EQ(tiles.size(), 3u);
  expectLabelled(tiles, "demo sheet");
  EXPECT_NE(tiles[0].labelArea, tiles[1].labelArea);
  EXPECT_NE(tiles[1].labelArea, tiles[2].labelArea);
}

// Without a Vulkan driver the demo still writes its models and samples, says why the sheet is
// missing, and succeeds.
TEST(DemoContactSheet, WithoutVulkanTheRestIsWrittenAndTheSheetNamed) {
  ScratchDir dir("demo_no_vulkan");
  const auto out = dir / "_stdout.txt", err = dir / "_stderr.txt";
  const CliResult r = runCaptured("cd " + quote(dir.path().string()) + " && VK_ICD_FILENAMES=/nonexistent.json " +
                                      quote(SHAPESPLINE_CLI) + " demo >" + quote(out.string()) + " 2>" +
                                      quote(err.string()),
                                  out, err);
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "notice: no shapespline-demo/contact_sheet.png: render needs a Vulkan device")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "shapespline-demo" / "contact_sheet.png"));
  EXPECT_FALSE(contains(r.out, "Look first")) << r.out;
  EXPECT_TRUE(fs::exists(dir / "shapespline-demo" / "surface_aeb_lambda_0.obj"));
}

}  // namespace
}  // namespace shapespline::test
