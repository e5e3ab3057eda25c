#pragma once
// NumPy .npy arrays that a model file names instead of writing the numbers out
// ("points": {"npy": "net.npy"}, docs/format.md "Arrays in .npy files"). Only what a control net
// needs is accepted: little-endian float64 or float32 ('<f8', '<f4'), C order, format versions 1-3.
// The header is checked in full before any value is read (dtype, order, shape, and the shape's
// byte count against the file's length, so a header claiming 10^12 elements or a truncated file
// is refused without allocating); the values are then read straight into the result (fp64) or
// through a fixed 1 MiB buffer (fp32).
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

namespace shapespline::io {

// The header block (magic, version, length, the dict text) is at most this long.
inline constexpr std::uint64_t kMaxNpyHeaderBytes = std::uint64_t{1} << 16;

struct NpyHeader {
  bool float64 = true;                // '<f8'; false: '<f4'
  std::vector<std::uint64_t> shape;   // () is a scalar: one value
  std::uint64_t dataOffset = 0;       // bytes before the first value
  std::uint64_t count = 1;            // values: the product of shape
};

// The header at the start of `head` (the file's first min(size, kMaxNpyHeaderBytes) bytes) of a
// file of `fileBytes` bytes. Throws std::invalid_argument whose message is the rule broken.
NpyHeader parseNpyHeader(std::string_view head, std::uint64_t fileBytes);

struct NpyArray {
  std::vector<std::uint64_t> shape;
  std::vector<double> values;        // C order; empty when the values are in `points`
  std::vector<glm::dvec3> points;    // the values in threes (C order), read with NpyLayout::Points

  const double* data() const { return points.empty() ? values.data() : &points.data()->x; }
  size_t size() const { return points.empty() ? values.size() : 3 * points.size(); }
};

// How the values are kept. Points: an array whose last extent is 3 goes straight into `points`
// (a control net, with no second copy); one of shape (rows, cols, 3) gets room for the patch net of
// a surface of rows x cols points (core/surface.h netCapacity), which Surface::create then builds
// in the same block. Any other shape is read as values.
enum class NpyLayout { Values, Points };

// The array of the regular file `path` as doubles. Its values (8 bytes each, whatever the file's
// dtype) may take at most `maxValueBytes`, checked on the header before reading. Throws
// std::invalid_argument (the rule: not a regular file, a bad header, over the budget, a file that
// changed while read) and std::runtime_error when the file cannot be opened or read.
NpyArray readNpyArray(const std::filesystem::path& path, std::uint64_t maxValueBytes,
                      NpyLayout layout = NpyLayout::Values);

class InputFd;

// The values of a .npy file in order, a run at a time, as doubles: an array of any size is read in
// bounded memory (a shard that streams a net through its checks), and readNpyArray reads through
// it. The constructor checks the header as readNpyArray describes (budget included); read() fails
// like readNpyArray, and the read that takes the last value also checks that the file ends there.
class NpyReader {
 public:
  NpyReader(const std::filesystem::path& path, std::uint64_t maxValueBytes);
  ~NpyReader();
  NpyReader(const NpyReader&) = delete;
  NpyReader& operator=(const NpyReader&) = delete;

  const NpyHeader& header() const { return header_; }
  // The next `count` values (at most those left) into `out`.
  void read(double* out, size_t count);
  // Moves on past the next `count` values (at most those left) without reading them.
  void skip(std::uint64_t count);

 private:
  std::filesystem::path path_;
  std::unique_ptr<InputFd> file_;
  NpyHeader header_;
  std::uint64_t done_ = 0;
  std::vector<float> floats_;  // fp32 files: the values as read, 1 MiB at a time
};

// Room for the values of an array of `shape` read as points: the surface net's capacity for
// (rows, cols, 3) but at most a quarter more than the points, the points themselves otherwise.
size_t pointCapacity(const std::vector<std::uint64_t>& shape);

}  // namespace shapespline::io
