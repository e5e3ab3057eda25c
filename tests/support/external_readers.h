#pragma once
// The readers we did not write that check our output files: Debian's /usr/bin/python3 (with
// numpy, and Open3D for meshes), assimp (`assimp info`, Debian assimp-utils) and the Khronos glTF validator (npm
// gltf-validator pinned in tests/tools/gltf, run by node). scripts/setup.sh installs all of them;
// a test that needs one that is missing skips with the reason.
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>

namespace shapespline::test {

inline constexpr const char* kSystemPython = "/usr/bin/python3";

// `text` single-quoted for sh.
inline std::string shellQuote(const std::string& text) {
  std::string q = "'";
  for (char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

struct ToolResult {
  int rc = -1;
  std::string out;  // stdout and stderr together
};

// Runs `command` with sh, stdout and stderr captured together.
inline ToolResult runTool(const std::string& command) {
  ToolResult r;
  FILE* p = ::popen(("(" + command + ") 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) r.out.append(buf, n);
  const int status = ::pclose(p);
  r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline std::string gltfValidatorScript() { return std::string(SHAPESPLINE_SOURCE_DIR) + "/tests/tools/gltf/validate.js"; }

// Why a reader cannot run here, or "".
inline std::string pythonNumpyMissing() {
  if (runTool(std::string(kSystemPython) + " -c 'import numpy'").rc != 0)
    return std::string(kSystemPython) + " with numpy is missing (install python3-numpy: scripts/setup.sh)";
  return "";
}
inline std::string open3dMissing() {
  if (runTool(std::string(kSystemPython) + " -c 'import open3d'").rc != 0)
    return std::string(kSystemPython) + " with open3d is missing (install python3-open3d: scripts/setup.sh)";
  return "";
}
inline std::string assimpMissing() {
  if (runTool("command -v assimp").rc != 0) return "assimp is missing (install assimp-utils: scripts/setup.sh)";
  return "";
}
inline std::string gltfValidatorMissing() {
  if (runTool("command -v node").rc != 0) return "node is missing (scripts/setup.sh installs it)";
  if (!std::filesystem::exists(std::string(SHAPESPLINE_SOURCE_DIR) +
                               "/tests/tools/gltf/node_modules/gltf-validator/package.json"))
    return "the glTF validator is not installed (scripts/setup.sh runs npm ci in tests/tools/gltf)";
  return "";
}

struct GltfValidation {
  int rc = -1;
  int errors = -1, warnings = -1, infos = -1, hints = -1;
  std::string report;  // the validator's whole output
};

// The Khronos validator's counts for `file` (a .glb, or a .gltf whose .bin lies beside it); -1
// when its summary line is missing.
inline GltfValidation validateGltf(const std::filesystem::path& file) {
  const ToolResult t = runTool("node " + shellQuote(gltfValidatorScript()) + " " + shellQuote(file.string()));
  GltfValidation v;
  v.rc = t.rc;
  v.report = t.out;
  std::smatch m;
  if (std::regex_search(t.out, m, std::regex("errors (\\d+) warnings (\\d+) infos (\\d+) hints (\\d+)"))) {
    v.errors = std::stoi(m[1]);
    v.warnings = std::stoi(m[2]);
    v.infos = std::stoi(m[3]);
    v.hints = std::stoi(m[4]);
  }
  return v;
}

}  // namespace shapespline::test
