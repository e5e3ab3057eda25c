// io/named_file.h: the one rule for files a model or a part manifest names (docs/format.md "Files a
// model names"): inside the naming file's folder, links followed, nothing of the file read.
#include <shapespline/core/model.h>
#include <shapespline/io/named_file.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace shapespline {
namespace {

namespace fs = std::filesystem;

class NamedFile : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("shapespline_named_file_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(folder() / "sub");
    fs::create_directories(root_ / "elsewhere");
    for (const fs::path& p : {folder() / "a.npy", folder() / "sub" / "b.json", root_ / "elsewhere" / "secret"})
      std::ofstream(p) << "secret bytes";
    fs::create_symlink(root_ / "elsewhere" / "secret", folder() / "out_link");
    fs::create_symlink("sub/b.json", folder() / "in_link.json");
    fs::create_symlink(root_ / "elsewhere", folder() / "out_dir");
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path folder() const { return root_ / "part"; }
  io::NamedFileRule rule() const {
    io::NamedFileRule r;
    r.folder = folder();
    r.namer = "part.json";
    return r;
  }
  // The ModelError `name` gets at `key`, or a failure when it is accepted.
  ModelError refusal(const std::string& name, const std::string& key = "faces[3].model") const {
    try {
      io::resolveNamedFile(rule(), name, key);
    } catch (const ModelError& e) {
      return e;
    }
    ADD_FAILURE() << name << " was accepted";
    return ModelError(key, name, "(accepted)");
  }
  fs::path root_;
};

TEST_F(NamedFile, NamesInsideTheFolderResolveThere) {
  EXPECT_EQ(io::resolveNamedFile(rule(), "a.npy", "points"), folder() / "a.npy");
  EXPECT_EQ(io::resolveNamedFile(rule(), "sub/b.json", "k"), folder() / "sub" / "b.json");
  EXPECT_EQ(io::resolveNamedFile(rule(), "sub/../a.npy", "k"), folder() / "sub/../a.npy");  // `..` that stays in
  EXPECT_EQ(io::resolveNamedFile(rule(), "in_link.json", "k"), folder() / "in_link.json");  // a link within
}

TEST_F(NamedFile, EveryWayOutIsRefusedNamingTheKeyTheNamerAndTheRule) {
  struct Case {
    std::string name, rule;
  };
  const Case cases[] = {
      {"../elsewhere/secret", "is outside the folder of part.json"},
      {"../../../../../../etc/hostname", "is outside the folder of part.json"},
      {(root_ / "elsewhere" / "secret").string(), "an absolute path is outside the folder of part.json"},
      {"/etc/hostname", "an absolute path is outside the folder of part.json"},
      {"out_link", "the file (after links) is outside the folder of part.json"},
      {"out_dir/secret", "the file (after links) is outside the folder of part.json"},
      {"missing.json", "no such file in the folder of part.json"},
      {"sub/missing.json", "no such file in the folder of part.json"},
      {"", "the file name is empty"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const ModelError e = refusal(c.name);
    EXPECT_EQ(e.field(), "faces[3].model");
    EXPECT_NE(e.rule().find(c.rule), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("secret bytes"), std::string::npos) << e.what();
  }
}

TEST_F(NamedFile, TheCallerMayAllowNamesOutside) {
  io::NamedFileRule r = rule();
  r.allowOutside = true;
  r.allowHint = "allow it with --allow-outside-arrays";
  EXPECT_EQ(io::resolveNamedFile(r, "../elsewhere/secret", "points"), folder() / "../elsewhere/secret");
  EXPECT_EQ(io::resolveNamedFile(r, "out_link", "points"), folder() / "out_link");
  r.allowOutside = false;
  try {
    io::resolveNamedFile(r, "out_link", "points");
    ADD_FAILURE() << "accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(e.rule().find("allow it with --allow-outside-arrays"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace shapespline
