#pragma once
// Number formatting for the text writers: std::to_chars (shortest round-trip form, or a fixed
// number of significant digits), no locale, no iostreams in hot loops.
#include <charconv>
#include <cstddef>

namespace shapespline::io {

// Largest text any of these produce.
inline constexpr size_t kMaxNumberChars = 32;

// Shortest text that parses back to exactly v (doubles) / exactly the float value.
inline char* writeNumber(char* p, double v) { return std::to_chars(p, p + kMaxNumberChars, v).ptr; }
inline char* writeNumber(char* p, float v) { return std::to_chars(p, p + kMaxNumberChars, v).ptr; }
// 17 significant digits (printf %.17g), as the `eval` output promises.
inline char* writeNumber17(char* p, double v) {
  return std::to_chars(p, p + kMaxNumberChars, v, std::chars_format::general, 17).ptr;
}
inline char* writeInteger(char* p, unsigned long long v) { return std::to_chars(p, p + kMaxNumberChars, v).ptr; }
inline char* writeInteger(char* p, long long v) { return std::to_chars(p, p + kMaxNumberChars, v).ptr; }

}  // namespace shapespline::io
