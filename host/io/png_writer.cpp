#include <shapespline/io/png_writer.h>

#include <exception>
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
namespace {

// libpng's I/O goes through these callbacks into the AtomicFile. libpng reports errors by longjmp
// and is C: an exception must not unwind through it, so a failed write is kept here and libpng
// is stopped with png_error (nothing with a destructor is alive in the callback at that point).
struct Sink {
  AtomicFile* out = nullptr;
  std::exception_ptr error;
};

void writeData(png_structp png, png_bytep data, size_t size) {
  auto* sink = static_cast<Sink*>(png_get_io_ptr(png));
  bool failed = false;
  try {
    sink->out->write(data, size);
  } catch (...) {
    sink->error = std::current_exception();
    failed = true;
  }
  if (failed) png_error(png, "write failed");
}

void flushData(png_structp) {}  // AtomicFile::commit flushes and fsyncs

}  // namespace

bool pngSupported() { return true; }

void writePng(AtomicFile& out, int width, int height, std::span<const uint8_t> rgba, bool withAlpha) {
  if (width <= 0 || height <= 0 || rgba.size() != size_t(width) * size_t(height) * 4)
    throw std::invalid_argument("writePng: " + std::to_string(width) + " x " + std::to_string(height) +
                                " image needs " + std::to_string(size_t(width) * height * 4) + " bytes, got " +
                                std::to_string(rgba.size()));
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("libpng: out of memory");
  }
  const int channels = withAlpha ? 4 : 3;
  std::vector<uint8_t> row(size_t(width) * channels);
  // On the heap: a local modified between setjmp and longjmp would be indeterminate afterwards.
  const auto sink = std::make_unique<Sink>();
  sink->out = &out;
  // libpng reports errors by longjmp back here; the objects above live in this frame and survive it.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    if (sink->error) std::rethrow_exception(sink->error);
    throw std::runtime_error("libpng failed while writing '" + out.target().string() + "'");
  }
  png_set_write_fn(png, sink.get(), &writeData, &flushData);
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
}
#else
bool pngSupported() { return false; }
void writePng(AtomicFile&, int, int, std::span<const uint8_t>, bool) {
  throw std::runtime_error("this build has no libpng: PNG output is unavailable");
}
#endif

void writePng(const std::filesystem::path& path, int width, int height, std::span<const uint8_t> rgba,
              bool withAlpha) {
  if (!pngSupported()) throw std::runtime_error("this build has no libpng: PNG output is unavailable");
  AtomicFile out(path, "-o");
  writePng(out, width, height, rgba, withAlpha);
  out.commit();
}

}  // namespace shapespline::io
