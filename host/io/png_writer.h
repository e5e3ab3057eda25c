#pragma once
// PNG output through libpng: 8-bit RGB or RGBA, rows top to bottom.
#include <cstdint>
#include <filesystem>
#include <span>

namespace shapespline::io {

// True when the build found libpng (otherwise writePng throws std::runtime_error).
bool pngSupported();

// Writes width x height pixels of 4 bytes (RGBA, row-major, top row first) to `path`. withAlpha =
// false drops the alpha channel. Throws std::invalid_argument for a size/data mismatch and
// std::runtime_error when the file cannot be written.
void writePng(const std::filesystem::path& path, int width, int height, std::span<const uint8_t> rgba,
              bool withAlpha = false);

}  // namespace shapespline::io
