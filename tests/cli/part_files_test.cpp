// The named-file rule for part manifests (docs/format.md "Files a model names"): every face file a
// part.json names lies inside the manifest's folder. A way out (`..`, an absolute path, a link that
// leads out) or a missing file is exit 2 naming the manifest and the key, with nothing written and
// nothing of the named file quoted; a link that stays inside is followed.
#include "cli_runner.h"
#include "handmade_part.h"

#include <gtest/gtest.h>

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

class PartFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    writeHandmadePart(dir_ / "part", {{1, 1}, {2, 1}});
    fs::create_directories(dir_ / "elsewhere");
    // What a foreign file holds must never reach stderr: not a model, and a model outside alike.
    writeText(dir_ / "elsewhere" / "hostname", "vm-secret-host\n");
    writeText(dir_ / "elsewhere" / "face.json", handmadeFace(1, 1, 0.0));
  }
  CliResult sample(const std::string& extra = "") {
    return runCli("sample " + quote((dir_ / "part" / "part.json").string()) + " --grid 4 --device cpu -o " +
                      quote((dir_ / "cloud.npy").string()) + extra,
                  dir_.path());
  }
  ScratchDir dir_{"part_files"};
};

TEST_F(PartFiles, FaceFilesOutsideTheManifestsFolderAreRefused) {
  fs::create_symlink(dir_ / "elsewhere" / "hostname", dir_ / "part" / "link_out.json");
  fs::create_symlink(dir_ / "elsewhere", dir_ / "part" / "dir_out");
  struct Case {
    std::string model, rule;
  };
  const Case cases[] = {
      {"../../../../../../../../etc/hostname", "is outside the folder of"},
      {"../elsewhere/hostname", "is outside the folder of"},
      {"../elsewhere/face.json", "is outside the folder of"},
      {"/etc/hostname", "an absolute path is outside the folder of"},
      {(dir_ / "elsewhere" / "face.json").string(), "an absolute path is outside the folder of"},
      {"link_out.json", "the file (after links) is outside the folder of"},
      {"dir_out/face.json", "the file (after links) is outside the folder of"},
      {"face_9.json", "no such file in the folder of"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.model);
    writePartManifest(dir_ / "part", {"face_0.json", "", "face_1.json", c.model});
    const CliResult r = sample();
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("shapespline: error: faces[3].model: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.rule + " " + (dir_ / "part" / "part.json").string()), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("vm-secret"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "cloud.npy"));
  }
}

TEST_F(PartFiles, LinksThatStayInsideAreFollowed) {
  fs::create_directories(dir_ / "part" / "faces");
  fs::rename(dir_ / "part" / "face_1.json", dir_ / "part" / "faces" / "face_1.json");
  fs::create_symlink("faces/face_1.json", dir_ / "part" / "face_1_link.json");
  writePartManifest(dir_ / "part", {"face_0.json", "face_1_link.json", "faces/../face_0.json"});
  const CliResult r = sample();
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.err.find("(3 faces, "), std::string::npos) << r.err;
}

// A face file inside the folder that is not JSON at all: refused naming the face's key, its bytes
// not quoted (they may be anything the folder holds).
TEST_F(PartFiles, AFaceFileThatIsNoModelIsNotQuoted) {
  writeText(dir_ / "part" / "notes.json", "vm-secret-host: not a model\n");
  writePartManifest(dir_ / "part", {"face_0.json", "notes.json"});
  const CliResult r = sample();
  EXPECT_EQ(r.rc, 2) << r.err;
  EXPECT_NE(r.err.find("faces[1].model (notes.json): "), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("vm-secret"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "cloud.npy"));
}

// The manifest is recognised however far into it its "format" key comes (import writes it after
// every face and edge; a 1,018-face part's manifest is over 64 KiB).
TEST_F(PartFiles, ALargeManifestIsStillAPart) {
  std::vector<std::string> models(3000, "");  // faces not converted at import: listed, skipped
  models[0] = "face_0.json";
  models[2999] = "face_1.json";
  writePartManifest(dir_ / "part", models);
  ASSERT_GT(fs::file_size(dir_ / "part" / "part.json"), 64u * 1024u);
  const CliResult r = sample();
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.err.find("(2 faces, "), std::string::npos) << r.err;
}

}  // namespace
}  // namespace shapespline::test
