#pragma once
// What every fuzz seed writer needs: a file written whole or an exception, and a file name made
// from an id or example name that is safe in any folder.
#include <cctype>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace shapespline::fuzz {

inline void writeSeed(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// Letters, digits, '_', '-' and '.' stay; everything else becomes '_'.
inline std::string seedName(std::string name) {
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') c = '_';
  }
  return name;
}

}  // namespace shapespline::fuzz
