#pragma once
// The byte layout of a merge fuzz input, shared by merge_fuzzer.cpp (decode) and
// merge_fuzz_seeds.cpp (encode): byte 0 picks the format (value % 5: obj, ply, csv, f64, f32), the
// rest is split at kMergeFuzzSeparator into at most 6 parts. Text and PLY formats: one part per
// shard (at most 3). Raw formats: data, sidecar, data, sidecar, ... (at most 3 shards; a shard
// without its sidecar part has no sidecar file).
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace shapespline::test {

inline constexpr std::string_view kMergeFuzzSeparator = "\n#SHARD#\n";
inline constexpr size_t kMergeFuzzMaxShards = 3;
inline constexpr const char* kMergeFuzzExtensions[5] = {"obj", "ply", "csv", "f64", "f32"};

struct MergeFuzzShard {
  std::string data, sidecar;
  bool hasSidecar = false;
};

struct MergeFuzzInput {
  int format = 0;  // index into kMergeFuzzExtensions
  std::vector<MergeFuzzShard> shards;
  bool raw() const { return format >= 3; }
  std::string extension() const { return kMergeFuzzExtensions[format]; }
};

inline MergeFuzzInput decodeMergeFuzzInput(std::string_view bytes) {
  MergeFuzzInput in;
  if (bytes.empty()) return in;
  in.format = static_cast<unsigned char>(bytes[0]) % 5;
  bytes.remove_prefix(1);
  std::vector<std::string_view> parts;
  while (parts.size() < 2 * kMergeFuzzMaxShards) {
    const size_t at = bytes.find(kMergeFuzzSeparator);
    if (at == std::string_view::npos || parts.size() + 1 == 2 * kMergeFuzzMaxShards) {
      parts.push_back(bytes);
      break;
    }
    parts.push_back(bytes.substr(0, at));
    bytes.remove_prefix(at + kMergeFuzzSeparator.size());
  }
  if (in.raw()) {
    for (size_t i = 0; i < parts.size(); i += 2) {
      MergeFuzzShard s;
      s.data = std::string(parts[i]);
      s.hasSidecar = i + 1 < parts.size();
      if (s.hasSidecar) s.sidecar = std::string(parts[i + 1]);
      in.shards.push_back(std::move(s));
    }
  } else {
    for (size_t i = 0; i < parts.size() && i < kMergeFuzzMaxShards; ++i)
      in.shards.push_back({std::string(parts[i]), "", false});
  }
  return in;
}

inline std::string encodeMergeFuzzInput(const MergeFuzzInput& in) {
  std::string s(1, static_cast<char>(in.format));
  bool firstPart = true;
  auto part = [&](const std::string& p) {
    if (!firstPart) s += kMergeFuzzSeparator;
    s += p;
    firstPart = false;
  };
  for (const auto& sh : in.shards) {
    part(sh.data);
    if (in.raw() && sh.hasSidecar) part(sh.sidecar);
  }
  return s;
}

}  // namespace shapespline::test
