#pragma once
// Text labels on rendered tiles (`render --sweep`): Dear ImGui's embedded font (ProggyClean,
// ASCII only) rasterised on the CPU by ImGui's font atlas and blended into a read-back RGBA image.
// No GPU backend and no ImGui context; ImGui stays inside the executable (nothing installed links it).
#include <shapespline/render/renderer.h>

#include <glm/vec3.hpp>

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

struct ImFontAtlas;
struct ImFont;

namespace shapespline::cli {

// "lambda = 0.5": the parameter's name and the shortest decimal that reads back as `value`.
std::string sweepLabel(std::string_view name, double value);

// Where a tile's label goes: a band across the top of the tile, kept free of the model.
struct LabelLayout {
  int fontPx = 0;  // 13 (ProggyClean's design size) times a whole scale, so the glyphs stay crisp
  int pad = 0;     // around the text, inside the band
  int lineHeight() const { return fontPx + 2 * pad; }
};

// The header band's colour: a light grey strip across the whole tile, which sets the text apart
// from the drawing (label ink is dark grey, r = g = b, on it).
inline constexpr float kHeaderGrey = 0.93f;

// One line of a legend: a swatch of the colour a curve is drawn in, then its text.
struct LegendEntry {
  std::string text;
  glm::vec3 colour;
};

// A colour bar of render::heatColour from t = 0 to 1: "caption low [bar] high".
struct ColourBar {
  std::string caption, low, high;
};

// What a tile's header says: a title line (the tile's name, or the sweep value of its tile) and a
// line with a legend or a colour bar; any of them may be absent.
struct TileHeader {
  std::string title;
  std::vector<LegendEntry> legend;
  std::optional<ColourBar> bar;
  int lines() const { return int(!title.empty()) + int(!legend.empty() || bar.has_value()); }
};

class LabelFont;

// Paints `header` over the top lines of `tile`: the band across the whole width, then the title and
// the legend from x = `left`. Rows painted: header.lines() * layout.lineHeight().
void drawHeader(render::Image& tile, const LabelFont& font, const LabelLayout& layout, const TileHeader& header,
                int left, const glm::vec3& ink);

// The layout for a tile of width x height pixels: the text grows with the tile (13 px per 240 px of
// height, 1 to 4 times); none (fontPx 0) for tiles under 64 px high.
LabelLayout labelLayout(int width, int height);

class LabelFont {
 public:
  explicit LabelFont(int pixelHeight);
  ~LabelFont();
  LabelFont(const LabelFont&) = delete;
  LabelFont& operator=(const LabelFont&) = delete;

  // Width of `text` in pixels (the sum of the glyphs' advances).
  int textWidth(std::string_view text) const;
  // Paints a box of `box` colour around `text` (`pad` pixels each side) with its top-left corner at
  // (x, y), then the text in `ink`, blended by the glyphs' coverage; clipped to the image. Painted
  // pixels become opaque (alpha 255).
  void draw(render::Image& image, int x, int y, int pad, std::string_view text, const glm::vec3& ink,
            const glm::vec3& box) const;

 private:
  std::unique_ptr<ImFontAtlas> atlas_;
  ImFont* font_ = nullptr;
  const unsigned char* coverage_ = nullptr;  // the atlas, one byte per pixel
  int atlasWidth_ = 0, atlasHeight_ = 0;
};

}  // namespace shapespline::cli
