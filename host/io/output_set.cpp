#include <shapespline/io/output_set.h>

#include <cerrno>
#include <cstdio>
#include <system_error>
#include <sys/stat.h>
#include <vector>

namespace shapespline::io {

namespace fs = std::filesystem;

namespace {

// The identity of an output's directory entry: its folder with symlinks and `..` resolved, and
// its file name. (Two names of one inode are different entries: each rename replaces its own.)
fs::path entryKey(const fs::path& path) {
  std::error_code ec;
  fs::path folder = path.parent_path();
  if (folder.empty()) folder = ".";
  fs::path resolved = fs::weakly_canonical(fs::absolute(folder, ec), ec);
  if (ec) resolved = fs::absolute(folder, ec).lexically_normal();
  return resolved / path.filename();
}

OutputPathError overwritesInput(const fs::path& output, const std::string& option, const fs::path& input,
                                const std::string& what) {
  return OutputPathError(option, output.string(),
                         "is the same file as " + what + " ('" + input.string() +
                             "'), which this command reads; give the output another path");
}

}  // namespace

bool sameFile(const fs::path& a, const fs::path& b) {
  struct stat sa {}, sb {};
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

void OutputSet::reads(const fs::path& path, const std::string& what) {
  for (const AtomicFile& f : files_) {
    if (sameFile(f.target(), path)) throw overwritesInput(f.target(), f.option(), path, what);
  }
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) inputs_.push_back({path, what});
}

AtomicFile& OutputSet::add(const fs::path& path, const std::string& option) {
  for (const Input& in : inputs_) {
    if (sameFile(path, in.path)) throw overwritesInput(path, option, in.path, in.what);
  }
  const fs::path key = entryKey(path);
  for (size_t i = 0; i < keys_.size(); ++i) {
    if (keys_[i] == key) {
      throw OutputPathError(option, path.string(),
                            "is the same file as " + files_[i].option() + " ('" + files_[i].target().string() +
                                "'); give each output its own path");
    }
  }
  files_.emplace_back(path, option);
  keys_.push_back(key);
  return files_.back();
}

void OutputSet::commit() {
  std::vector<AtomicFile*> files;
  for (auto& f : files_) files.push_back(&f);
  commitFiles(files.data(), files.size());
}

void OutputSet::discard() noexcept {
  for (auto& f : files_) f.discard();
}

void OutputSet::clear() noexcept {
  discard();
  files_.clear();
  keys_.clear();
  inputs_.clear();
}

void writeStdout(std::string_view text) {
  if (!text.empty() && std::fwrite(text.data(), 1, text.size(), stdout) != text.size()) {
    const int err = errno;
    throw OutputWriteError("stdout", "", "write failed: " + std::generic_category().message(err));
  }
}

void flushStdout() {
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    const int err = errno ? errno : EIO;
    throw OutputWriteError("stdout", "", "write failed: " + std::generic_category().message(err));
  }
}

}  // namespace shapespline::io
