#pragma once
// Runs the built shapespline binary (SHAPESPLINE_CLI) with stdout/stderr captured to files, and a
// scratch folder per test.
#include "support/external_readers.h"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

namespace shapespline::test {

using json = nlohmann::json;

struct CliResult {
  int rc = -1;
  std::string out, err;
};

inline std::string readText(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void writeText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream o(p, std::ios::binary);
  o << text;
}

// A fresh folder under the system temp folder, removed at the end of the test.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name) {
    path_ = std::filesystem::temp_directory_path() / ("shapespline_cli_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& f) const { return path_ / f; }
  // Names of every entry in the folder (to prove no temporary/partial file was left).
  std::vector<std::string> entries() const {
    std::vector<std::string> v;
    for (const auto& e : std::filesystem::directory_iterator(path_)) v.push_back(e.path().filename().string());
    return v;
  }

 private:
  std::filesystem::path path_;
};

inline std::string quote(const std::string& s) { return shellQuote(s); }

// Runs a shell command whose stdout/stderr go to `out`/`err`, then reads and removes both files.
inline CliResult runCaptured(const std::string& cmd, const std::filesystem::path& out,
                             const std::filesystem::path& err) {
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readText(out);
  r.err = readText(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

// Runs a shell command line (its last command's stdout/stderr captured through files in `scratch`).
inline CliResult runShell(const std::string& cmd, const std::filesystem::path& scratch) {
  const auto out = scratch / "_stdout.txt", err = scratch / "_stderr.txt";
  return runCaptured(cmd + " >" + quote(out.string()) + " 2>" + quote(err.string()), out, err);
}

// Runs `shapespline <args>` (args already shell-quoted where needed) in `cwd`.
inline CliResult runCli(const std::string& args, const std::filesystem::path& scratch,
                        const std::filesystem::path& cwd = {}) {
  return runShell(std::string(cwd.empty() ? "" : "cd " + quote(cwd.string()) + " && ") + quote(SHAPESPLINE_CLI) +
                      " " + args,
                  scratch);
}

inline std::string examplesDir() { return std::string(SHAPESPLINE_SOURCE_DIR) + "/examples/models"; }
// examples/models/NAME.
inline std::string exampleModel(const std::string& name) { return examplesDir() + "/" + name; }

// Debian's interpreter, the one that sees python3-numpy (another python3 may come first on PATH).
inline constexpr const char* kPython = kSystemPython;

}  // namespace shapespline::test
