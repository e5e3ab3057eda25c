#pragma once
// Shard file-name patterns (issue 16): `sample -o 'out-{shard:05d}-of-{count:05d}.f32' --shard K/N`
// writes out-0000K-of-0000N.f32, and `merge -o OUT 'out-{shard:05d}-of-{count:05d}.f32'` expands the
// same pattern to the shards 1..N. Placeholders: `{shard}` (K, 1-based) and `{count}` (N), each
// optionally zero-padded to a width W in 1..10 as `{shard:0Wd}` (as Python's format and printf
// write it; a number wider than W is written in full). Other braces are ordinary characters.
// Placeholders may appear in the file name only (not in a folder), and a placeholder must not be
// followed directly by a digit or by another placeholder, so that every expanded name reads back to
// one (K, N) (match()).
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace shapespline::jobs {

// A malformed pattern; what() is the rule (the caller names the option: "-o", "SHARD").
class ShardPatternError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

inline constexpr int kMaxPatternWidth = 10;

class ShardPattern {
 public:
  struct Part {
    enum class Kind { Text, Shard, Count } kind = Kind::Text;
    std::string text;  // Text only
    int width = 0;     // 0: no padding
  };

  // True when `path` holds a placeholder opening (`{shard` or `{count`): it is then a pattern and
  // must parse.
  static bool looksLikePattern(std::string_view path);
  // Throws ShardPatternError naming the offending placeholder and its position (1-based).
  static ShardPattern parse(std::string_view path);

  // The path of shard k of n.
  std::string expand(uint64_t k, uint64_t n) const;
  // The folder part of the pattern, up to and including its last '/' ("" when none).
  const std::string& folder() const { return folder_; }
  bool hasShard() const { return hasShard_; }
  bool hasCount() const { return hasCount_; }
  // (K, N) when `fileName` (no folder) is the file name of expand(K, N); N is 0 when the pattern
  // has no {count}, K is 0 when it has no {shard}. Numbers are at most 10 digits.
  std::optional<std::pair<uint64_t, uint64_t>> match(std::string_view fileName) const;

 private:
  std::string folder_;
  std::vector<Part> parts_;  // the file name
  bool hasShard_ = false, hasCount_ = false;
};

}  // namespace shapespline::jobs
