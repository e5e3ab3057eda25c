#include "tile_labels.h"

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
