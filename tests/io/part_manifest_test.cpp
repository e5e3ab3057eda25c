// io/part_manifest.h: part.json as `shapespline import` writes it (docs/cad.md), written by hand
// here: faces with their orientation and coedges, edges, shells; a manifest from before coedges
// (none in its faces, no edges or shells) still reads; each malformed key is refused by name.
#include <shapespline/core/model.h>
#include <shapespline/io/part_manifest.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <cmath>
#include <functional>
#include <string>

namespace shapespline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class PartManifestRead : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("shapespline_part_manifest_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    for (const char* name : {"face_0001.json", "face_0002.json"}) std::ofstream(root_ / name) << "{}";
  }
  void TearDown() override { fs::remove_all(root_); }

  // Two faces of a closed strip: face 1 with one loop over edges 1, 2 (a pole) and 3, face 2 with
  // edge 3 the other way and edge 1 twice (its seam); edge 2 degenerate; one shell of both.
  static json manifest() {
    return json::parse(R"({
      "format": "shapespline-part", "version": 1,
      "faces": [
        {"id": 1, "model": "face_0001.json", "surface": "Geom_Plane", "reversed": false, "loops": 1,
         "coedges": [[{"edge": 1, "start": 0, "t": [0, 0.5, 1]},
                      {"edge": 2, "start": 2, "t": [3, 4]},
                      {"edge": 3, "start": 3, "t": [1, 0]}]]},
        {"id": 2, "model": "face_0002.json", "surface": "Geom_CylindricalSurface", "reversed": true, "loops": 1,
         "coedges": [[{"edge": 3, "start": 0, "t": [0, 1]},
                      {"edge": 1, "start": 1, "t": [1, 0]},
                      {"edge": 1, "start": 2, "t": [0, 1]}]]},
        {"id": 3, "model": null, "skipped": "not converted"}
      ],
      "edges": [{"id": 1, "model": "edge_0001.json"}, {"id": 2, "model": null, "degenerate": true},
                {"id": 3, "model": "edge_0003.json"}],
      "shells": [{"id": 1, "faces": [1, 2]}]
    })");
  }
  fs::path write(const json& j) const {
    const fs::path p = root_ / "part.json";
    std::ofstream(p) << j.dump(1);
    return p;
  }
  // The ModelError reading `j` gives, or a failure when it is accepted.
  ModelError refusal(const json& j) const {
    try {
      io::readPartManifest(write(j));
    } catch (const ModelError& e) {
      return e;
    }
    ADD_FAILURE() << "accepted: " << j.dump();
    return ModelError("(accepted)", "", "");
  }
  fs::path root_;
};

TEST_F(PartManifestRead, ReadsFacesCoedgesEdgesAndShells) {
  const io::PartManifest m = io::readPartManifest(write(manifest()));
  ASSERT_EQ(m.faces.size(), 3u);
  EXPECT_EQ(m.skipped, 1);
  EXPECT_EQ(m.faces[0].surface, "Geom_Plane");
  EXPECT_FALSE(m.faces[0].reversed);
  EXPECT_TRUE(m.faces[1].reversed);
  ASSERT_EQ(m.faces[0].coedges.size(), 1u);
  ASSERT_EQ(m.faces[0].coedges[0].size(), 3u);
  EXPECT_EQ(m.faces[0].coedges[0][1].edge, 2);
  EXPECT_EQ(m.faces[0].coedges[0][1].start, 2);
  EXPECT_EQ(m.faces[0].coedges[0][0].t, (std::vector<double>{0, 0.5, 1}));
  EXPECT_EQ(m.faces[1].coedges[0][2].edge, 1);
  EXPECT_EQ(m.faces[1].coedges[0][1].t, (std::vector<double>{1, 0}));
  EXPECT_TRUE(m.faces[2].coedges.empty());
  ASSERT_EQ(m.edges.size(), 3u);
  EXPECT_EQ(m.edges[1].id, 2);
  EXPECT_TRUE(m.edges[1].degenerate);
  EXPECT_FALSE(m.edges[2].degenerate);
  ASSERT_EQ(m.shells.size(), 1u);
  EXPECT_EQ(m.shells[0], (std::vector<int>{1, 2}));
}

// A manifest written before coedges (and a hand-made one of faces alone) reads with none.
TEST_F(PartManifestRead, AManifestWithoutCoedgesStillReads) {
  json old = manifest();
  for (json& face : old["faces"]) face.erase("coedges");
  io::PartManifest m = io::readPartManifest(write(old));
  ASSERT_EQ(m.faces.size(), 3u);
  for (const io::PartFaceEntry& face : m.faces) EXPECT_TRUE(face.coedges.empty());
  EXPECT_EQ(m.edges.size(), 3u);

  json bare = {{"format", "shapespline-part"}, {"faces", {{{"id", 0}, {"model", "face_0001.json"}}}}};
  m = io::readPartManifest(write(bare));
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_TRUE(m.faces[0].coedges.empty());
  EXPECT_FALSE(m.faces[0].reversed);
  EXPECT_TRUE(m.edges.empty());
  EXPECT_TRUE(m.shells.empty());
}

TEST_F(PartManifestRead, RefusesMalformedCoedgesNamingTheKey) {
  struct Case {
    std::function<void(json&)> edit;
    std::string field, ruleHas;
  };
  const std::vector<Case> cases = {
      {[](json& j) { j["faces"][1]["coedges"][0][2]["edge"] = 99; }, "faces[1].coedges[0][2].edge",
       "not an edge id of the part"},
      {[](json& j) { j["faces"][0]["coedges"][0][0]["edge"] = "1"; }, "faces[0].coedges[0][0].edge",
       "not an edge id"},
      {[](json& j) { j["faces"][0]["coedges"][0][1]["start"] = -1; }, "faces[0].coedges[0][1].start",
       "non-negative"},
      {[](json& j) { j["faces"][0]["coedges"][0][1]["t"] = {3}; }, "faces[0].coedges[0][1].t", "at least 2"},
      {[](json& j) { j["faces"][0]["coedges"][0][1]["t"] = 3; }, "faces[0].coedges[0][1].t", "at least 2"},
      {[](json& j) { j["faces"][0]["coedges"][0][0]["t"][1] = "x"; }, "faces[0].coedges[0][0].t[1]", "finite"},
      // nlohmann writes a NaN as null: not a number.
      {[](json& j) { j["faces"][0]["coedges"][0][0]["t"][2] = std::nan(""); }, "faces[0].coedges[0][0].t[2]",
       "finite"},
      {[](json& j) { j["faces"][0]["coedges"][0][0].erase("start"); }, "faces[0].coedges[0][0]", "a coedge is"},
      {[](json& j) { j["faces"][0]["coedges"][0] = json::array(); }, "faces[0].coedges[0]", "non-empty"},
      {[](json& j) { j["faces"][0]["coedges"] = {{"edge", 1}}; }, "faces[0].coedges", "array of loops"},
      {[](json& j) { j["faces"][0]["reversed"] = 1; }, "faces[0].reversed", "true or false"},
      {[](json& j) { j["faces"][0]["surface"] = 5; }, "faces[0].surface", "string"},
      {[](json& j) { j["edges"][2]["id"] = 1; }, "edges[2].id", "earlier edge"},
      {[](json& j) { j["edges"][0]["id"] = -4; }, "edges[0]", "non-negative integer"},
      {[](json& j) { j["edges"][1]["degenerate"] = "yes"; }, "edges[1].degenerate", "true or false"},
      {[](json& j) { j["edges"] = 3; }, "edges", "array"},
      {[](json& j) { j["shells"][0]["faces"][1] = 7; }, "shells[0].faces[1]", "not a face id"},
      {[](json& j) { j["shells"][0].erase("faces"); }, "shells[0]", "\"faces\" array"},
  };
  for (const Case& c : cases) {
    json j = manifest();
    c.edit(j);
    const ModelError e = refusal(j);
    EXPECT_EQ(e.field(), c.field) << e.what();
    EXPECT_NE(e.rule().find(c.ruleHas), std::string::npos) << e.what();
    EXPECT_NE(e.rule().find("part.json"), std::string::npos) << e.what();  // names the manifest
  }
}

}  // namespace
}  // namespace shapespline
