#pragma once
// Number formatting for the text writers: std::to_chars (shortest round-trip form, or a fixed
// number of significant digits), no locale, no iostreams in hot loops.
#include <shapespline/core/sample_grid.h>

#include <charconv>
#include <cstddef>

namespace shapespline::io {

// Largest text any of these produce.
inline constexpr size_t kMaxNumberChars = 32;

// Shortest text that parses back to exactly v (doubles: at most 17 significant digits) / exactly
// the float value (at most 9): std::to_chars without a precision (C++17 [charconv.to.chars]).
inline char* writeNumber(char* p, double v) { return std::to_chars(p, p + kMaxNumberChars, v).ptr; }
inline char* writeNumber(char* p, float v) { return std::to_chars(p, p + kMaxNumberChars, v).ptr; }
// The one form every text sample writer (OBJ, CSV) prints a value in: the shortest text of v as
// the file stores it, fp32 (v rounded to float) or fp64.
inline char* writeValue(char* p, double v, Precision filePrecision) {
  return filePrecision == Precision::Float ? writeNumber(p, static_cast<float>(v)) : writeNumber(p, v);
}
// 17 significant digits (printf %.17g), for error messages that show a value in full.
inline char* writeNumber17(char* p, double v) {
  return std::to_chars(p, p + kMaxNumberChars, v, std::chars_format::general, 17).ptr;
}
inline char* writeInteger(char* p, unsigned long long v) { return std::to_chars(p, p + kMaxNumberChars, v).ptr; }
inline char* writeInteger(char* p, long long v) { return std::to_chars(p, p + kMaxNumberChars, v).ptr; }

}  // namespace shapespline::io
