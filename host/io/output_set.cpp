#include <shapespline/io/output_set.h>

#include <cerrno>
#include <cstdio>
#include <system_error>
#include <sys/stat.h>
#include <vector>

namespace shapespline::io {

namespace fs = std::filesystem;

namespace {

// An output's folder with symlinks and `..` resolved.
fs::path resolvedFolder(const fs::path& folder) {
  std::error_code ec;
  fs::path resolved = fs::weakly_canonical(fs::absolute(folder, ec), ec);
  if (ec) resolved = fs::absolute(folder, ec).lexically_normal();
  return resolved;
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
  // The identity of the output's directory entry: its folder resolved (once per folder: an import
  // adds thousands of files to one) and its name. Two names of one inode are different entries:
  // each rename replaces its own.
  const std::string folder = path.parent_path().empty() ? std::string(".") : path.parent_path().string();
  auto resolved = resolvedFolders_.find(folder);
  if (resolved == resolvedFolders_.end()) resolved = resolvedFolders_.emplace(folder, resolvedFolder(folder)).first;
  const std::string key = (resolved->second / path.filename()).string();
  if (const auto same = keys_.find(key); same != keys_.end()) {
    const AtomicFile& other = files_[same->second];
    throw OutputPathError(option, path.string(),
                          "is the same file as " + other.option() + " ('" + other.target().string() +
                              "'); give each output its own path");
  }
  files_.emplace_back(path, option);
  keys_.emplace(key, files_.size() - 1);
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
  resolvedFolders_.clear();
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
