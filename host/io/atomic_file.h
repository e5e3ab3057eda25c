#pragma once
// An output file that appears only when complete: bytes go to `OUT.tmp.<pid>` in the target's
// folder (same file system, so the final rename is atomic), commit() flushes, fsyncs and renames;
// the destructor removes the temporary file when commit() was never reached, so an error never
// leaves a partial output behind. Writes are buffered (1 MiB); writers format straight into the
// buffer with std::to_chars through space()/advance().
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace shapespline::io {

// The output path cannot be used (missing or unwritable folder, a directory, unknown extension).
// A bad-input error: `option` is the command-line option that named the path ("-o", "--svg").
class OutputPathError : public std::invalid_argument {
 public:
  OutputPathError(std::string option, std::string path, std::string reason);
  const std::string& option() const { return option_; }
  const std::string& path() const { return path_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string option_, path_, reason_;
};

// Writing the output failed after it was opened (disk full, file size limit, I/O error): a runtime
// error (exit code 3), not bad input. The temporary file is removed; the target is untouched.
class OutputWriteError : public std::runtime_error {
 public:
  OutputWriteError(std::string option, std::string path, std::string reason);
  const std::string& option() const { return option_; }
  const std::string& path() const { return path_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string option_, path_, reason_;
};

class AtomicFile {
 public:
  // Creates the temporary file now (fails early): throws OutputPathError when the folder does not
  // exist or is not writable, when `target` is a directory, or when it exists and is not a regular
  // file (a device such as /dev/full, a FIFO, a socket: the rename would replace it, so it is
  // refused rather than written through). I/O failures later throw OutputWriteError.
  explicit AtomicFile(std::filesystem::path target, std::string option = "-o");
  ~AtomicFile();
  AtomicFile(AtomicFile&& other) noexcept;
  AtomicFile& operator=(AtomicFile&&) = delete;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const void* data, size_t size);
  void write(std::string_view text) { write(text.data(), text.size()); }
  // At least `size` (<= 64 KiB) writable bytes at the returned pointer; advance() publishes them.
  char* space(size_t size) {
    if (buffer_.size() - used_ < size) flush();
    return buffer_.data() + used_;
  }
  void advance(size_t size) { used_ += size; }

  // Flush, fsync, close and rename onto the target. Throws OutputWriteError on an I/O failure
  // (the temporary file is then removed by the destructor).
  void commit();
  // Close and remove the temporary file now.
  void discard() noexcept;

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& tempPath() const { return temp_; }
  uint64_t bytesWritten() const { return written_ + used_; }

 private:
  void flush();

  [[noreturn]] void fail(const std::string& what, int err);

  std::filesystem::path target_, temp_;
  std::string option_;
  int fd_ = -1;
  bool committed_ = false;
  std::vector<char> buffer_;
  size_t used_ = 0;
  uint64_t written_ = 0;
};

}  // namespace shapespline::io
