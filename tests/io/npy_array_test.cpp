// io/npy_array.h: .npy headers as numpy writes them (format versions 1-3, the dict text of
// numpy.lib.format) are accepted with their dtype, shape and data offset; every other header is
// refused with the rule it breaks, before any value is read; readNpyArray keeps to its budget.
#include <shapespline/io/npy_array.h>

#include <shapespline/core/surface.h>

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace shapespline::io {
namespace {

// A header of format `major` around `dict`, padded as numpy pads it (to 64 bytes, '\n' last).
std::string header(int major, std::string dict) {
  const size_t lengthBytes = major == 1 ? 2 : 4;
  while ((8 + lengthBytes + dict.size() + 1) % 64 != 0) dict += ' ';
  dict += '\n';
  std::string out = "\x93NUMPY";
  out += char(major);
  out += char(0);
  for (size_t b = 0; b < lengthBytes; ++b) out += char((dict.size() >> (8 * b)) & 0xff);
  return out + dict;
}

std::string dict(const std::string& descr, const std::string& fortran, const std::string& shape) {
  return "{'descr': '" + descr + "', 'fortran_order': " + fortran + ", 'shape': " + shape + ", }";
}

// The rule parseNpyHeader gives for `bytes` as a whole file, or "" when it accepts it.
std::string ruleFor(const std::string& bytes) {
  try {
    parseNpyHeader(bytes, bytes.size());
    return "";
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
}

TEST(NpyHeader, AcceptsWhatNumpyWrites) {
  // numpy.save of np.zeros((4, 5, 3)): version 1, 128-byte header.
  const std::string h = header(1, dict("<f8", "False", "(4, 5, 3)"));
  ASSERT_EQ(h.size(), 128u);
  const NpyHeader a = parseNpyHeader(h + std::string(4 * 5 * 3 * 8, '\0'), 128 + 480);
  EXPECT_TRUE(a.float64);
  EXPECT_EQ(a.shape, (std::vector<uint64_t>{4, 5, 3}));
  EXPECT_EQ(a.dataOffset, 128u);
  EXPECT_EQ(a.count, 60u);
  const std::string f32 = header(2, "{'descr': '<f4', 'fortran_order': False, 'shape': (7,), }");
  const NpyHeader b = parseNpyHeader(f32, f32.size() + 28);
  EXPECT_FALSE(b.float64);
  EXPECT_EQ(b.shape, (std::vector<uint64_t>{7}));
  const std::string scalar = header(3, dict("<f8", "False", "()"));
  EXPECT_EQ(parseNpyHeader(scalar, scalar.size() + 8).count, 1u);
  const std::string empty = header(1, dict("<f8", "False", "(0, 3)"));
  EXPECT_EQ(parseNpyHeader(empty, empty.size()).count, 0u);
  // Key order and quoting are free in the dict.
  const std::string reordered = header(1, "{\"shape\": (2, 3), \"fortran_order\": False, \"descr\": \"<f8\"}");
  EXPECT_EQ(parseNpyHeader(reordered, reordered.size() + 48).count, 6u);
}

TEST(NpyHeader, RefusesEveryOtherHeaderWithItsRule) {
  const std::string net = dict("<f8", "False", "(4, 5, 3)");
  const std::string data(480, '\0');
  const std::pair<std::string, std::string> cases[] = {
      {"PK\x03\x04 not numpy at all", "not a .npy file"},
      {header(4, net) + data, "version 4"},
      {header(1, dict("<i8", "False", "(4, 5, 3)")) + data, "not float64 or float32"},
      {header(1, dict(">f8", "False", "(4, 5, 3)")) + data, "little-endian"},
      {header(1, dict("<f8", "True", "(4, 5, 3)")) + data, "Fortran order"},
      {header(1, dict("<f8", "False", "(4, 5, 3)")) + data.substr(8), "truncated"},
      {header(1, dict("<f8", "False", "(4, 5, 3)")) + data + "x", "extra bytes"},
      {header(1, dict("<f8", "False", "(1000000, 1000000, 3)")) + data, "24000000000000 data bytes"},
      {header(1, dict("<f8", "False", "(4294967296, 4294967296, 4294967296)")), "overflows"},
      {header(1, dict("<f8", "False", "(99999999999999999999,)")), "too large"},
      {header(1, dict("<f8", "False", "(4, -5, 3)")), "non-negative integers"},
      {header(1, dict("<f8", "Maybe", "(4, 5, 3)")), "True or False"},
      {header(1, "{'descr': '<f8', 'fortran_order': False}") + data, "lacks"},
      {header(1, "{'descr': '<f8', 'descr': '<f8', 'fortran_order': False, 'shape': (1,)}"), "twice"},
      {header(1, "{'descr': '<f8', 'fortran_order': False, 'shape': (1,), 'extra': 1}"), "unknown key 'extra'"},
      {header(1, "{'descr': '<f8', 'fortran_order': False, 'shape': (1,)} trailing"), "text after"},
      {header(1, "{'descr: '<f8'}"), "malformed"},
      {header(1, net).substr(0, 60), "cut short"},
      {std::string("\x93NUMPY\x01\x00\xff\xff", 10) + std::string(70000, ' '), "longer than"},
  };
  for (const auto& [bytes, rule] : cases) {
    const std::string got = ruleFor(bytes);
    EXPECT_NE(got.find(rule), std::string::npos) << "want '" << rule << "', got '" << got << "'";
  }
}

class NpyFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("shapespline_npy_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path write(const std::string& name, const std::string& bytes) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    return dir_ / name;
  }
  std::filesystem::path dir_;
};

// A C-order .npy file of `values` as Real ("<f8" for double, "<f4" for float) in `shape`.
template <class Real>
std::string npyFile(const std::string& shape, const std::vector<double>& values) {
  std::string bytes = header(1, dict(sizeof(Real) == 8 ? "<f8" : "<f4", "False", shape));
  for (double v : values) {
    const Real r = static_cast<Real>(v);
    bytes.append(reinterpret_cast<const char*>(&r), sizeof r);
  }
  return bytes;
}

// value(k) for k < n.
std::vector<double> valuesOf(int n, double (*value)(int)) {
  std::vector<double> v;
  for (int k = 0; k < n; ++k) v.push_back(value(k));
  return v;
}

TEST_F(NpyFile, ReadsFloat64AndFloat32ValuesInCOrder) {
  const auto values = valuesOf(6, [](int k) { return 0.5 * k - 1.0; });
  for (const auto& path :
       {write("a.npy", npyFile<double>("(2, 3)", values)), write("b.npy", npyFile<float>("(2, 3)", values))}) {
    const NpyArray a = readNpyArray(path, 1 << 20);
    EXPECT_EQ(a.shape, (std::vector<uint64_t>{2, 3}));
    ASSERT_EQ(a.values.size(), 6u);
    for (int k = 0; k < 6; ++k) EXPECT_EQ(a.values[size_t(k)], 0.5 * k - 1.0);
  }
}

// NpyLayout::Points: the same values in threes, in one block with room for a surface's patch net,
// but never more than a quarter beyond the points (a shape no surface takes must not reserve more).
TEST_F(NpyFile, ReadsPointsIntoOneBlockWithRoomForTheNet) {
  const auto values = valuesOf(60, [](int k) { return 0.25 * k - 3.0; });
  for (const auto& path :
       {write("p8.npy", npyFile<double>("(4, 5, 3)", values)), write("p4.npy", npyFile<float>("(4, 5, 3)", values))}) {
    const NpyArray a = readNpyArray(path, 1 << 20, NpyLayout::Points);
    EXPECT_TRUE(a.values.empty());
    ASSERT_EQ(a.points.size(), 20u);
    ASSERT_EQ(a.size(), 60u);
    for (int k = 0; k < 60; ++k) EXPECT_EQ(a.data()[k], 0.25 * k - 3.0);
    EXPECT_GE(a.points.capacity(), pointCapacity(a.shape));
    EXPECT_EQ(readNpyArray(path, 1 << 20).values, std::vector<double>(a.data(), a.data() + a.size()));
  }
  // (4, 5, 3): a quarter more (25) caps the net's room; 4096² needs 0.5% more, which it gets.
  EXPECT_EQ(pointCapacity({4, 5, 3}), 25u);
  EXPECT_EQ(pointCapacity({4096, 4096, 3}), netCapacity(4096, 4096));
  EXPECT_EQ(pointCapacity({1, 100000000, 3}), 125000000u);
  EXPECT_EQ(pointCapacity({7, 3}), 7u);  // a curve: the points
}

TEST_F(NpyFile, KeepsToItsBudgetAndToRegularFiles) {
  const std::string bytes = header(1, dict("<f4", "False", "(1000,)")) + std::string(4000, '\0');
  const auto path = write("c.npy", bytes);
  EXPECT_EQ(readNpyArray(path, 8000).values.size(), 1000u);  // float32 counts as 8 bytes a value
  try {
    readNpyArray(path, 7999);
    ADD_FAILURE() << "over the budget, yet read";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("over the array budget of 7999 bytes"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readNpyArray(dir_, 1 << 20), std::invalid_argument);  // a directory
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  EXPECT_THROW(readNpyArray(dir_ / "fifo", 1 << 20), std::invalid_argument);  // never blocks
  EXPECT_THROW(readNpyArray(dir_ / "missing.npy", 1 << 20), std::runtime_error);
}

}  // namespace
}  // namespace shapespline::io
