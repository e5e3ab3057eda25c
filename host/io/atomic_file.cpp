#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

namespace shapespline::io {

namespace fs = std::filesystem;

namespace {
constexpr size_t kBufferSize = size_t{1} << 20;

std::string errnoText(int err) { return std::generic_category().message(err); }
}  // namespace

OutputPathError::OutputPathError(std::string option, std::string path, std::string reason)
    : std::invalid_argument(option + ": '" + path + "': " + reason),
      option_(std::move(option)),
      path_(std::move(path)),
      reason_(std::move(reason)) {}

OutputWriteError::OutputWriteError(std::string option, std::string path, std::string reason)
    : std::runtime_error(option + ": cannot write '" + path + "': " + reason),
      option_(std::move(option)),
      path_(std::move(path)),
      reason_(std::move(reason)) {}

AtomicFile::AtomicFile(fs::path target, std::string option) : target_(std::move(target)), option_(std::move(option)) {
  const std::string& opt = option_;
  if (target_.empty()) throw OutputPathError(opt, "", "empty output path");
  std::error_code ec;
  const fs::file_status st = fs::status(target_, ec);
  if (fs::is_directory(st)) throw OutputPathError(opt, target_.string(), "is a directory");
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    throw OutputPathError(opt, target_.string(),
                          "exists and is not a regular file (a device, FIFO or socket); output is written to a "
                          "temporary file and renamed, which would replace it");
  }
  fs::path folder = target_.parent_path();
  if (folder.empty()) folder = ".";
  const fs::file_status fst = fs::status(folder, ec);
  if (fs::exists(fst) && !fs::is_directory(fst)) {
    throw OutputPathError(opt, target_.string(), "'" + folder.string() + "' is not a folder");
  }
  if (!fs::is_directory(fst)) {
    throw OutputPathError(opt, target_.string(), "folder '" + folder.string() + "' does not exist");
  }
  temp_ = target_;
  temp_ += ".tmp." + std::to_string(::getpid());
  fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    const int err = errno;
    throw OutputPathError(opt, target_.string(),
                          "cannot create a file in folder '" + folder.string() + "': " + errnoText(err));
  }
  buffer_.resize(kBufferSize);
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : target_(std::move(other.target_)),
      temp_(std::move(other.temp_)),
      option_(std::move(other.option_)),
      fd_(other.fd_),
      committed_(other.committed_),
      buffer_(std::move(other.buffer_)),
      used_(other.used_),
      written_(other.written_) {
  other.fd_ = -1;
  other.committed_ = true;  // the moved-from object owns nothing
  other.temp_.clear();
}

AtomicFile::~AtomicFile() {
  if (!committed_) discard();
}

void AtomicFile::discard() noexcept {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  if (!temp_.empty() && !committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
  committed_ = true;
  used_ = 0;
}

void AtomicFile::fail(const std::string& what, int err) {
  discard();  // the partial temporary file goes now, not only when the writer unwinds
  throw OutputWriteError(option_, target_.string(),
                         what + " failed: " + errnoText(err) + " (nothing written; the temporary file was removed)");
}

void AtomicFile::flush() {
  size_t done = 0;
  while (done < used_) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, used_ - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("write", errno);
    }
    done += static_cast<size_t>(n);
  }
  written_ += used_;
  used_ = 0;
}

void AtomicFile::write(const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    if (used_ == buffer_.size()) flush();
    const size_t n = std::min(size, buffer_.size() - used_);
    std::memcpy(buffer_.data() + used_, p, n);
    used_ += n;
    p += n;
    size -= n;
  }
}

void AtomicFile::commit() {
  if (committed_) throw std::logic_error("AtomicFile::commit called twice");
  flush();
  // fsync before rename: after a crash the target is either the old file or the complete new one.
  if (::fsync(fd_) != 0) fail("fsync", errno);
  const int closed = ::close(fd_);
  fd_ = -1;
  if (closed != 0) fail("close", errno);
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) fail("rename of '" + temp_.string() + "'", ec.value());
  committed_ = true;
}

}  // namespace shapespline::io
