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

AtomicFile::AtomicFile(fs::path target, std::string option) : target_(std::move(target)) {
  if (target_.empty()) throw OutputPathError(option, "", "empty output path");
  std::error_code ec;
  if (fs::is_directory(target_, ec)) throw OutputPathError(option, target_.string(), "is a directory");
  fs::path folder = target_.parent_path();
  if (folder.empty()) folder = ".";
  if (!fs::is_directory(folder, ec)) {
    throw OutputPathError(option, target_.string(), "folder '" + folder.string() + "' does not exist");
  }
  temp_ = target_;
  temp_ += ".tmp." + std::to_string(::getpid());
  fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    const int err = errno;
    throw OutputPathError(option, target_.string(),
                          "cannot create a file in folder '" + folder.string() + "': " + errnoText(err));
  }
  buffer_.resize(kBufferSize);
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : target_(std::move(other.target_)),
      temp_(std::move(other.temp_)),
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

void AtomicFile::flush() {
  size_t done = 0;
  while (done < used_) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, used_ - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      throw std::runtime_error("writing '" + temp_.string() + "': " + errnoText(err));
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
  if (::fsync(fd_) != 0) {
    const int err = errno;
    throw std::runtime_error("fsync '" + temp_.string() + "': " + errnoText(err));
  }
  if (::close(fd_) != 0) {
    fd_ = -1;
    const int err = errno;
    throw std::runtime_error("closing '" + temp_.string() + "': " + errnoText(err));
  }
  fd_ = -1;
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) throw std::runtime_error("renaming '" + temp_.string() + "' to '" + target_.string() + "': " + ec.message());
  committed_ = true;
}

}  // namespace shapespline::io
