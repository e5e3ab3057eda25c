#include <shapespline/io/atomic_file.h>

#include <fcntl.h>
#include <pthread.h>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <string_view>
#include <system_error>
#include <thread>

namespace shapespline::io {

namespace fs = std::filesystem;

namespace {

// From this many files a commit syncs each filesystem once instead of each file (commitFiles).
constexpr size_t kSyncfsFiles = 64;
constexpr size_t kMaxTempPath = 4096;       // bytes of one registry entry, NUL included
constexpr size_t kMaxNameInTemp = 200;      // `.NAME.tmp-XXXXXXXXXXXXXXXX` stays below NAME_MAX
// SIGPIPE too: `shapespline gb-fit ... -o X | head` must not leave X's temporary file behind when
// the reader goes away (the process still ends by SIGPIPE, as a filter should).
constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};

std::string errnoText(int err) { return std::generic_category().message(err); }

// ---- Signal-cleanup registry: only atomics and fixed arrays, read by the signal handler ----------
struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being written, 2 live
  char path[kMaxTempPath];
};
Slot gSlots[kMaxLiveTempFiles];
std::atomic<int> gInCommit{0};
std::atomic<int> gPendingSignal{0};
static_assert(std::atomic<int>::is_always_lock_free);

int registerTemp(const std::string& absolute) {
  if (absolute.size() >= kMaxTempPath) return -1;
  for (int i = 0; i < kMaxLiveTempFiles; ++i) {
    int expected = 0;
    if (gSlots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(gSlots[i].path, absolute.c_str(), absolute.size() + 1);
      gSlots[i].state.store(2, std::memory_order_release);
      return i;
    }
  }
  return -1;
}

void unregisterTemp(int& slot) {
  if (slot >= 0) gSlots[slot].state.store(0, std::memory_order_release);
  slot = -1;
}

extern "C" void onCleanupSignal(int sig) {
  const int savedErrno = errno;
  if (gInCommit.load() > 0) {  // a set is being renamed: finish it, then die (commitFiles re-raises)
    gPendingSignal.store(sig);
    errno = savedErrno;
    return;
  }
  for (Slot& s : gSlots) {
    if (s.state.load(std::memory_order_acquire) == 2) ::unlink(s.path);
  }
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  ::sigaction(sig, &dfl, nullptr);
  ::raise(sig);  // delivered with the default action when this handler returns (it is blocked here)
  errno = savedErrno;
}

// ---- Names, modes ---------------------------------------------------------------------------------
std::string randomHex() {
  uint64_t r = 0;
  size_t got = 0;
  auto* bytes = reinterpret_cast<unsigned char*>(&r);
  while (got < sizeof r) {
    const ssize_t n = ::getrandom(bytes + got, sizeof r - got, 0);
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    got += static_cast<size_t>(n);
  }
  if (got < sizeof r) {  // no getrandom (very old kernel): still unique per process and call
    static std::atomic<uint64_t> counter{0};
    r ^= static_cast<uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) * 0x9E3779B97F4A7C15ull ^
         (static_cast<uint64_t>(::getpid()) << 32) ^ counter.fetch_add(1);
  }
  static const char* digits = "0123456789abcdef";
  std::string s(16, '0');
  for (int i = 0; i < 16; ++i) s[static_cast<size_t>(i)] = digits[(r >> (4 * i)) & 15];
  return s;
}

// `.<name>.<tag>-<16 hex>` beside `target`.
fs::path hiddenSibling(const fs::path& target, const char* tag) {
  std::string name = target.filename().string();
  if (name.size() > kMaxNameInTemp) name.resize(kMaxNameInTemp);
  std::string hidden = ".";
  hidden += name;
  hidden += '.';
  hidden += tag;
  hidden += '-';
  hidden += randomHex();
  return target.parent_path() / hidden;
}

// The process umask, read without changing it (umask(2) can only be read by setting it, which
// would race with threads creating files): /proc/self/status has it since Linux 4.7. Read at each
// commit, as a program may change its umask.
mode_t processUmask() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("Umask:", 0) == 0) return static_cast<mode_t>(std::strtoul(line.c_str() + 6, nullptr, 8) & 0777);
  }
  const mode_t m = ::umask(022);
  ::umask(m);
  return m;
}

// ---- Test-only fault ------------------------------------------------------------------------------
struct IoFault {
  int failRename = 0;  // 1-based index of the rename that fails in each commit
  int delayMs = 0;
};

IoFault ioFault() {
  IoFault r;
  const char* env = std::getenv("SHAPESPLINE_IO_FAULT");
  if (!env) return r;
  const std::string_view v(env);
  if (v.rfind("rename:", 0) == 0) r.failRename = std::atoi(env + 7);
  if (v.rfind("commit-delay:", 0) == 0) r.delayMs = std::atoi(env + 13);
  return r;
}

// Holds SIGINT/SIGTERM/SIGHUP back during the renames of a commit: blocked in this thread, and
// deferred by the handler when another thread receives it; re-raised at the end.
class SignalHold {
 public:
  SignalHold() {
    gInCommit.fetch_add(1);
    sigset_t set;
    sigemptyset(&set);
    for (int s : kCleanupSignals) sigaddset(&set, s);
    ::pthread_sigmask(SIG_BLOCK, &set, &old_);
  }
  ~SignalHold() {
    ::pthread_sigmask(SIG_SETMASK, &old_, nullptr);  // a signal blocked meanwhile is delivered here
    if (gInCommit.fetch_sub(1) == 1) {
      const int sig = gPendingSignal.exchange(0);
      if (sig != 0) ::raise(sig);
    }
  }
  SignalHold(const SignalHold&) = delete;
  SignalHold& operator=(const SignalHold&) = delete;

 private:
  sigset_t old_;
};

// Exclusive flock on each distinct target folder (in (device, inode) order, so two sets sharing
// folders cannot deadlock): concurrent commits of the same outputs are serialized. A folder that
// cannot be opened for reading is committed without the lock.
class FolderLocks {
 public:
  explicit FolderLocks(const std::vector<fs::path>& folders) {
    struct Entry {
      dev_t dev;
      ino_t ino;
      int fd;
    };
    std::vector<Entry> found;
    for (const auto& f : folders) {
      const int fd = ::open(f.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      if (fd < 0) continue;
      struct stat st {};
      if (::fstat(fd, &st) != 0) {
        ::close(fd);
        continue;
      }
      const bool dup = std::any_of(found.begin(), found.end(),
                                   [&](const Entry& e) { return e.dev == st.st_dev && e.ino == st.st_ino; });
      if (dup) {
        ::close(fd);
        continue;
      }
      found.push_back({st.st_dev, st.st_ino, fd});
    }
    std::sort(found.begin(), found.end(),
              [](const Entry& a, const Entry& b) { return a.dev != b.dev ? a.dev < b.dev : a.ino < b.ino; });
    for (const auto& e : found) {
      while (::flock(e.fd, LOCK_EX) != 0 && errno == EINTR) {
      }
      fds_.push_back(e.fd);
    }
  }
  ~FolderLocks() {
    for (int fd : fds_) ::close(fd);  // closing drops the flock
  }
  // The renames' directory entries reach the disk.
  void syncAll() const {
    for (int fd : fds_) ::fsync(fd);
  }
  FolderLocks(const FolderLocks&) = delete;
  FolderLocks& operator=(const FolderLocks&) = delete;

 private:
  std::vector<int> fds_;
};

fs::path folderOf(const fs::path& target) {
  fs::path folder = target.parent_path();
  return folder.empty() ? fs::path(".") : folder;
}

}  // namespace

void installTempFileCleanup() {
  for (int sig : kCleanupSignals) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;  // nohup, background jobs
    struct sigaction sa {};
    sa.sa_handler = onCleanupSignal;
    sigemptyset(&sa.sa_mask);
    for (int s : kCleanupSignals) sigaddset(&sa.sa_mask, s);
    sa.sa_flags = 0;
    ::sigaction(sig, &sa, nullptr);
  }
}

OutputPathError::OutputPathError(std::string option, std::string path, std::string reason)
    : std::invalid_argument(option + ": '" + path + "': " + reason),
      option_(std::move(option)),
      path_(std::move(path)),
      reason_(std::move(reason)) {}

OutputWriteError::OutputWriteError(std::string option, std::string path, std::string reason)
    : std::runtime_error(path.empty() ? option + ": " + reason : option + ": cannot write '" + path + "': " + reason),
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
  const fs::path folder = folderOf(target_);
  const fs::file_status fst = fs::status(folder, ec);
  if (fs::exists(fst) && !fs::is_directory(fst)) {
    throw OutputPathError(opt, target_.string(), "'" + folder.string() + "' is not a folder");
  }
  if (!fs::is_directory(fst)) {
    throw OutputPathError(opt, target_.string(), "folder '" + folder.string() + "' does not exist");
  }
  if (target_.filename().empty() || target_.filename() == "." || target_.filename() == "..") {
    throw OutputPathError(opt, target_.string(), "names a folder, not a file");
  }
  // O_EXCL|O_NOFOLLOW: a file or symlink planted at the name is never opened, truncated or
  // followed; the random name makes a collision a retry, not a denial of service.
  int err = 0;
  for (int attempt = 0; attempt < 16 && fd_ < 0; ++attempt) {
    temp_ = hiddenSibling(target_, "tmp");
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    err = errno;
    if (fd_ < 0 && err != EEXIST) break;
  }
  if (fd_ < 0) {
    temp_.clear();
    throw OutputPathError(opt, target_.string(),
                          "cannot create a file in folder '" + folder.string() + "': " + errnoText(err));
  }
  slot_ = registerTemp(fs::absolute(temp_, ec).string());
  buffer_ = std::make_unique_for_overwrite<char[]>(kBufferBytes);
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : target_(std::move(other.target_)),
      temp_(std::move(other.temp_)),
      option_(std::move(other.option_)),
      fd_(other.fd_),
      slot_(other.slot_),
      committed_(other.committed_),
      buffer_(std::move(other.buffer_)),
      used_(other.used_),
      written_(other.written_) {
  other.fd_ = -1;
  other.slot_ = -1;
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
  if (!temp_.empty() && !committed_) ::unlink(temp_.c_str());
  unregisterTemp(slot_);
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
    const ssize_t n = ::write(fd_, buffer_.get() + done, used_ - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("write", errno);
    }
    done += static_cast<size_t>(n);
  }
  written_ += used_;
  used_ = 0;
}

void AtomicFile::writeAt(uint64_t offset, const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::pwrite(fd_, p, size, static_cast<off_t>(offset));
    if (n < 0) {
      if (errno == EINTR) continue;
      throw OutputWriteError(option_, target_.string(),
                             "write failed: " + errnoText(errno) + " (nothing written; the temporary file was removed)");
    }
    p += n;
    offset += static_cast<uint64_t>(n);
    size -= static_cast<size_t>(n);
  }
}

void AtomicFile::write(const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    if (used_ == kBufferBytes) flush();
    const size_t n = std::min(size, kBufferBytes - used_);
    std::memcpy(buffer_.get() + used_, p, n);
    used_ += n;
    p += n;
    size -= n;
  }
}

void AtomicFile::prepare() {
  if (committed_ || fd_ < 0) throw std::logic_error("AtomicFile: commit of a committed or discarded file");
  flush();
  // fsync before rename: after a crash the target is either the old file or the complete new one.
  if (::fsync(fd_) != 0) fail("fsync", errno);
}

void AtomicFile::commit() {
  AtomicFile* self = this;
  commitFiles(&self, 1);
}

void commitFiles(AtomicFile* const* files, size_t count) {
  // Phase 1, outside the lock: every byte written and on disk (the slow part). A large set (an
  // import writes thousands of files) is synced with one syncfs per filesystem, which puts every
  // file of it on disk as an fsync of each would, and reports their writeback errors (Linux 5.8+).
  if (count < kSyncfsFiles) {
    for (size_t i = 0; i < count; ++i) files[i]->prepare();
  } else {
    std::vector<std::pair<dev_t, AtomicFile*>> filesystems;
    for (size_t i = 0; i < count; ++i) {
      AtomicFile& f = *files[i];
      if (f.committed_ || f.fd_ < 0) throw std::logic_error("AtomicFile: commit of a committed or discarded file");
      f.flush();
      struct stat st {};
      if (::fstat(f.fd_, &st) != 0) f.fail("fstat", errno);
      if (std::none_of(filesystems.begin(), filesystems.end(), [&](const auto& e) { return e.first == st.st_dev; }))
        filesystems.emplace_back(st.st_dev, &f);
    }
    for (const auto& [dev, f] : filesystems)
      if (::syncfs(f->fd_) != 0) f->fail("syncfs", errno);
  }

  // Phase 2: signals held back, folders locked; modes, backups, renames.
  SignalHold hold;
  std::vector<fs::path> folders;  // each once (a set may put thousands of files in one folder)
  for (size_t i = 0; i < count; ++i) {
    fs::path folder = folderOf(files[i]->target_);
    if (std::find(folders.begin(), folders.end(), folder) == folders.end()) folders.push_back(std::move(folder));
  }
  FolderLocks locks(folders);
  std::optional<mode_t> umask;  // read once a commit, when a new file needs it
  for (size_t i = 0; i < count; ++i) {
    AtomicFile& f = *files[i];
    struct stat st {};
    const bool replaces = ::stat(f.target_.c_str(), &st) == 0 && S_ISREG(st.st_mode);
    if (!replaces && !umask) umask = processUmask();
    const mode_t mode = replaces ? (st.st_mode & 07777) : (0666 & ~*umask);
    if (::fchmod(f.fd_, mode) != 0) f.fail("chmod", errno);
    const int closed = ::close(f.fd_);
    f.fd_ = -1;
    if (closed != 0) f.fail("close", errno);
  }
  // The previous version of each target, as a hidden hard link, so that a failed rename can put
  // every target back (one file needs none: its single rename either happens or not).
  std::vector<fs::path> backups(count);
  std::vector<char> existed(count, 0);
  if (count > 1) {
    for (size_t i = 0; i < count; ++i) {
      struct stat st {};
      if (::lstat(files[i]->target_.c_str(), &st) != 0) continue;  // a new file: nothing to keep
      existed[i] = 1;
      for (int attempt = 0; attempt < 16; ++attempt) {
        const fs::path b = hiddenSibling(files[i]->target_, "bak");
        if (::link(files[i]->target_.c_str(), b.c_str()) == 0) {
          backups[i] = b;
          break;
        }
        if (errno != EEXIST) break;  // no hard links here: that target cannot be restored
      }
    }
  }
  const IoFault fault = ioFault();
  for (size_t i = 0; i < count; ++i) {
    AtomicFile& f = *files[i];
    int err = 0;
    if (fault.failRename == static_cast<int>(i) + 1) {
      err = EIO;
    } else if (::rename(f.temp_.c_str(), f.target_.c_str()) != 0) {
      err = errno;
    }
    if (err != 0) {
      std::string note;
      for (size_t j = 0; j < i; ++j) {  // put back what this commit already replaced
        AtomicFile& g = *files[j];
        if (!backups[j].empty()) {
          if (::rename(backups[j].c_str(), g.target_.c_str()) != 0)
            note += "; the previous '" + g.target_.string() + "' is kept as '" + backups[j].string() + "'";
          backups[j].clear();
        } else if (!existed[j]) {
          ::unlink(g.target_.c_str());  // it did not exist before this commit
        } else {
          note += "; '" + g.target_.string() + "' was already replaced (no hard link could keep the previous one)";
        }
        g.committed_ = true;
      }
      for (auto& b : backups)
        if (!b.empty()) ::unlink(b.c_str());
      for (size_t j = i + 1; j < count; ++j) files[j]->discard();
      const std::string what = "rename of '" + f.temp_.string() + "'" +
                               (fault.failRename == static_cast<int>(i) + 1 ? kIoFaultNote : "");
      f.discard();
      throw OutputWriteError(f.option_, f.target_.string(),
                             what + " failed: " + errnoText(err) +
                                 (note.empty() ? " (nothing written: every output of the job was left as it was)"
                                               : note));
    }
    f.temp_.clear();  // the temporary name no longer exists
    unregisterTemp(f.slot_);
    if (fault.delayMs > 0 && i + 1 < count) std::this_thread::sleep_for(std::chrono::milliseconds(fault.delayMs));
  }
  for (size_t i = 0; i < count; ++i) {
    files[i]->committed_ = true;
    if (!backups[i].empty()) ::unlink(backups[i].c_str());
  }
  locks.syncAll();
}

}  // namespace shapespline::io
