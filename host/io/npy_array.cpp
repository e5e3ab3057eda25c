#include <shapespline/io/npy_array.h>

#include <shapespline/core/huge_pages.h>
#include <shapespline/core/model.h>
#include <shapespline/core/surface.h>
#include <shapespline/io/input_file.h>

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace shapespline::io {

// fp64 values are read straight into doubles: the file's little-endian bytes are the host's.
static_assert(std::endian::native == std::endian::little, "the .npy reader assumes a little-endian host");

namespace {

[[noreturn]] void refuse(const std::string& rule) { throw std::invalid_argument(rule); }

// The header dict, a Python literal as numpy writes it: {'descr': '<f8', 'fortran_order': False,
// 'shape': (2048, 2048, 3), } then spaces and a newline. Parsed strictly: these three keys once
// each, nothing else.
class DictParser {
 public:
  explicit DictParser(std::string_view text) : s_(text) {}

  NpyHeader parse() {
    NpyHeader h;
    std::optional<std::string> descr;
    std::optional<bool> fortran;
    std::optional<std::vector<std::uint64_t>> shape;
    expect('{');
    while (!peek('}')) {
      const std::string key = quoted();
      expect(':');
      if (key == "descr") {
        if (descr) refuse("the header gives 'descr' twice");
        descr = quoted();
      } else if (key == "fortran_order") {
        if (fortran) refuse("the header gives 'fortran_order' twice");
        fortran = boolean();
      } else if (key == "shape") {
        if (shape) refuse("the header gives 'shape' twice");
        shape = tuple();
      } else {
        refuse("the header has the unknown key '" + key.substr(0, 32) + "' (a .npy header has descr, fortran_order and shape)");
      }
      if (!peek('}')) expect(',');
    }
    expect('}');
    skipSpace();
    if (pos_ != s_.size()) refuse("the header has text after its dict");
    if (!descr || !fortran || !shape) refuse("the header lacks descr, fortran_order or shape");
    if (*descr == "<f8") h.float64 = true;
    else if (*descr == "<f4") h.float64 = false;
    else refuse("dtype '" + descr->substr(0, 16) + "' is not float64 or float32 little-endian ('<f8', '<f4')");
    if (*fortran) refuse("the array is in Fortran order; write it in C order (numpy.ascontiguousarray)");
    h.shape = *shape;
    return h;
  }

 private:
  void skipSpace() {
    while (pos_ < s_.size() && (s_[pos_] == ' ' || s_[pos_] == '\n' || s_[pos_] == '\t')) ++pos_;
  }
  bool peek(char c) {
    skipSpace();
    return pos_ < s_.size() && s_[pos_] == c;
  }
  void expect(char c) {
    if (!peek(c)) refuse(std::string("the header dict is malformed (expected '") + c + "' at byte " + std::to_string(pos_) + ")");
    ++pos_;
  }
  std::string quoted() {
    skipSpace();
    if (pos_ >= s_.size() || (s_[pos_] != '\'' && s_[pos_] != '"')) refuse("the header dict is malformed (expected a string at byte " + std::to_string(pos_) + ")");
    const char q = s_[pos_++];
    const size_t end = s_.find(q, pos_);
    if (end == std::string_view::npos) refuse("the header dict is malformed (an unterminated string)");
    std::string out(s_.substr(pos_, end - pos_));
    pos_ = end + 1;
    return out;
  }
  bool boolean() {
    skipSpace();
    for (const auto& [word, value] : {std::pair{std::string_view("True"), true}, std::pair{std::string_view("False"), false}})
      if (s_.substr(pos_, word.size()) == word) {
        pos_ += word.size();
        return value;
      }
    refuse("fortran_order must be True or False");
  }
  std::vector<std::uint64_t> tuple() {
    std::vector<std::uint64_t> dims;
    expect('(');
    while (!peek(')')) {
      skipSpace();
      std::uint64_t v = 0;
      size_t digits = 0;
      while (pos_ < s_.size() && s_[pos_] >= '0' && s_[pos_] <= '9') {
        if (v > (std::numeric_limits<std::uint64_t>::max() - 9) / 10) refuse("a shape entry is too large");
        v = v * 10 + std::uint64_t(s_[pos_++] - '0');
        ++digits;
      }
      if (pos_ < s_.size() && s_[pos_] == 'L') ++pos_;  // Python 2 long
      if (digits == 0) refuse("the shape must be a tuple of non-negative integers");
      if (dims.size() == 32) refuse("the shape has more than 32 dimensions");
      dims.push_back(v);
      if (!peek(')')) expect(',');
    }
    expect(')');
    return dims;
  }

  std::string_view s_;
  size_t pos_ = 0;
};

std::uint16_t le16(const char* p) {
  return std::uint16_t(std::uint8_t(p[0]) | std::uint8_t(p[1]) << 8);
}
std::uint32_t le32(const char* p) {
  return std::uint32_t(std::uint8_t(p[0])) | std::uint32_t(std::uint8_t(p[1])) << 8 |
         std::uint32_t(std::uint8_t(p[2])) << 16 | std::uint32_t(std::uint8_t(p[3])) << 24;
}

// Reads exactly n bytes at the current offset, or fails naming the file as changed.
void readExactly(int fd, char* dst, std::uint64_t n, const std::filesystem::path& path) {
  while (n > 0) {
    const ssize_t got = ::read(fd, dst, size_t(std::min<std::uint64_t>(n, std::uint64_t{1} << 30)));
    if (got < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error("cannot read '" + path.string() + "': " + std::strerror(errno));
    }
    if (got == 0) refuse("the file ended early (it changed while being read)");
    dst += got;
    n -= std::uint64_t(got);
  }
}

}  // namespace

NpyHeader parseNpyHeader(std::string_view head, std::uint64_t fileBytes) {
  static constexpr char kMagic[] = "\x93NUMPY";
  if (head.size() < 10 || head.substr(0, 6) != std::string_view(kMagic, 6))
    refuse("not a .npy file (it does not start with \\x93NUMPY)");
  const int major = std::uint8_t(head[6]);
  if (major < 1 || major > 3) refuse(".npy format version " + std::to_string(major) + " is not 1, 2 or 3");
  const size_t lengthBytes = major == 1 ? 2 : 4;
  if (head.size() < 8 + lengthBytes) refuse("the header is cut short");
  const std::uint64_t dictBytes = major == 1 ? le16(head.data() + 8) : le32(head.data() + 8);
  const std::uint64_t offset = 8 + lengthBytes + dictBytes;
  if (offset > kMaxNpyHeaderBytes) refuse("the header is longer than " + std::to_string(kMaxNpyHeaderBytes) + " bytes");
  if (offset > head.size() || offset > fileBytes) refuse("the header is cut short (the file ends inside it)");
  NpyHeader h = DictParser(head.substr(8 + lengthBytes, dictBytes)).parse();
  h.dataOffset = offset;
  h.count = 1;
  for (std::uint64_t d : h.shape) {
    if (d != 0 && h.count > std::numeric_limits<std::uint64_t>::max() / 8 / d)
      refuse("the shape's element count overflows");
    h.count *= d;
  }
  const std::uint64_t item = h.float64 ? 8 : 4;
  const std::uint64_t dataBytes = fileBytes - offset;
  if (dataBytes != h.count * item)
    refuse("the shape needs " + std::to_string(h.count * item) + " data bytes, the file has " +
           std::to_string(dataBytes) + (dataBytes < h.count * item ? " (truncated)" : " (extra bytes at its end)"));
  return h;
}

size_t pointCapacity(const std::vector<std::uint64_t>& shape) {
  std::uint64_t count = 1;
  for (std::uint64_t d : shape) count *= d;
  const size_t points = size_t(count / 3);
  constexpr std::uint64_t kIntExtent = std::numeric_limits<int>::max() / 2;
  if (shape.size() != 3 || shape[2] != 3 || shape[0] > kIntExtent || shape[1] > kIntExtent) return points;
  // At most a quarter more than the points: a net has only a few rows and columns more (0.1% at
  // 4096²), and a shape like (1, 10^8, 3), which no surface accepts, must not reserve 11 times the
  // array budget.
  return std::clamp(netCapacity(int(shape[0]), int(shape[1])), points, points + points / 4);
}

NpyReader::NpyReader(const std::filesystem::path& path, std::uint64_t maxValueBytes) : path_(path) {
  try {
    file_ = std::make_unique<InputFd>(path, "");
  } catch (const ModelError& e) {
    refuse(e.rule());  // not a regular file: the caller names the key and the file
  }
  const int fd = file_->get();
  const std::uint64_t fileBytes = file_->size();
  std::string head(size_t(std::min<std::uint64_t>(fileBytes, kMaxNpyHeaderBytes)), '\0');
  readExactly(fd, head.data(), head.size(), path);
  header_ = parseNpyHeader(head, fileBytes);
  if (header_.count > maxValueBytes / 8)
    refuse("its " + std::to_string(header_.count) + " values need " + std::to_string(header_.count * 8) +
           " bytes as float64, over the array budget of " + std::to_string(maxValueBytes) + " bytes");
  if (::lseek(fd, off_t(header_.dataOffset), SEEK_SET) < 0)
    throw std::runtime_error("cannot seek in '" + path.string() + "': " + std::strerror(errno));
}

NpyReader::~NpyReader() = default;

void NpyReader::skip(std::uint64_t count) {
  if (count > header_.count - done_) throw std::logic_error("NpyReader::skip past the array's end");
  if (::lseek(file_->get(), off_t(count * (header_.float64 ? 8 : 4)), SEEK_CUR) < 0)
    throw std::runtime_error("cannot seek in '" + path_.string() + "': " + std::strerror(errno));
  done_ += count;
}

void NpyReader::read(double* out, size_t count) {
  if (count > header_.count - done_) throw std::logic_error("NpyReader::read past the array's end");
  const int fd = file_->get();
  if (header_.float64) {
    readExactly(fd, reinterpret_cast<char*>(out), std::uint64_t(count) * 8, path_);
  } else {
    constexpr size_t kChunk = size_t{1} << 18;  // floats per read: 1 MiB
    if (floats_.empty()) floats_.resize(std::min<size_t>(kChunk, size_t(header_.count)));
    for (size_t done = 0; done < count;) {
      const size_t n = std::min(floats_.size(), count - done);
      readExactly(fd, reinterpret_cast<char*>(floats_.data()), n * 4, path_);
      std::copy(floats_.begin(), floats_.begin() + std::ptrdiff_t(n), out + done);
      done += n;
    }
  }
  done_ += count;
  if (done_ < header_.count) return;
  char extra = 0;
  ssize_t more = 0;
  do {
    more = ::read(fd, &extra, 1);
  } while (more < 0 && errno == EINTR);
  if (more != 0) refuse("the file grew while being read");
}

NpyArray readNpyArray(const std::filesystem::path& path, std::uint64_t maxValueBytes, NpyLayout layout) {
  NpyReader reader(path, maxValueBytes);
  const NpyHeader& h = reader.header();
  NpyArray out;
  out.shape = h.shape;
  double* values = nullptr;
  if (layout == NpyLayout::Points && !h.shape.empty() && h.shape.back() == 3 && h.count > 0) {
    reserveHuge(out.points, pointCapacity(h.shape));
    out.points.resize(size_t(h.count / 3));
    values = &out.points.data()->x;
  } else {
    resizeHuge(out.values, size_t(h.count));
    values = out.values.data();
  }
  reader.read(values, size_t(h.count));
  return out;
}

}  // namespace shapespline::io
