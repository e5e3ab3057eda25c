// Issue 12 at the command line, outputs: the files of one job appear together or not at all (raw
// data + sidecar, -o + --svg, a PNG), also when two processes write the same -o at once; the same
// path twice is refused; temporary files are unpredictable, never follow a planted symlink, keep
// the replaced file's mode and are removed on SIGINT/SIGTERM/SIGHUP (and SIGPIPE); `render` writes
// atomically and refuses a bad -o as bad input; a failed write to stdout is exit 3 everywhere.
//
// SHAPESPLINE_TEST_CLI=/path/to/shapespline runs these tests against another binary (e.g. one
// built before the fixes, to see them fail).
#include "cli_runner.h"
#include "output_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <regex>
#include <spawn.h>
#include <sys/stat.h>
#include <thread>

extern char** environ;

namespace shapespline::test {
namespace {

namespace fs = std::filesystem;

std::string cli() {
  const char* other = std::getenv("SHAPESPLINE_TEST_CLI");
  return other && *other ? other : SHAPESPLINE_CLI;
}

// `shapespline <args>` through the shell; `redirect` replaces the stdout capture (e.g. ">/dev/full"),
// `prefix` goes before the binary (environment, ulimit).
CliResult run(const std::string& args, const fs::path& scratch, const std::string& prefix = "",
              const std::string& redirect = "") {
  const auto out = scratch / "_stdout.txt", err = scratch / "_stderr.txt";
  const std::string cmd = "cd " + quote(scratch.string()) + " && " + prefix + " " + quote(cli()) + " " + args + " " +
                          (redirect.empty() ? ">" + quote(out.string()) : redirect) + " 2>" + quote(err.string());
  return runCaptured(cmd, out, err);
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += x + " ";
  return s;
}

mode_t modeOf(const fs::path& p) {
  struct stat st {};
  EXPECT_EQ(::stat(p.c_str(), &st), 0) << p;
  return st.st_mode & 07777;
}

bool vulkanDevice() {
  static const bool yes = [] {
    ScratchDir dir("outset_probe");
    const CliResult r = run("info", dir.path());
    return r.rc == 0 && r.out.find("selected: none") == std::string::npos;
  }();
  return yes;
}

const char* kGbModel = R"({"kind": "curve", "construction": "gb", "lambda": 0, "closed": false,
  "points": [[0, 0], [1, 3], [4, 3], [5, 0]]})";
const char* kGbThrough = "2.154296875,2.873046875";

// ---- One commit per output set -----------------------------------------------------------------

TEST(OutputSetCli, SamePathTwiceIsRefused) {
  ScratchDir dir("outset_dup");
  writeText(dir / "gb.json", kGbModel);
  fs::create_directories(dir / "d");
  const std::vector<std::pair<std::string, std::string>> jobs = {
      {"basis --family gb --lambda 0.5", "basis"},
      {"gb-fit gb.json --span 1 --through " + std::string(kGbThrough), "gb-fit"},
      {"extend " + quote(exampleModel("clamped_bspline.json")) + " --to 10,4", "extend"},
  };
  for (const auto& [job, name] : jobs) {
    for (const std::string& second : {std::string("d/X"), std::string("./d/../d/X")}) {
      const CliResult r = run(job + " -o d/X --svg " + second, dir.path());
      EXPECT_EQ(r.rc, 2) << name << " " << second << ": " << r.err;
      EXPECT_TRUE(contains(r.err, "shapespline: error: --svg:") && contains(r.err, "-o")) << name << ": " << r.err;
      EXPECT_TRUE(entries(dir / "d").empty()) << name << " left " << joined(entries(dir / "d"));
    }
  }
}

TEST(OutputSetCli, FailedSidecarRenameKeepsTheOldRawSet) {
  ScratchDir dir("outset_raw");
  const std::string model = quote(exampleModel("gb_curve.json"));
  ASSERT_EQ(run("sample " + model + " -o a.f32 --samples 8 --device cpu -q", dir.path()).rc, 0);
  const std::string oldData = readText(dir / "a.f32"), oldSide = readText(dir / "a.f32.json");
  // The second rename of the commit (the sidecar) fails.
  const CliResult r =
      run("sample " + model + " -o a.f32 --samples 16 --device cpu -q", dir.path(), "SHAPESPLINE_IO_FAULT=rename:2");
  EXPECT_EQ(r.rc, 3) << r.err;
  EXPECT_TRUE(contains(r.err, "a.f32.json")) << r.err;
  EXPECT_TRUE(readText(dir / "a.f32") == oldData) << "new data beside the old sidecar";
  EXPECT_TRUE(readText(dir / "a.f32.json") == oldSide);
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"a.f32", "a.f32.json"}));
  // A new set: neither file appears.
  const CliResult n =
      run("sample " + model + " -o b.f64 --samples 16 --device cpu -q", dir.path(), "SHAPESPLINE_IO_FAULT=rename:2");
  EXPECT_EQ(n.rc, 3) << n.err;
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"a.f32", "a.f32.json"}));
}

TEST(OutputSetCli, FailedSvgRenameKeepsTheOldModelAndPlot) {
  ScratchDir dir("outset_svg");
  writeText(dir / "gb.json", kGbModel);
  writeText(dir / "X.csv", "old table\n");
  writeText(dir / "X.svg", "old plot\n");
  writeText(dir / "M.json", "old model\n");
  writeText(dir / "M.svg", "old plot\n");
  const std::vector<std::string> jobs = {
      "basis --family gb --lambda 0.5 -o X.csv --svg X.svg",
      "gb-fit gb.json --span 1 --through " + std::string(kGbThrough) + " -o M.json --svg M.svg",
      "extend " + quote(exampleModel("clamped_bspline.json")) + " --to 10,4 -o M.json --svg M.svg",
  };
  for (const auto& job : jobs) {
    const CliResult r = run(job, dir.path(), "SHAPESPLINE_IO_FAULT=rename:2");
    EXPECT_EQ(r.rc, 3) << job << ": " << r.err;
    EXPECT_TRUE(readText(dir / "X.csv") == "old table\n") << job;
    EXPECT_TRUE(readText(dir / "X.svg") == "old plot\n") << job;
    EXPECT_TRUE(readText(dir / "M.json") == "old model\n") << job;
    EXPECT_TRUE(readText(dir / "M.svg") == "old plot\n") << job;
    EXPECT_EQ(entries(dir.path()).size(), 5u) << job << " left " << joined(entries(dir.path()));
  }
}

// Two processes writing the same raw -o at once: the data file and the sidecar always come from
// the same job (before issue 12 about a third of the races ended mixed).
TEST(OutputSetCli, ConcurrentWritersOfOneOutputNeverMix) {
  ScratchDir dir("outset_race");
  const std::string model = quote(exampleModel("gb_curve.json"));
  const std::string a = quote(cli()) + " sample " + model + " -o r.f32 --samples 8 --device cpu -q";
  const std::string b = quote(cli()) + " sample " + model + " -o r.f32 --samples 16 --device cpu -q";
  int mixed = 0;
  for (int round = 0; round < 20; ++round) {
    const std::string cmd = "cd " + quote(dir.path().string()) + " && (" + a + " & " + b + " & wait)";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    const json side = json::parse(readText(dir / "r.f32.json"));
    if (side["counts"]["bytes"].get<uintmax_t>() != fs::file_size(dir / "r.f32")) ++mixed;
  }
  EXPECT_EQ(mixed, 0) << "data and sidecar from different jobs in " << mixed << " of 20 races";
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"r.f32", "r.f32.json"}));
}

// ---- Temporary files ---------------------------------------------------------------------------

TEST(OutputSetCli, SymlinkPlantedAtTheOldTemporaryNameIsNotFollowed) {
  ScratchDir dir("outset_symlink");
  writeText(dir / "victim", "precious\n");
  // bash -c '...; exec shapespline': the binary keeps bash's pid, so $$ is the pid the old
  // predictable name OUT.tmp.<pid> used.
  const std::string cmd = "cd " + quote(dir.path().string()) + " && bash -c 'ln -s victim out.csv.tmp.$$ && exec " +
                          quote(cli()) + " sample " + quote(exampleModel("gb_curve.json")) +
                          " -o out.csv --device cpu -q' 2>/dev/null";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_TRUE(readText(dir / "victim") == "precious\n") << "the symlink's target was overwritten";
  EXPECT_FALSE(fs::is_symlink(dir / "out.csv"));
  EXPECT_TRUE(contains(readText(dir / "out.csv"), "span"));
}

TEST(OutputSetCli, ReplacedOutputKeepsItsMode) {
  ScratchDir dir("outset_mode");
  writeText(dir / "out.csv", "old\n");
  fs::permissions(dir / "out.csv", fs::perms(0600));
  ASSERT_EQ(run("sample " + quote(exampleModel("gb_curve.json")) + " -o out.csv --device cpu -q", dir.path()).rc, 0);
  EXPECT_NE(readText(dir / "out.csv"), "old\n");
  EXPECT_EQ(modeOf(dir / "out.csv"), 0600u);
  ASSERT_EQ(run("sample " + quote(exampleModel("gb_curve.json")) + " -o new.csv --device cpu -q", dir.path(), "umask 027;")
                .rc,
            0);
  EXPECT_EQ(modeOf(dir / "new.csv"), 0640u);
}

// Starts `shapespline args...` without a shell (a shell's background job would ignore SIGINT).
pid_t spawnCli(const std::vector<std::string>& args, const fs::path& err, int stdoutFd = -1) {
  std::vector<std::string> argv = {cli()};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> cargv;
  for (auto& s : argv) cargv.push_back(s.data());
  cargv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  if (stdoutFd >= 0) {
    posix_spawn_file_actions_adddup2(&fa, stdoutFd, 1);
  } else {
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  }
  posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, dfl;
  sigemptyset(&none);
  sigemptyset(&dfl);
  for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaddset(&dfl, s);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &dfl);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, cargv[0], &fa, &attr, cargv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  return rc == 0 ? pid : -1;
}

TEST(OutputSetCli, SignalsRemoveTheTemporaryFiles) {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    ScratchDir dir("outset_signal_" + std::to_string(sig));
    fs::create_directories(dir / "out");
    // A job of many seconds (16 patches of 1024 x 1024 on one thread), interrupted once its
    // temporary files exist.
    const pid_t pid = spawnCli({"sample", exampleModel("surface_aeb.json"), "-o", (dir / "out" / "s.f32").string(),
                                "--grid", "1024", "--device", "cpu", "--threads", "1", "-q"},
                               dir / "err.txt");
    ASSERT_GT(pid, 0);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (entries(dir / "out").size() < 2 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_EQ(entries(dir / "out").size(), 2u) << "the job's temporary files did not appear";
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    ::kill(pid, sig);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig)
        << "signal " << sig << ": status " << status << " " << readText(dir / "err.txt");
    EXPECT_TRUE(entries(dir / "out").empty()) << "signal " << sig << " left " << joined(entries(dir / "out"));
  }
}

// stdout is a pipe whose reader has gone: the job ends by SIGPIPE (as a filter should) and leaves
// neither its outputs nor their temporary files.
TEST(OutputSetCli, BrokenStdoutPipeLeavesNoFile) {
  ScratchDir dir("outset_pipe");
  fs::create_directories(dir / "out");
  writeText(dir / "gb.json", kGbModel);
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  ::close(fds[0]);  // no reader
  const pid_t pid = spawnCli({"gb-fit", (dir / "gb.json").string(), "--span", "1", "--through", kGbThrough, "-o",
                              (dir / "out" / "fit.json").string(), "--svg", (dir / "out" / "fit.svg").string()},
                             dir / "err.txt", fds[1]);
  ::close(fds[1]);
  ASSERT_GT(pid, 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGPIPE) << "status " << status;
  EXPECT_TRUE(entries(dir / "out").empty()) << "left " << joined(entries(dir / "out"));
}

// ---- render ------------------------------------------------------------------------------------

TEST(OutputSetCli, RenderBadOutputPathIsBadInput) {
  if (!vulkanDevice()) GTEST_SKIP() << "no Vulkan device";
  ScratchDir dir("outset_render_path");
  fs::create_directories(dir / "adir");
  for (const std::string& out : {std::string("missing/x.png"), std::string("adir")}) {
    const CliResult r = run("render " + quote(exampleModel("gb_curve.json")) + " -o " + out, dir.path());
    EXPECT_EQ(r.rc, 2) << out << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "shapespline: error: -o: '" + out + "':")) << r.err;
  }
}

TEST(OutputSetCli, RenderNeverDestroysTheOldPng) {
  if (!vulkanDevice()) GTEST_SKIP() << "no Vulkan device";
  ScratchDir dir("outset_render_atomic");
  const std::string old(1500, 'o');  // under the 2 KiB limit below; the new PNG is about 5 KB
  writeText(dir / "x.png", old);
  fs::permissions(dir / "x.png", fs::perms(0600));
  const CliResult r = run("render " + quote(exampleModel("gb_curve.json")) + " -o x.png -q", dir.path(), "ulimit -f 2;");
  EXPECT_EQ(r.rc, 3) << r.err;
  EXPECT_TRUE(readText(dir / "x.png") == old) << "the old PNG was overwritten in place";
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"x.png"}));
  const CliResult ok = run("render " + quote(exampleModel("gb_curve.json")) + " -o x.png -q", dir.path());
  ASSERT_EQ(ok.rc, 0) << ok.err;
  EXPECT_TRUE(readText(dir / "x.png").substr(1, 3) == "PNG");
  EXPECT_EQ(modeOf(dir / "x.png"), 0600u);
}

// ---- stdout ------------------------------------------------------------------------------------

TEST(OutputSetCli, StdoutWriteFailureIsExit3) {
  ScratchDir dir("outset_stdout");
  writeText(dir / "gb.json", kGbModel);
  writeText(dir / "at.json", R"({"samples": [{"span": 1, "t": 0.5}]})");
  const std::vector<std::string> jobs = {
      "basis --family gb --lambda 0.5",
      "gb-fit gb.json --span 1 --through " + std::string(kGbThrough),
      "extend " + quote(exampleModel("clamped_bspline.json")) + " --to 10,4 -o ext.json",
      "info",
      "eval gb.json --at at.json --device cpu",
  };
  for (const auto& job : jobs) {
    const CliResult r = run(job, dir.path(), "", ">/dev/full");
    EXPECT_EQ(r.rc, 3) << job << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "shapespline: error: stdout: ")) << job << ": " << r.err;
  }
  // A job whose stdout failed writes no file either.
  const CliResult g = run("gb-fit gb.json --span 1 --through " + std::string(kGbThrough) + " -o fit.json --svg fit.svg",
                          dir.path(), "", ">/dev/full");
  EXPECT_EQ(g.rc, 3) << g.err;
  EXPECT_FALSE(fs::exists(dir / "fit.json"));
  EXPECT_FALSE(fs::exists(dir / "fit.svg"));
  EXPECT_FALSE(fs::exists(dir / "ext.json"));
  EXPECT_EQ(entries(dir.path()), (std::vector<std::string>{"at.json", "gb.json"}));
}

}  // namespace
}  // namespace shapespline::test
