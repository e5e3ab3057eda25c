// `render --sweep` contact sheets, read back from the PNG: every tile carries its parameter value as
// text in the light grey header band at its top (dark grey label pixels there, different pixels
// for different values, the same for the same value), the model fills the tile below the band (the
// bounding box of its pixels spans at least kMinFill of the width or of the height below the band)
// and stays clear of the band and of every tile edge; a single render fills its image and has no
// label. Surfaces
// and curves, overlays (--overlay: a legend colour per value, curves apart) and distance maps
// (--distance), and the contact sheet `demo` writes, whose tiles must show what λ and α change.
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <string>
#include <vector>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

constexpr double kMinFill = 0.85;  // of the tile's width or height, in the tighter direction
constexpr int kMinEdgeGap = 2;     // pixels between the model and a tile edge
constexpr int kMinLabelPixels = 30;

// Label text is grey (ink blended over the header band: r = g = b); nothing the model draws is (the
// surface is blue or brown, curves blue or a legend colour, the net blue-grey, points red, distance
// maps yellow to red).
bool labelPixel(const uint8_t* p) { return p[0] < 200 && p[0] == p[1] && p[1] == p[2]; }
bool background(const uint8_t* p) { return p[0] >= 250 && p[1] >= 250 && p[2] >= 250; }
// The header band's light grey (tile_labels.h kHeaderGrey, 0.93).
bool headerPixel(const uint8_t* p) { return p[0] == 237 && p[1] == 237 && p[2] == 237; }

struct TileFacts {
  int tx = 0, ty = 0;        // the tile's corner in the sheet
  int band = 0;              // rows of the header band (0: none)
  int labelPixels = 0;       // label ink in the label area
  int labelBottom = -1;      // last row holding a label pixel
  std::vector<uint8_t> labelArea;
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;  // the model's pixels below the band, inclusive
};

// The header band: the top rows whose last pixel (right of any text) is the band's grey. The label
// area: the top-left of the tile (the title lies inside it).
TileFacts tileFacts(const Rgb& sheet, int tx, int ty, int w, int h) {
  TileFacts f;
  f.tx = tx * w;
  f.ty = ty * h;
  while (f.band < h && headerPixel(sheet.at(f.tx + w - 1, f.ty + f.band))) ++f.band;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = sheet.at(f.tx + x, f.ty + y);
      const bool inLabelArea = y < h / 6 && x < w / 2;
      if (inLabelArea) f.labelArea.insert(f.labelArea.end(), p, p + 3);
      if (y < f.band) {
        f.labelPixels += inLabelArea && labelPixel(p);
        if (labelPixel(p)) f.labelBottom = std::max(f.labelBottom, y);
      } else if (labelPixel(p)) {
        f.labelBottom = std::max(f.labelBottom, y);  // ink below the band: the test below fails
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
      // Of the tile below its header band, which the camera fits the model into.
      const double fillX = double(f.x1 - f.x0 + 1) / w, fillY = double(f.y1 - f.y0 + 1) / (h - f.band);
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
    EXPECT_LT(tiles[k].labelBottom, tiles[k].band) << what << ": tile " << k + 1 << ": label ink below its band";
    EXPECT_GE(tiles[k].y0, tiles[k].band + kMinEdgeGap) << what << ": tile " << k + 1 << ": the model runs into the label";
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

// --overlay: a curve's values in one tile (stderr names each value's colour); --distance: one tile
// of the surface at the second value. Both framed below a two-line header.
TEST(RenderSweepCli, OverlayAndDistanceMapAreOneTileEach) {
  REQUIRE_VULKAN();
  std::string err;
  auto tiles = renderSheet("render " + quote(examplesDir() + "/open_aeb.json") +
                               " --sweep lambda=-15,0,1 --overlay --title \"open curve\"",
                           1, 1, 1, 400, 300, &err);
  ASSERT_EQ(tiles.size(), 1u);
  expectLabelled(tiles, "overlay");
  for (const char* text : {"lambda = -15: blue\n", "lambda = 0: orange\n", "lambda = 1: green\n"})
    EXPECT_TRUE(contains(err, text)) << err;
  tiles = renderSheet("render " + quote(examplesDir() + "/surface_aeb.json") + " --sweep alpha=1,0.1 --distance", 1, 1, 1,
                      400, 300, &err);
  ASSERT_EQ(tiles.size(), 1u);
  expectLabelled(tiles, "distance map");
  EXPECT_TRUE(contains(err, "alpha = 0.1, coloured by its distance from alpha = 1: at most ")) << err;
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

// ---- what the demo's sheet must show ---------------------------------------------------------------

using Colour = std::array<uint8_t, 3>;
Colour colourAt(const Rgb& sheet, int x, int y) {
  const uint8_t* p = sheet.at(x, y);
  return {p[0], p[1], p[2]};
}
int colourDistance(const Colour& a, const Colour& b) {
  return std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]);
}

// The colours in a tile's header band other than its greys (legend swatches, a colour bar), in the
// order they first appear from left to right.
std::vector<Colour> headerColours(const Rgb& sheet, const TileFacts& f, int w) {
  std::vector<Colour> out;
  for (int x = 0; x < w; ++x)
    for (int y = 0; y < f.band; ++y) {
      const Colour c = colourAt(sheet, f.tx + x, f.ty + y);
      if (c[0] == c[1] && c[1] == c[2]) continue;
      if (std::find(out.begin(), out.end(), c) == out.end()) out.push_back(c);
    }
  return out;
}

// The pixels of one colour below a tile's band (give or take the GPU's rounding), as a mask of the tile.
struct Mask {
  int w = 0, h = 0, count = 0;
  std::vector<uint8_t> on;
};
Mask pixelsOf(const Rgb& sheet, const TileFacts& f, int w, int h, const Colour& c) {
  Mask m{w, h, 0, std::vector<uint8_t>(size_t(w) * h, 0)};
  for (int y = f.band; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (colourDistance(colourAt(sheet, f.tx + x, f.ty + y), c) <= 3) m.on[size_t(y) * w + x] = 1, ++m.count;
  return m;
}

// The share of a's pixels that lie more than r pixels (in x or y) from every pixel of b: how much
// of one curve is drawn apart from the other.
double shareApart(const Mask& a, const Mask& b, int r) {
  if (a.count == 0) return 0.0;
  int apart = 0;
  for (int y = 0; y < a.h; ++y)
    for (int x = 0; x < a.w; ++x) {
      if (!a.on[size_t(y) * a.w + x]) continue;
      bool near = false;
      for (int dy = -r; dy <= r && !near; ++dy)
        for (int dx = -r; dx <= r && !near; ++dx) {
          const int u = x + dx, v = y + dy;
          near = u >= 0 && v >= 0 && u < b.w && v < b.h && b.on[size_t(v) * b.w + u];
        }
      apart += !near;
    }
  return double(apart) / a.count;
}

constexpr int kMinCurvePixels = 150;   // each overlaid value's curve is drawn, not hidden by the others
constexpr double kMinApart = 0.25;     // of the extreme values' curves, drawn more than 3 px apart
constexpr double kMinHotArea = 0.02;   // of a distance map's tile, coloured from halfway up its scale

// An overlay tile: one legend colour per value, each drawn as a curve, the extreme values' curves
// visibly apart.
void expectCurvesApart(const Rgb& sheet, const TileFacts& f, int w, int h, size_t values, const std::string& what) {
  const std::vector<Colour> legend = headerColours(sheet, f, w);
  ASSERT_EQ(legend.size(), values) << what << ": expected one legend colour per value";
  std::vector<Mask> curves;
  for (size_t k = 0; k < values; ++k) {
    curves.push_back(pixelsOf(sheet, f, w, h, legend[k]));
    EXPECT_GE(curves.back().count, kMinCurvePixels) << what << ": the curve of legend entry " << k + 1 << " is not drawn";
  }
  const double firstApart = shareApart(curves.front(), curves.back(), 3);
  const double lastApart = shareApart(curves.back(), curves.front(), 3);
  std::printf("%s: %.3f of the first value's curve and %.3f of the last's lie more than 3 px from the other\n",
              what.c_str(), firstApart, lastApart);
  EXPECT_GE(firstApart, kMinApart) << what << ": the extreme values draw nearly the same curve";
  EXPECT_GE(lastApart, kMinApart) << what << ": the extreme values draw nearly the same curve";
}

// A distance-map tile: a colour bar in the header, and a visible part of the tile coloured from
// halfway up the bar (the surface moved by half the scale's top or more there).
void expectVisibleDistance(const Rgb& sheet, const TileFacts& f, int w, int h, const std::string& what) {
  const std::vector<Colour> bar = headerColours(sheet, f, w);
  ASSERT_GE(bar.size(), 20u) << what << ": no colour bar in the header";
  int mapped = 0, hot = 0;
  for (int y = f.band; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Colour c = colourAt(sheet, f.tx + x, f.ty + y);
      size_t nearest = 0;
      for (size_t k = 1; k < bar.size(); ++k)
        if (colourDistance(c, bar[k]) < colourDistance(c, bar[nearest])) nearest = k;
      if (colourDistance(c, bar[nearest]) > 12) continue;  // background, patch lines
      ++mapped;
      hot += 2 * nearest >= bar.size() - 1;
    }
  const double area = double(w) * h;
  std::printf("%s: %.3f of the tile shows the map, %.3f from halfway up its scale\n", what.c_str(), mapped / area,
              hot / area);
  EXPECT_GE(mapped / area, 0.1) << what << ": the surface is hardly drawn";
  EXPECT_GE(hot / area, kMinHotArea) << what << ": the parameter change hardly moves the surface";
}

// `demo` ends with a 2 x 2 contact sheet of 480 x 360 tiles, each titled, and says to look there
// first: λ overlaid on an open curve (4 values), α on the closed butterfly (3 values), and the
// surface coloured by how far λ, then α, moves it.
TEST(DemoContactSheet, ShowsWhatLambdaAndAlphaChange) {
  REQUIRE_VULKAN();
  ScratchDir dir("demo_sheet");
  const CliResult r = runCli("demo", dir.path(), dir.path());
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "  shapespline-demo/contact_sheet.png\n")) << r.out;
  EXPECT_TRUE(contains(r.out, "Look first at shapespline-demo/contact_sheet.png")) << r.out;
  const int w = 480, h = 360;
  const Rgb sheet = readPng(dir / "shapespline-demo" / "contact_sheet.png");
  const auto tiles = sheetTiles(sheet, "demo", 4, 2, 2, w, h);
  ASSERT_EQ(tiles.size(), 4u);
  expectLabelled(tiles, "demo sheet");
  for (size_t i = 0; i < tiles.size(); ++i)
    for (size_t j = i + 1; j < tiles.size(); ++j)
      EXPECT_NE(tiles[i].labelArea, tiles[j].labelArea) << "demo tiles " << i + 1 << " and " << j + 1 << " share a title";
  expectCurvesApart(sheet, tiles[0], w, h, 4, "demo lambda overlay");
  expectCurvesApart(sheet, tiles[1], w, h, 3, "demo alpha overlay");
  expectVisibleDistance(sheet, tiles[2], w, h, "demo surface lambda map");
  expectVisibleDistance(sheet, tiles[3], w, h, "demo surface alpha map");
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
