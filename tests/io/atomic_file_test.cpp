// io::AtomicFile and io::OutputSet (issue 12): unpredictable temporary names created with
// O_EXCL|O_NOFOLLOW and mode 0600, the replaced file's mode kept, a set committed as a whole (a
// failed rename puts every target back), the same path twice refused, temporary files removed on
// SIGTERM.
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/output_set.h>

#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace shapespline::io {
namespace {

namespace fs = std::filesystem;

class Scratch {
 public:
  explicit Scratch(const std::string& name)
      : path_(fs::temp_directory_path() / ("shapespline_atomic_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  fs::path operator/(const std::string& f) const { return path_ / f; }
  const fs::path& path() const { return path_; }
  std::vector<std::string> entries() const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(path_)) v.push_back(e.path().filename().string());
    std::sort(v.begin(), v.end());
    return v;
  }

 private:
  fs::path path_;
};

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void writeAll(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

mode_t modeOf(const fs::path& p) {
  struct stat st {};
  EXPECT_EQ(::stat(p.c_str(), &st), 0) << p;
  return st.st_mode & 07777;
}

// Sets SHAPESPLINE_IO_FAULT for one scope.
class IoFaultScope {
 public:
  explicit IoFaultScope(const char* value) { ::setenv("SHAPESPLINE_IO_FAULT", value, 1); }
  ~IoFaultScope() { ::unsetenv("SHAPESPLINE_IO_FAULT"); }
};

TEST(AtomicFile, TemporaryNameIsHiddenRandomAndPrivate) {
  Scratch dir("name");
  AtomicFile a(dir / "out.csv"), b(dir / "out.csv");
  const std::regex pattern(R"(\.out\.csv\.tmp-[0-9a-f]{16})");
  for (const AtomicFile* f : {&a, &b}) {
    EXPECT_EQ(f->tempPath().parent_path(), dir.path());
    EXPECT_TRUE(std::regex_match(f->tempPath().filename().string(), pattern)) << f->tempPath();
    EXPECT_EQ(modeOf(f->tempPath()), 0600u) << "the temporary file must be private until commit";
  }
  EXPECT_NE(a.tempPath(), b.tempPath()) << "two writers of one target must not share a temporary name";
}

TEST(AtomicFile, SymlinkAtTheOldPredictableNameIsNotFollowed) {
  Scratch dir("symlink");
  writeAll(dir / "victim", "precious\n");
  // The name the writer used before issue 12: OUT.tmp.<pid>.
  fs::create_symlink(dir / "victim", dir / ("out.csv.tmp." + std::to_string(::getpid())));
  AtomicFile f(dir / "out.csv");
  f.write("new\n");
  f.commit();
  EXPECT_EQ(readAll(dir / "victim"), "precious\n") << "the planted symlink's target was written through";
  EXPECT_TRUE(fs::is_symlink(dir / ("out.csv.tmp." + std::to_string(::getpid()))));
  EXPECT_FALSE(fs::is_symlink(dir / "out.csv"));
  EXPECT_EQ(readAll(dir / "out.csv"), "new\n");
}

TEST(AtomicFile, ReplacedFileKeepsItsMode) {
  Scratch dir("mode");
  writeAll(dir / "secret.csv", "old\n");
  fs::permissions(dir / "secret.csv", fs::perms(0600));
  AtomicFile f(dir / "secret.csv");
  f.write("new\n");
  f.commit();
  EXPECT_EQ(readAll(dir / "secret.csv"), "new\n");
  EXPECT_EQ(modeOf(dir / "secret.csv"), 0600u);
}

TEST(AtomicFile, NewFileGetsTheUmaskMode) {
  Scratch dir("umask");
  const mode_t old = ::umask(027);
  {
    AtomicFile f(dir / "new.csv");
    f.write("x\n");
    f.commit();
  }
  ::umask(old);
  EXPECT_EQ(modeOf(dir / "new.csv"), 0640u);
}

TEST(AtomicFile, DiscardRemovesTheTemporaryFile) {
  Scratch dir("discard");
  {
    AtomicFile f(dir / "out.csv");
    f.write("partial");
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(OutputSet, CommitsEveryFile) {
  Scratch dir("set");
  OutputSet set;
  set.add(dir / "a.f32", "-o").write("data");
  set.add(dir / "a.f32.json", "-o").write("side");
  EXPECT_EQ(dir.entries().size(), 2u);  // the two temporary files
  set.commit();
  EXPECT_EQ(readAll(dir / "a.f32"), "data");
  EXPECT_EQ(readAll(dir / "a.f32.json"), "side");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.f32", "a.f32.json"}));
}

TEST(OutputSet, FailedSecondRenameRestoresTheWholeOldSet) {
  Scratch dir("restore");
  writeAll(dir / "a.f32", "old data");
  writeAll(dir / "a.f32.json", "old side");
  fs::permissions(dir / "a.f32", fs::perms(0600));
  {
    OutputSet set;
    set.add(dir / "a.f32", "-o").write("new data");
    set.add(dir / "a.f32.json", "-o").write("new side");
    IoFaultScope fault("rename:2");
    try {
      set.commit();
      FAIL() << "the injected rename failure was not reported";
    } catch (const OutputWriteError& e) {
      EXPECT_NE(std::string(e.what()).find("a.f32.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(kIoFaultNote), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(readAll(dir / "a.f32"), "old data") << "new data beside the old sidecar";
  EXPECT_EQ(readAll(dir / "a.f32.json"), "old side");
  EXPECT_EQ(modeOf(dir / "a.f32"), 0600u);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a.f32", "a.f32.json"})) << "a temporary or backup file was left";
}

TEST(OutputSet, FailedRenameOfANewSetLeavesNothing) {
  Scratch dir("restore_new");
  {
    OutputSet set;
    set.add(dir / "x.csv", "-o").write("table");
    set.add(dir / "x.svg", "--svg").write("<svg/>");
    set.add(dir / "x.png", "--png").write("png");
    IoFaultScope fault("rename:3");
    EXPECT_THROW(set.commit(), OutputWriteError);
  }
  EXPECT_TRUE(dir.entries().empty());
}

// Past 64 files a commit syncs the filesystem once instead of each file (an import's thousands of
// face files): the files are all there after it, and a failed rename still restores the whole set.
TEST(OutputSet, ALargeSetCommitsEveryFileAndAFailedRenameRestoresIt) {
  Scratch dir("large");
  const int files = 150;
  const auto name = [](int i) { return "face_" + std::to_string(1000 + i) + ".json"; };
  {
    OutputSet set;
    for (int i = 0; i < files; ++i) set.add(dir / name(i), "-o").write("first " + std::to_string(i));
    set.commit();
  }
  ASSERT_EQ(dir.entries().size(), size_t(files));
  for (int i = 0; i < files; ++i) EXPECT_EQ(readAll(dir / name(i)), "first " + std::to_string(i));
  {
    OutputSet set;
    for (int i = 0; i < files; ++i) set.add(dir / name(i), "-o").write("second " + std::to_string(i));
    set.add(dir / "part.json", "-o").write("{}");
    IoFaultScope fault("rename:120");
    EXPECT_THROW(set.commit(), OutputWriteError);
  }
  ASSERT_EQ(dir.entries().size(), size_t(files)) << "a temporary or backup file was left, or part.json written";
  for (int i = 0; i < files; ++i) EXPECT_EQ(readAll(dir / name(i)), "first " + std::to_string(i));
}

TEST(OutputSet, SamePathTwiceIsRefusedNamingBothOptions) {
  Scratch dir("dup");
  fs::create_directories(dir / "sub");
  fs::create_directory_symlink(dir / "sub", dir / "link");
  OutputSet set;
  set.add(dir / "sub" / "x", "-o");
  for (const fs::path& again : {dir / "sub" / "x", dir / "sub" / "." / "x", dir / "link" / ".." / "sub" / "x",
                                dir / "link" / "x"}) {
    try {
      set.add(again, "--svg");
      FAIL() << again << " was accepted as a second output";
    } catch (const OutputPathError& e) {
      EXPECT_EQ(e.option(), "--svg");
      EXPECT_NE(e.reason().find("-o"), std::string::npos) << e.reason();
    }
  }
  EXPECT_EQ(set.size(), 1u);
  set.discard();
  EXPECT_TRUE(fs::is_empty(dir / "sub"));
}

TEST(OutputSet, SigtermRemovesLiveTemporaryFiles) {
  Scratch dir("signal");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    installTempFileCleanup();
    OutputSet set;
    set.add(dir / "a.f32", "-o").write("data");
    set.add(dir / "a.f32.json", "-o").write("side");
    ::raise(SIGTERM);
    ::_exit(0);  // not reached
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status;
  EXPECT_TRUE(dir.entries().empty()) << dir.entries().size() << " files left";
}

}  // namespace
}  // namespace shapespline::io
