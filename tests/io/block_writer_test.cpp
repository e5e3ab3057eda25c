// io::BlockWriter: blocks filled on several threads land at their offsets, and writers one after
// another (a batch's models) reuse the blocks of the last ones through the writer's pool, whatever
// their block sizes: a later writer with larger blocks never gets a smaller kept block (under the
// sanitizers an overrun here is a report), and a smaller one writes only its own bytes; so do the
// submitting threads when the writer has no thread of its own.
#include <gtest/gtest.h>

#include <filesystem>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "support/temp_files.h"

#include <shapespline/io/atomic_file.h>
#include <shapespline/io/block_writer.h>

namespace shapespline::io {
namespace {

namespace fs = std::filesystem;

// The byte at file offset `at` of writer number `writer`.
char writerByte(size_t writer, size_t at) { return static_cast<char>((at * 131 + writer * 17 + (at >> 11)) & 0xff); }

// Writes `blocks` full blocks of `blockBytes` from two threads, block k at offset k * blockBytes,
// each block filled to its last byte, and returns the committed file's bytes.
std::vector<char> writeBlocks(size_t writer, size_t blockBytes, size_t blocks,
                              BlockWriter::Writes writes = BlockWriter::Writes::OnOwnThread) {
  const fs::path path = test::processTempFile("block", std::to_string(writer) + ".bin");
  {
    AtomicFile file(path);
    BlockWriter out(file, blockBytes, 3, writes);
    EXPECT_EQ(out.blockBytes(), blockBytes);
    auto fill = [&](size_t first) {
      for (size_t k = first; k < blocks; k += 2) {
        const BlockWriter::Block block = out.acquire();
        for (size_t b = 0; b < blockBytes; ++b) block.data[b] = writerByte(writer, k * blockBytes + b);
        out.submit(block, k * blockBytes, blockBytes);
      }
    };
    std::thread other(fill, 1);
    fill(0);
    other.join();
    out.finish();
    file.commit();
  }
  std::vector<char> bytes = test::readBytes(path);
  fs::remove(path);
  return bytes;
}

TEST(BlockWriter, WritersOneAfterAnotherOfAnyBlockSizeWriteEveryByteAtItsOffset) {
  // Small after large, large after small, and one larger than everything kept before.
  const size_t sizes[] = {size_t{64} << 10, size_t{1} << 20, size_t{64} << 10, 4096 + 3, size_t{3} << 20,
                          size_t{614} << 10};
  for (size_t w = 0; w < std::size(sizes); ++w) {
    SCOPED_TRACE("writer " + std::to_string(w) + ", blocks of " + std::to_string(sizes[w]) + " bytes");
    const size_t blocks = 7;
    const std::vector<char> bytes = writeBlocks(w, sizes[w], blocks);
    ASSERT_EQ(bytes.size(), blocks * sizes[w]);
    size_t wrong = 0;
    for (size_t at = 0; at < bytes.size(); ++at) wrong += bytes[at] != writerByte(w, at);
    EXPECT_EQ(wrong, 0u);
  }
}

// Without a thread of its own (a job of one block) the submitting threads write: the same bytes.
TEST(BlockWriter, WritesOnTheCallersThreadsPlaceEveryByteAtItsOffset) {
  const size_t sizes[] = {size_t{614} << 10, 4096 + 3};
  for (size_t w = 0; w < std::size(sizes); ++w) {
    SCOPED_TRACE("blocks of " + std::to_string(sizes[w]) + " bytes");
    const std::vector<char> bytes = writeBlocks(w, sizes[w], 5, BlockWriter::Writes::OnCaller);
    ASSERT_EQ(bytes.size(), 5 * sizes[w]);
    size_t wrong = 0;
    for (size_t at = 0; at < bytes.size(); ++at) wrong += bytes[at] != writerByte(w, at);
    EXPECT_EQ(wrong, 0u);
  }
}

}  // namespace
}  // namespace shapespline::io
