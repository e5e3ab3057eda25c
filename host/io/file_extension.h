#pragma once
// A file's extension in lower case (".PLY" -> ".ply"): formats are chosen by it, whatever its case.
#include <cctype>
#include <filesystem>
#include <string>

namespace shapespline::io {

inline std::string lowercaseExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace shapespline::io
