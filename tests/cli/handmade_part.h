#pragma once
// Parts written by hand for the CLI tests that need no Open CASCADE: trimmed bicubic B-spline faces
// (docs/format.md Trim) and a part.json that names them, as `shapespline import` writes them
// (docs/cad.md). A face of N x M knot intervals has N*M patches: its share of a part's samples.
#include "cli_runner.h"

#include <filesystem>
#include <string>
#include <vector>

namespace shapespline::test {

// A bicubic face over [0, 1]^2 with `intervalsU` x `intervalsV` knot intervals, a wavy net offset by
// `shift` in z, trimmed by a square loop with a square hole (the even-odd rule keeps the ring).
inline std::string handmadeFace(int intervalsU, int intervalsV, double shift) {
  auto knots = [](int n) {
    std::string k = "[0,0,0";
    for (int i = 0; i <= n; ++i) k += "," + std::to_string(static_cast<double>(i) / n);
    return k + ",1,1,1]";
  };
  const int rows = intervalsU + 3, cols = intervalsV + 3;
  std::string net = "[";
  for (int i = 0; i < rows; ++i) {
    net += i ? ",[" : "[";
    for (int j = 0; j < cols; ++j) {
      const double x = static_cast<double>(i) / (rows - 1), y = static_cast<double>(j) / (cols - 1);
      const double z = shift + 0.1 * ((i * 7 + j * 3) % 5);
      net += (j ? ",[" : "[") + std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(z) + "]";
    }
    net += "]";
  }
  net += "]";
  return R"({"kind": "surface", "construction": "bspline", "order": [4, 4], "knots": [)" + knots(intervalsU) + "," +
         knots(intervalsV) + R"(], "closed": [false, false],
 "trim": {"loops": [[[0.05,0.05],[0.95,0.05],[0.95,0.95],[0.05,0.95]], [[0.4,0.4],[0.6,0.4],[0.6,0.6],[0.4,0.6]]],
          "tolerance": 1e-9},
 "points": )" + net + "}\n";
}

// DIR/part.json naming `models` in order as faces 0, 1, ... (a "" model is a face not converted).
// `handmadeCoedges`: each face's two loops (handmadeFace's 4-point square and hole) run along one
// edge of their own, as part::faceAsPart makes them, so that the part can be meshed.
inline void writePartManifest(const std::filesystem::path& dir, const std::vector<std::string>& models,
                              bool handmadeCoedges = false) {
  json faces = json::array(), edges = json::array();
  for (size_t i = 0; i < models.size(); ++i) {
    json face = {{"id", i}, {"model", models[i].empty() ? json(nullptr) : json(models[i])}};
    if (handmadeCoedges && !models[i].empty()) {
      json loops = json::array();
      for (int l = 0; l < 2; ++l) {
        const int edge = static_cast<int>(2 * i) + l + 1;
        edges.push_back({{"id", edge}});
        loops.push_back(json::array({{{"edge", edge}, {"start", 0}, {"t", {0, 1, 2, 3, 4}}}}));
      }
      face["coedges"] = loops;
    }
    faces.push_back(face);
  }
  writeText(dir / "part.json", json{{"format", "shapespline-part"}, {"faces", faces}, {"edges", edges}}.dump(1));
}

// DIR/face_I.json for each face's knot intervals, and DIR/part.json naming them (with coedges when
// `coedges`: a part the mesher takes).
inline void writeHandmadePart(const std::filesystem::path& dir, const std::vector<std::pair<int, int>>& intervals,
                              bool coedges = false) {
  std::filesystem::create_directories(dir);
  std::vector<std::string> names;
  for (size_t i = 0; i < intervals.size(); ++i) {
    names.push_back("face_" + std::to_string(i) + ".json");
    writeText(dir / names.back(), handmadeFace(intervals[i].first, intervals[i].second, static_cast<double>(i)));
  }
  writePartManifest(dir, names, coedges);
}

}  // namespace shapespline::test
