#pragma once
// A test process's own files in the system's temp folder, and reading a file back as bytes.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace shapespline::test {

// <temp>/shapespline_<prefix>_<pid>_<name>: the process id keeps test shards that run at once apart.
inline std::filesystem::path processTempFile(const std::string& prefix, const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("shapespline_" + prefix + "_" + std::to_string(::getpid()) + "_" + name);
}

inline std::vector<char> readBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace shapespline::test
