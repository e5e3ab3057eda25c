#pragma once
// The files of one job (raw data + its .json sidecar, -o + --svg, a PNG) committed together: all
// of them appear, or none changes. add() opens each temporary file (io::AtomicFile, so a bad path
// fails before any work); commit() first flushes and fsyncs every temporary file (a set of 64 or
// more: one syncfs per filesystem, io/atomic_file.cpp commitFiles), then, holding an
// exclusive flock on each target folder (so two processes writing the same outputs never
// interleave their renames) and with SIGINT/SIGTERM/SIGHUP held back, keeps the previous version
// of each target as a hidden hard link, renames every temporary file onto its target and on a
// failed rename puts every target back as it was; then the backups are removed and the folders
// fsynced. The one window that cannot be closed: a power loss or SIGKILL between the renames
// leaves the set mixed (and a `.NAME.bak-*` file beside a target).
#include <shapespline/io/atomic_file.h>

#include <deque>
#include <filesystem>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace shapespline::io {

class OutputSet {
 public:
  OutputSet() = default;
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  // Opens the temporary file for `path` (AtomicFile's checks, OutputPathError naming `option`).
  // The same path twice in one set (compared after resolving the folder, so `-o d/x --svg ./d/x`
  // collide) is an OutputPathError naming both options. The reference stays valid for the set's
  // life.
  AtomicFile& add(const std::filesystem::path& path, const std::string& option);
  // Declares a file the job reads (`what` names it in errors: "MODEL", "--to-curve[0]", "SHARD[2]").
  // An output that is the same file as an input (io::sameFile: another spelling, a symlink or a hard
  // link) is an OutputPathError naming both, thrown by whichever of add() and reads() comes second,
  // so that the command is refused before it does any work. An input that does not exist is not
  // recorded (reading it fails on its own).
  void reads(const std::filesystem::path& path, const std::string& what);

  // Commits every file as one set (see above). Throws OutputWriteError naming the file whose write
  // or rename failed; every target is then as it was and every temporary file is removed.
  void commit();
  // Removes every temporary file now (the destructor does it too when commit() was not reached).
  void discard() noexcept;
  // discard(), then forgets every file and input: the set is as new (a job that starts again).
  void clear() noexcept;

  size_t size() const { return files_.size(); }

 private:
  std::deque<AtomicFile> files_;
  // Each output's folder resolved + file name -> its index in files_, for the duplicate check; the
  // folders as resolved the first time (by the folder as given).
  std::unordered_map<std::string, size_t> keys_;
  std::unordered_map<std::string, std::filesystem::path> resolvedFolders_;
  struct Input {
    std::filesystem::path path;
    std::string what;
  };
  std::vector<Input> inputs_;
};

// Whether both paths name one existing file: the same device and inode after following symlinks, so
// another spelling, a symlink and a hard link all count. False when either does not exist.
bool sameFile(const std::filesystem::path& a, const std::filesystem::path& b);

// Writes to stdout and flushes it; a failure (a full disk, a closed pipe) throws
// OutputWriteError("stdout", "", reason), exit 3 like any failed output.
void writeStdout(std::string_view text);
void flushStdout();

}  // namespace shapespline::io
