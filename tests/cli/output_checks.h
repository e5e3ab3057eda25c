#pragma once
// Checks shared by the CLI tests: the Vulkan probe, PNG pictures read back, folder listings, and reading every number of
// an output file back (text, binary, PLY, SVG) to prove that no NaN or Inf was written.
#include "cli_runner.h"

#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace shapespline::test {

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// True when `shapespline info` selects a Vulkan device (lavapipe counts).
inline bool vulkanDevice() {
  static const bool yes = [] {
    ScratchDir dir("vulkan_probe");
    const CliResult r = runCli("info", dir.path());
    return r.rc == 0 && r.out.find("selected: none") == std::string::npos;
  }();
  return yes;
}

#define REQUIRE_VULKAN() \
  if (!::shapespline::test::vulkanDevice()) GTEST_SKIP() << "no Vulkan device"

struct Rgb {
  int width = 0, height = 0;
  std::vector<uint8_t> px;
  const uint8_t* at(int x, int y) const { return px.data() + (size_t(y) * width + x) * 3; }
};

// A PNG read back as RGB, top row first; empty (width 0) when it cannot be read.
inline Rgb readPng(const std::filesystem::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  Rgb out;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return out;
  image.format = PNG_FORMAT_RGB;
  out.px.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, out.px.data(), 0, nullptr)) return {};
  out.width = int(image.width);
  out.height = int(image.height);
  return out;
}

// Entries of a folder other than the runner's capture files, sorted.
inline std::vector<std::string> entries(const std::filesystem::path& folder) {
  std::vector<std::string> v;
  for (const auto& e : std::filesystem::directory_iterator(folder)) {
    const std::string n = e.path().filename().string();
    if (n != "_stdout.txt" && n != "_stderr.txt") v.push_back(n);
  }
  std::sort(v.begin(), v.end());
  return v;
}

// Every token of a text output that strtod reads entirely must be finite ("nan", "-nan", "inf" in
// any spelling are read by strtod too, so they are caught). Returns how many numbers were read.
inline size_t expectFiniteText(const std::string& text, const std::string& what) {
  size_t n = 0;
  std::string token;
  auto flush = [&] {
    if (token.empty()) return;
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() + token.size()) {
      ++n;
      EXPECT_TRUE(std::isfinite(v)) << what << ": non-finite number '" << token << "'";
    }
    token.clear();
  };
  for (char c : text) {
    if (std::isspace(static_cast<unsigned char>(c)) || std::strchr(",[]{}\":/=", c)) flush();
    else token += c;
  }
  flush();
  return n;
}

template <class T>
void expectFiniteBinary(const char* data, size_t bytes, const std::string& what) {
  ASSERT_EQ(bytes % sizeof(T), 0u) << what;
  for (size_t i = 0; i < bytes / sizeof(T); ++i) {
    T v;
    std::memcpy(&v, data + i * sizeof(T), sizeof(T));
    ASSERT_TRUE(std::isfinite(v)) << what << ": value " << i << " is " << v;
  }
}

// PLY (binary little endian): the vertex block, property by property (s t included).
inline void expectFinitePly(const std::string& bytes, const std::string& what) {
  const size_t end = bytes.find("end_header\n");
  ASSERT_NE(end, std::string::npos) << what;
  std::istringstream header(bytes.substr(0, end));
  std::string line;
  size_t vertices = 0;
  std::vector<int> sizes;
  bool inVertex = false;
  while (std::getline(header, line)) {
    std::istringstream ls(line);
    std::string a, b, c;
    ls >> a >> b >> c;
    if (a == "element") {
      inVertex = b == "vertex";
      if (inVertex) vertices = std::stoull(c);
    } else if (a == "property" && inVertex) {
      ASSERT_TRUE(b == "float" || b == "double") << what << ": " << line;
      sizes.push_back(b == "float" ? 4 : 8);
    }
  }
  const char* p = bytes.data() + end + std::strlen("end_header\n");
  ASSERT_GT(vertices, 0u) << what;
  for (size_t v = 0; v < vertices; ++v) {
    for (int s : sizes) {
      ASSERT_LE(p + s, bytes.data() + bytes.size()) << what;
      if (s == 4) expectFiniteBinary<float>(p, 4, what);
      else expectFiniteBinary<double>(p, 8, what);
      p += s;
    }
  }
}

// SVG: every coordinate attribute, the viewBox and the size.
inline void expectFiniteSvg(const std::string& text, const std::string& what) {
  static const std::regex attr(R"re(\b(points|cx|cy|x|y|x1|y1|x2|y2|r|viewBox|width|height)="([^"]*)")re");
  size_t n = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), attr); it != std::sregex_iterator(); ++it) {
    n += expectFiniteText((*it)[2].str(), what + " attribute " + (*it)[1].str());
  }
  EXPECT_GT(n, 10u) << what;
}

// Every number of an output file (by extension) is finite; text formats must hold some numbers.
inline void expectFiniteOutput(const std::filesystem::path& file, const std::string& what) {
  const std::string ext = file.extension().string();
  const std::string bytes = readText(file);
  ASSERT_FALSE(bytes.empty()) << what;
  if (ext == ".ply") {
    expectFinitePly(bytes, what);
  } else if (ext == ".f64") {
    expectFiniteBinary<double>(bytes.data(), bytes.size(), what);
  } else if (ext == ".f32") {
    expectFiniteBinary<float>(bytes.data(), bytes.size(), what);
  } else if (ext == ".svg") {
    expectFiniteSvg(bytes, what);
  } else {
    EXPECT_GT(expectFiniteText(bytes, what), 10u) << what;
  }
}

// Runs `script` (written to DIR/check.py) with Debian's /usr/bin/python3 in DIR, with `args`, and
// expects exit status 0 and "OK" on stdout (each script prints it after its asserts).
inline void expectPythonOk(const ScratchDir& dir, const std::string& script, const std::vector<std::string>& args) {
  writeText(dir / "check.py", script);
  std::string cmd = "cd " + quote(dir.path().string()) + " && /usr/bin/python3 check.py";
  for (const auto& a : args) cmd += " " + quote(a);
  const auto out = dir / "_py_out.txt", err = dir / "_py_err.txt";
  const CliResult r = runCaptured(cmd + " >" + quote(out.string()) + " 2>" + quote(err.string()), out, err);
  EXPECT_EQ(r.rc, 0) << r.out << r.err;
  EXPECT_TRUE(contains(r.out, "OK")) << r.out << r.err;
}

}  // namespace shapespline::test
