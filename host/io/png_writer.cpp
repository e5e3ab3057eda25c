#include "io/png_writer.h"

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#if __has_include(<png.h>)
#include <png.h>
#define SHAPESPLINE_HAVE_PNG 1
#endif

namespace shapespline::io {

#ifdef SHAPESPLINE_HAVE_PNG
bool pngSupported() { return true; }

void writePng(const std::filesystem::path& path, int width, int height, std::span<const uint8_t> rgba,
              bool withAlpha) {
  if (width <= 0 || height <= 0 || rgba.size() != size_t(width) * size_t(height) * 4)
    throw std::invalid_argument("writePng: " + std::to_string(width) + " x " + std::to_string(height) +
                                " image needs " + std::to_string(size_t(width) * height * 4) + " bytes, got " +
                                std::to_string(rgba.size()));
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!file) throw std::runtime_error("cannot open '" + path.string() + "' for writing");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("libpng: out of memory");
  }
  const int channels = withAlpha ? 4 : 3;
  std::vector<uint8_t> row(size_t(width) * channels);
  // libpng reports errors by longjmp; nothing with a destructor lives between here and the calls.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("libpng failed while writing '" + path.string() + "'");
  }
  png_init_io(png, file.get());
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8,
               withAlpha ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) {
    const uint8_t* src = rgba.data() + size_t(y) * width * 4;
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < channels; ++c) row[size_t(x) * channels + c] = src[size_t(x) * 4 + c];
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(file.get()) != 0) throw std::runtime_error("writing '" + path.string() + "' failed");
}
#else
bool pngSupported() { return false; }
void writePng(const std::filesystem::path&, int, int, std::span<const uint8_t>, bool) {
  throw std::runtime_error("this build has no libpng: PNG output is unavailable");
}
#endif

}  // namespace shapespline::io
