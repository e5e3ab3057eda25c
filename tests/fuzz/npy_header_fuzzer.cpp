// libFuzzer target over .npy headers (issue 31): the bytes of a file that a model's array
// reference names, through io::parseNpyHeader as readNpyArray calls it (its first
// min(size, kMaxNpyHeaderBytes) bytes, the file's size), and again as if the file were longer. The
// contract checked here:
//  * parsing either returns or throws std::invalid_argument (exit code 2); nothing else escapes;
//  * every message stays bounded (the header's own text is never echoed whole);
//  * an accepted header is consistent: its data start inside the file, the shape's element count
//    (no overflow) times the item size is exactly the bytes after the header.
// Sanitizers and libFuzzer's -timeout turn everything else into a finding. The same function is
// linked into `npy_header_fuzz_replay` (replay_main.cpp) for builds without libFuzzer.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include <shapespline/io/npy_array.h>

namespace {

constexpr size_t kMaxMessageChars = 300;

[[noreturn]] void violated(const std::string& what) {
  std::fprintf(stderr, "npy_header_fuzzer: contract violated: %s\n", what.c_str());
  std::abort();
}

void check(std::string_view bytes, uint64_t fileBytes) {
  using namespace shapespline::io;
  const std::string_view head = bytes.substr(0, size_t(std::min<uint64_t>(bytes.size(), kMaxNpyHeaderBytes)));
  try {
    const NpyHeader h = parseNpyHeader(head, fileBytes);
    if (h.dataOffset > fileBytes || h.dataOffset > kMaxNpyHeaderBytes) violated("data offset beyond the file or header limit");
    uint64_t count = 1;
    for (uint64_t d : h.shape) {
      if (d != 0 && count > UINT64_MAX / d) violated("accepted an overflowing shape");
      count *= d;
    }
    if (count != h.count) violated("count is not the shape's product");
    if (h.count * (h.float64 ? 8 : 4) != fileBytes - h.dataOffset) violated("data bytes do not match the shape");
  } catch (const std::invalid_argument& e) {
    if (std::string(e.what()).size() > kMaxMessageChars) violated(std::string("unbounded message: ") + e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  check(bytes, size);
  check(bytes, uint64_t(size) + 4096);  // a file that goes on past what the fuzzer gave
  return 0;
}
