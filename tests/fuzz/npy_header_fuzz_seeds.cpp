// Writes the seed corpus of npy_header_fuzzer into argv[1]: headers as numpy writes them (format
// versions 1, 2 and 3; float64 and float32; 1-, 2- and 3-D, a scalar and an empty array) with
// their data, and near misses (Fortran order, an int dtype, a cut file, a huge shape).
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

std::string npy(int major, const std::string& dict, size_t dataBytes) {
  std::string text = dict;
  const size_t lengthBytes = major == 1 ? 2 : 4;
  while ((10 + (lengthBytes - 2) + text.size() + 1) % 64 != 0) text += ' ';
  text += '\n';
  std::string out = "\x93NUMPY";
  out += char(major);
  out += char(0);
  for (size_t b = 0; b < lengthBytes; ++b) out += char((text.size() >> (8 * b)) & 0xff);
  return out + text + std::string(dataBytes, '\0');
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: npy_header_fuzz_seeds FOLDER\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  const auto dict = [](const char* descr, const char* fortran, const char* shape) {
    return std::string("{'descr': '") + descr + "', 'fortran_order': " + fortran + ", 'shape': " + shape + ", }";
  };
  const std::pair<const char*, std::string> seeds[] = {
      {"v1_f8_net", npy(1, dict("<f8", "False", "(4, 5, 3)"), 4 * 5 * 3 * 8)},
      {"v1_f4_curve", npy(1, dict("<f4", "False", "(7, 2)"), 7 * 2 * 4)},
      {"v2_f8_vector", npy(2, dict("<f8", "False", "(9,)"), 9 * 8)},
      {"v3_f8_scalar", npy(3, dict("<f8", "False", "()"), 8)},
      {"v1_empty", npy(1, dict("<f8", "False", "(0, 3)"), 0)},
      {"v1_fortran", npy(1, dict("<f8", "True", "(4, 5, 3)"), 4 * 5 * 3 * 8)},
      {"v1_int", npy(1, dict("<i8", "False", "(4, 3)"), 4 * 3 * 8)},
      {"v1_cut", npy(1, dict("<f8", "False", "(4, 5, 3)"), 100)},
      {"v1_huge", npy(1, dict("<f8", "False", "(1000000, 1000000, 3)"), 64)},
      {"v1_long", npy(1, dict("<f8", "False", "(3L, 2L)"), 48)},
  };
  for (const auto& [name, bytes] : seeds) std::ofstream(dir / name, std::ios::binary) << bytes;
  return 0;
}
