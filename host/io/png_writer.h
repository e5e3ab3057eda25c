#pragma once
// PNG output through libpng: 8-bit RGB or RGBA, rows top to bottom, written through an
// io::AtomicFile (so an old file is replaced only by a complete new one).
#include <shapespline/io/atomic_file.h>

#include <cstdint>
#include <filesystem>
#include <span>

namespace shapespline::io {

// True when the build found libpng (otherwise writePng throws std::runtime_error).
bool pngSupported();

// Encodes width x height pixels of 4 bytes (RGBA, row-major, top row first) into `out`; the
// caller commits it (alone or in an OutputSet). withAlpha = false drops the alpha channel. Throws
// std::invalid_argument for a size/data mismatch, OutputWriteError when a write fails and
// std::runtime_error when libpng fails.
void writePng(AtomicFile& out, int width, int height, std::span<const uint8_t> rgba, bool withAlpha = false);

// The same into `path`, committed atomically (OutputPathError for a path that cannot be used).
void writePng(const std::filesystem::path& path, int width, int height, std::span<const uint8_t> rgba,
              bool withAlpha = false);

}  // namespace shapespline::io
