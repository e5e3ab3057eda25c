#pragma once
// An output file that appears only when complete: bytes go to a temporary file in the target's
// folder (same file system, so the final rename is atomic), named `.<name>.tmp-<16 hex>` from
// getrandom() and created with O_CREAT|O_EXCL|O_NOFOLLOW, mode 0600 (a planted file or symlink is
// never opened or followed). commit() flushes, fsyncs, gives the file the mode of the file it
// replaces (or 0666 & ~umask for a new one) and renames it; the destructor removes the temporary
// file when commit() was never reached, so an error never leaves a partial output behind, and the
// signal handlers of installTempFileCleanup() remove it on SIGINT/SIGTERM/SIGHUP. Writes are
// buffered (1 MiB); writers format straight into the buffer with std::to_chars through
// space()/advance(). Several files that must appear together are committed by io::OutputSet.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace shapespline::io {

// The output path cannot be used (missing or unwritable folder, a directory, unknown extension,
// the same path given for two outputs). A bad-input error: `option` is the command-line option
// that named the path ("-o", "--svg").
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
// `path` is empty for a stream (option "stdout").
class OutputWriteError : public std::runtime_error {
 public:
  OutputWriteError(std::string option, std::string path, std::string reason);
  const std::string& option() const { return option_; }
  const std::string& path() const { return path_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string option_, path_, reason_;
};

class OutputSet;

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
  // Writes at byte `offset` (pwrite), for a writer that places data by position from several
  // threads at once: safe for disjoint ranges, concurrently with each other (not with write()).
  // The sequential buffer and position are untouched, and bytesWritten() does not count it. A
  // failure throws OutputWriteError; the owner's unwinding removes the temporary file.
  void writeAt(uint64_t offset, const void* data, size_t size);
  // At least `size` (<= kMaxSpace) writable bytes at the returned pointer; advance() publishes them.
  static constexpr size_t kMaxSpace = 64 * 1024;
  char* space(size_t size) {
    if (kBufferBytes - used_ < size) flush();
    return buffer_.get() + used_;
  }
  void advance(size_t size) { used_ += size; }

  // Flush, fsync, close and rename onto the target (under the folder lock OutputSet uses, so a
  // concurrent set commit of the same folder is never interleaved with it). Throws
  // OutputWriteError on an I/O failure (the temporary file is then removed).
  void commit();
  // Close and remove the temporary file now.
  void discard() noexcept;
  // Writes the buffered bytes to the temporary file now, so that it can be read back (the shard
  // record hashes it, jobs/shard_files.h) before commit(), which flushes too.
  void flushToTemp() { flush(); }

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& tempPath() const { return temp_; }
  const std::string& option() const { return option_; }
  uint64_t bytesWritten() const { return written_ + used_; }

 private:
  friend class OutputSet;
  friend void commitFiles(AtomicFile* const* files, size_t count);
  void flush();
  // Commit phase 1 (outside any lock): every byte on disk.
  void prepare();
  [[noreturn]] void fail(const std::string& what, int err);

  std::filesystem::path target_, temp_;
  std::string option_;
  int fd_ = -1;
  int slot_ = -1;  // index in the signal-cleanup registry, -1 when not registered
  bool committed_ = false;
  // The sequential buffer: not zero-filled, so a small file (a sidecar) touches only the pages it
  // writes (a batch of a thousand models paid 2 MiB of memset and page faults per model).
  static constexpr size_t kBufferBytes = size_t{1} << 20;
  std::unique_ptr<char[]> buffer_;
  size_t used_ = 0;
  uint64_t written_ = 0;
};

// Commits `count` prepared-or-not files as one set (see OutputSet::commit). Internal to io.
void commitFiles(AtomicFile* const* files, size_t count);

// Installs SIGINT, SIGTERM, SIGHUP and SIGPIPE handlers (those not ignored at start) that unlink
// every live temporary file, then restore the default action and re-raise the signal, so the
// process still ends by that signal. The handler is async-signal-safe: it reads a fixed-size static
// registry of C strings (at most kMaxLiveTempFiles paths of up to 4095 bytes; a file beyond that is
// still removed on every error path, only not on a signal). During the renames of a commit the
// signal is held back and raised when the commit has finished, so a set is never left half renamed.
inline constexpr int kMaxLiveTempFiles = 32;
void installTempFileCleanup();

// Test-only fault (SHAPESPLINE_IO_FAULT, read at each commit): "rename:N" makes the N-th rename (1-based) of
// every commit fail with EIO, "commit-delay:MS" sleeps MS milliseconds between the renames of a
// set (to widen the window a concurrent writer could use). Messages say "(injected by
// SHAPESPLINE_IO_FAULT)".
inline constexpr const char* kIoFaultNote = " (injected by SHAPESPLINE_IO_FAULT)";

}  // namespace shapespline::io
