// The progress bar: shown on stderr only when stderr is a terminal, the job is long (>= 4 M
// points) and --quiet is not given. The terminal comes from script(1) (util-linux, always in
// Debian), which runs the command on a pseudo-terminal.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace {

namespace fs = std::filesystem;

std::string capture(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return out;
  char buffer[4096];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  ::pclose(pipe);
  return out;
}

class CliProgress : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists("/usr/bin/script")) GTEST_SKIP() << "script(1) is not installed: no pseudo-terminal to test with";
    dir_ = fs::temp_directory_path() / ("shapespline_progress_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  // `sample` of the example surface at 512x512 per patch (16 patches: 4.19 M points) on the CPU.
  std::string sampleCommand(const std::string& extra) const {
    return std::string(SHAPESPLINE_CLI) + " sample " + SHAPESPLINE_SOURCE_DIR +
           "/examples/models/surface_aeb.json --grid 512 --device cpu --precision float -o " +
           (dir_ / "big.f32").string() + " " + extra;
  }
  std::string onTerminal(const std::string& command) const {
    return capture("script -qfec '" + command + "' /dev/null");
  }
  fs::path dir_;
};

TEST_F(CliProgress, ShownOnATerminalForLongJobs) {
  const std::string out = onTerminal(sampleCommand(""));
  EXPECT_NE(out.find("100.0%"), std::string::npos) << out;
  EXPECT_NE(out.find("4194304 / 4194304 points"), std::string::npos) << out;
}

TEST_F(CliProgress, NotShownWithQuietOrWithoutATerminal) {
  const std::string quiet = onTerminal(sampleCommand("--quiet"));
  EXPECT_EQ(quiet.find('%'), std::string::npos) << quiet;
  const std::string piped = capture(sampleCommand(""));
  EXPECT_EQ(piped.find('%'), std::string::npos) << piped;
  EXPECT_NE(piped.find("wrote"), std::string::npos) << piped;
}

}  // namespace
