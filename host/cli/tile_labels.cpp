#include "tile_labels.h"

#include <shapespline/render/colour_map.h>

#include <imgui.h>

#include <algorithm>
#include <charconv>
#include <cmath>

namespace shapespline::cli {
namespace {

constexpr int kDesignPx = 13;  // ProggyClean is drawn on a 13 px grid

uint8_t toByte(float c) { return uint8_t(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f)); }

}  // namespace

std::string sweepLabel(std::string_view name, double value) {
  char digits[32];
  const auto end = std::to_chars(digits, digits + sizeof digits, value).ptr;  // shortest round trip
  return std::string(name) + " = " + std::string(digits, end);
}

LabelLayout labelLayout(int /*width*/, int height) {
  if (height < 64) return {};
  const int scale = std::clamp(height / 240, 1, 4);
  return {kDesignPx * scale, 3 * scale};
}

void drawHeader(render::Image& tile, const LabelFont& font, const LabelLayout& layout, const TileHeader& header,
                int left, const glm::vec3& ink) {
  const glm::vec3 band(kHeaderGrey);
  const int rows = std::min(tile.height, header.lines() * layout.lineHeight());
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < tile.width; ++x) {
      uint8_t* p = tile.rgba.data() + (size_t(y) * tile.width + x) * 4;
      p[0] = p[1] = p[2] = toByte(kHeaderGrey);
      p[3] = 255;
    }
  int y = 0;
  if (!header.title.empty()) {
    font.draw(tile, left, y, layout.pad, header.title, ink, band);
    y += layout.lineHeight();
  }
  const int gap = font.textWidth(" ");
  const auto fill = [&](int x0, int x1, int thickness, const auto& colourAt) {  // a strip across the line
    const int sy = y + layout.pad + (layout.fontPx - thickness) / 2;
    for (int py = sy; py < sy + thickness && py < tile.height; ++py)
      for (int px = x0; px < x1 && px < tile.width; ++px) {
        uint8_t* p = tile.rgba.data() + (size_t(py) * tile.width + px) * 4;
        const glm::vec3 c = colourAt(px);
        for (int k = 0; k < 3; ++k) p[k] = toByte(c[k]);
        p[3] = 255;
      }
  };
  int x = left + layout.pad;
  const auto text = [&](const std::string& t) {  // then a gap
    font.draw(tile, x - layout.pad, y, layout.pad, t, ink, band);
    x += font.textWidth(t) + gap;
  };
  // Each entry: a swatch two characters wide and a third of the text's height thick, then its text.
  const int swatchWidth = 2 * font.textWidth("m");
  for (const LegendEntry& e : header.legend) {
    fill(x, x + swatchWidth, std::max(2, layout.fontPx / 3), [&](int) { return e.colour; });
    x += swatchWidth + gap / 2;
    text(e.text);
    x += gap;
  }
  if (header.bar) {
    // The bar: twelve characters wide and as tall as the text, t from 0 at its left to 1 at its right.
    if (!header.bar->caption.empty()) text(header.bar->caption);
    text(header.bar->low);
    const int barWidth = 12 * font.textWidth("m"), x0 = x;
    fill(x0, x0 + barWidth, layout.fontPx, [&](int px) { return render::heatColour(double(px - x0) / (barWidth - 1)); });
    x += barWidth + gap;
    text(header.bar->high);
  }
}

LabelFont::LabelFont(int pixelHeight) : atlas_(std::make_unique<ImFontAtlas>()) {
  ImFontConfig config;
  config.SizePixels = float(pixelHeight);
  config.OversampleH = config.OversampleV = 1;  // one atlas texel per image pixel
  config.PixelSnapH = true;
  font_ = atlas_->AddFontDefault(&config);
  unsigned char* pixels = nullptr;
  atlas_->GetTexDataAsAlpha8(&pixels, &atlasWidth_, &atlasHeight_);
  coverage_ = pixels;
}

LabelFont::~LabelFont() = default;

int LabelFont::textWidth(std::string_view text) const {
  float width = 0.0f;
  for (unsigned char c : text) width += font_->FindGlyph(ImWchar(c))->AdvanceX;
  return int(std::ceil(width));
}

void LabelFont::draw(render::Image& image, int x, int y, int pad, std::string_view text, const glm::vec3& ink,
                     const glm::vec3& box) const {
  const auto blend = [&](int px, int py, const glm::vec3& colour, float a) {
    if (px < 0 || py < 0 || px >= image.width || py >= image.height || a <= 0.0f) return;
    uint8_t* p = image.rgba.data() + (size_t(py) * image.width + px) * 4;
    for (int k = 0; k < 3; ++k) p[k] = toByte(colour[k] * a + float(p[k]) / 255.0f * (1.0f - a));
    p[3] = 255;
  };
  const int boxWidth = textWidth(text) + 2 * pad, boxHeight = int(font_->FontSize) + 2 * pad;
  for (int py = y; py < y + boxHeight; ++py)
    for (int px = x; px < x + boxWidth; ++px) blend(px, py, box, 1.0f);
  float pen = float(x + pad);
  for (unsigned char c : text) {
    const ImFontGlyph* g = font_->FindGlyph(ImWchar(c));
    // The glyph's texels map one to one onto pixels (oversampling 1, pixel-snapped advances).
    const int u0 = int(std::lround(g->U0 * atlasWidth_)), v0 = int(std::lround(g->V0 * atlasHeight_));
    const int u1 = int(std::lround(g->U1 * atlasWidth_)), v1 = int(std::lround(g->V1 * atlasHeight_));
    const int gx = int(std::lround(pen + g->X0)), gy = y + pad + int(std::lround(g->Y0));
    for (int v = v0; v < v1; ++v)
      for (int u = u0; u < u1; ++u)
        blend(gx + (u - u0), gy + (v - v0), ink, float(coverage_[size_t(v) * atlasWidth_ + u]) / 255.0f);
    pen += g->AdvanceX;
  }
}

}  // namespace shapespline::cli
