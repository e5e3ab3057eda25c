#pragma once
// A cloud of query points read a block at a time (`shapespline project POINTS`), from the files
// point-cloud tools write: .npy (float32 or float64, shape (N, 3)), PLY (ascii or binary
// little-endian; the x, y, z of its vertex element, which must come first; other scalar properties
// are skipped), CSV (x, y, z as the first three columns; a first line that is not numbers is a
// header) and raw little-endian .f32/.f64 (x y z triples). Every value must be finite: a bad one is
// a ModelError naming the file, the point's index and the value, and so are an empty cloud, a
// shape that is not (N, 3) and a truncated file. The count is known before the first block (a CSV
// file is counted by a first pass), so writers can put it in their headers.
#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace shapespline::io {

class PointCloudReader {
 public:
  // `field` names the file in errors ("POINTS").
  PointCloudReader(const std::filesystem::path& path, std::string field);
  ~PointCloudReader();
  PointCloudReader(const PointCloudReader&) = delete;
  PointCloudReader& operator=(const PointCloudReader&) = delete;

  std::uint64_t count() const { return count_; }
  // The next at most `max` points into `out` (replacing its contents); false when none are left.
  bool next(std::vector<glm::dvec3>& out, std::size_t max);
  // Passes over the next `count` points (at most those left) unread and unchecked: a shard's start.
  void skip(std::uint64_t count);

  struct Format;

 private:
  std::filesystem::path path_;
  std::string field_;
  std::uint64_t count_ = 0, done_ = 0;
  std::unique_ptr<Format> format_;
};

}  // namespace shapespline::io
