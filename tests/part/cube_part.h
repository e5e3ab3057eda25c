#pragma once
// The part tests' closed shell: the cube [0, size]^3 of six planar faces written as `import` writes
// a part (DIR/part.json, a face file each, the coedges and one shell).
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

namespace shapespline::part {

inline void writeJson(const std::filesystem::path& path, const nlohmann::json& j) { std::ofstream(path) << j.dump(); }

inline nlohmann::json planarFace(glm::dvec3 o, glm::dvec3 u, glm::dvec3 v) {
  using nlohmann::json;
  json points = json::array();
  for (int i = 0; i < 2; ++i) {
    json row = json::array();
    for (int j = 0; j < 2; ++j) {
      const glm::dvec3 p = o + double(i) * u + double(j) * v;
      row.push_back({p.x, p.y, p.z});
    }
    points.push_back(row);
  }
  return {{"kind", "surface"}, {"construction", "bspline"}, {"order", {2, 2}},
          {"knots", {{0, 0, 1, 1}, {0, 0, 1, 1}}}, {"closed", {false, false}},
          {"trim", {{"loops", {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}}, {"tolerance", 1e-9}}}, {"points", points}};
}

// DIR/part.json and six face files of the cube [0, size]^3, with the coedges import writes: each
// of the 12 edges parametrised from its lower-numbered corner (t = 0) to the other (t = 1).
inline void writeCube(const std::filesystem::path& dir, double size) {
  using nlohmann::json;
  std::filesystem::create_directories(dir);
  const glm::dvec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  std::map<std::pair<int, int>, int> edgeIds;
  json faces = json::array(), edges = json::array(), shell = json::array();
  const auto corner = [&](glm::dvec3 p) {
    return int(std::lround(p.x / size)) + 2 * int(std::lround(p.y / size)) + 4 * int(std::lround(p.z / size));
  };
  int id = 0;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      ++id;
      const glm::dvec3 u = size * axes[(a + 1) % 3], v = size * axes[(a + 2) % 3];  // u x v along axis a
      const glm::dvec3 o = double(side) * size * axes[a];
      const std::string name = "face_" + std::to_string(id) + ".json";
      writeJson(dir / name, planarFace(o, u, v));
      const glm::dvec2 uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      json loop = json::array();
      for (int k = 0; k < 4; ++k) {
        const int from = corner(o + uv[k].x * u + uv[k].y * v);
        const int to = corner(o + uv[(k + 1) % 4].x * u + uv[(k + 1) % 4].y * v);
        const auto key = std::minmax(from, to);
        auto [it, added] = edgeIds.try_emplace(key, int(edgeIds.size()) + 1);
        if (added) edges.push_back({{"id", it->second}, {"curve", "Geom_Line"}, {"model", nullptr}});
        loop.push_back({{"edge", it->second}, {"start", k}, {"t", from < to ? json{0.0, 1.0} : json{1.0, 0.0}}});
      }
      faces.push_back({{"id", id}, {"model", name}, {"reversed", side == 0}, {"surface", "Geom_Plane"},
                       {"coedges", json::array({loop})}});
      shell.push_back(id);
    }
  writeJson(dir / "part.json", {{"format", "shapespline-part"}, {"faces", faces}, {"edges", edges},
                                {"shells", json::array({{{"id", 1}, {"faces", shell}}})}});
}

}  // namespace shapespline::part
