#pragma once
// A check run on JSON text from files this process did not write (raw sidecars, shard records)
// before it is parsed: nlohmann's parser is recursive, so a crafted file nested deeply enough
// would exhaust the stack.
#include <string_view>

namespace shapespline::io {

// True when no value of `text` is nested deeper than `limit` (strings and escapes skipped).
inline bool jsonDepthWithin(std::string_view text, int limit) {
  int depth = 0;
  bool inString = false, escaped = false;
  for (char c : text) {
    if (inString) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limit) return false;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return true;
}

}  // namespace shapespline::io
