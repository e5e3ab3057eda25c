#pragma once
// Input files (models, `eval --at` sample lists, `extend --to-curve` target curves) read and parsed
// within fixed limits, so that no input can exhaust memory, block, or overflow the stack:
//  * readInputFile opens with O_RDONLY|O_NONBLOCK|O_CLOEXEC (a FIFO never blocks the open), requires
//    a regular file (not a FIFO, device or directory) and at most kMaxInputFileBytes, checked on the
//    size fstat reports and again while reading (the file may grow);
//  * parseJsonText limits nesting depth, keys per object and array length and rejects duplicate
//    keys (nlohmann would keep the last one silently), in O(n) time;
//  * shortValue / shortText show a value in an error message in at most kMaxValueChars characters
//    without serializing it whole (a deep or huge value is never dumped).
// Limit and rule violations are ModelError (exit code 2 at the command line) naming the field, the
// limit and the value; a file that cannot be opened or read is std::runtime_error.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace shapespline::io {

inline constexpr std::uint64_t kMaxInputFileBytes = 32ull << 20;  // 32 MiB
inline constexpr int kMaxJsonDepth = 64;                          // nested arrays/objects
inline constexpr std::size_t kMaxJsonObjectKeys = 1024;
inline constexpr std::size_t kMaxJsonArrayLength = std::size_t{1} << 22;  // 4,194,304 elements
inline constexpr std::size_t kMaxValueChars = 60;                         // a value shown in a message

// A regular file opened for reading as readInputFile opens it (O_NONBLOCK: a FIFO never blocks the
// open), with its size; the descriptor closes with the object. Throws ModelError naming `field`
// and the path when it is not a regular file ("is not a regular file (it is a FIFO)"), and
// std::runtime_error when it cannot be opened or examined.
class InputFd {
 public:
  InputFd(const std::filesystem::path& path, const std::string& field);
  ~InputFd();
  InputFd(const InputFd&) = delete;
  InputFd& operator=(const InputFd&) = delete;
  int get() const { return fd_; }
  std::uint64_t size() const { return size_; }

 private:
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

// The whole file as bytes. `field` names the file in errors ("MODEL", "--at"). Throws ModelError
// when it is not a regular file or larger than `maxBytes`, std::runtime_error when it cannot be
// opened or read.
std::string readInputFile(const std::filesystem::path& path, const std::string& field,
                          std::uint64_t maxBytes = kMaxInputFileBytes);

// JSON text -> value within the limits above. Errors are ModelError: malformed text names
// `documentField` and shows the text near the error; a limit names the JSON path of the value,
// written `pathPrefix` + "points[2][1]" (the document itself is `documentField`).
nlohmann::json parseJsonText(std::string_view text, const std::string& documentField,
                             const std::string& pathPrefix = "");

// `s` cut to at most `maxChars` characters ("..." at the end when cut, never inside a UTF-8
// sequence).
std::string shortText(std::string_view s, std::size_t maxChars = kMaxValueChars);
// A JSON value as compact JSON text (as dump() writes it), cut like shortText; only the part
// shown is ever formatted.
std::string shortValue(const nlohmann::json& value, std::size_t maxChars = kMaxValueChars);

}  // namespace shapespline::io
