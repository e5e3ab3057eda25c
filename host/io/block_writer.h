#pragma once
// Positioned writes from a thread of their own: the sampler's workers fill blocks with records and
// hand them over, and go on computing while this thread copies them into the file. The kernel
// serialises the writes of one file anyway (its inode lock), so workers writing themselves spent
// half their time waiting for each other (e2e .f32 of 15.2 M points x 3 fields: 0.42 s with one
// worker or two). Memory is bounded: `blocks` buffers of `blockBytes`, reused, and kept for the next
// writer up to a bound (block_writer.cpp). A job of one block gains nothing from the thread and
// pays its start and a wake-up per block, so it may write on the caller's thread instead (Writes).
#include <shapespline/io/atomic_file.h>

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace shapespline::io {

class BlockWriter {
 public:
  struct Block {
    char* data = nullptr;
    size_t index = 0;
  };
  // A block's memory: at least blockBytes(). Blocks outlive their writer in a bounded pool
  // (block_writer.cpp), so that the next writer, e.g. of a batch's next model, reuses pages
  // already faulted in.
  struct Storage {
    std::unique_ptr<char[]> data;
    size_t bytes = 0;
  };

  // Where submit()'s blocks are written: by a thread of the writer's own while the caller goes on,
  // or at once by the thread that submits them. Either way a failed write is rethrown by the next
  // acquire() or finish(), never by submit().
  enum class Writes { OnOwnThread, OnCaller };

  BlockWriter(AtomicFile& out, size_t blockBytes, size_t blocks, Writes writes = Writes::OnOwnThread);
  ~BlockWriter();  // stops the thread; blocks not yet written are dropped (the file is being discarded)
  BlockWriter(const BlockWriter&) = delete;
  BlockWriter& operator=(const BlockWriter&) = delete;

  size_t blockBytes() const { return blockBytes_; }
  bool ownThread() const { return thread_.joinable(); }  // Writes::OnOwnThread
  // A free block (waits while all are queued). Rethrows a failed write.
  Block acquire();
  // Queues the first `size` bytes of `block` for byte `offset` of the file.
  void submit(Block block, uint64_t offset, size_t size);
  // Waits until every queued block is in the file. Rethrows a failed write.
  void finish();

 private:
  struct Pending {
    size_t index;
    uint64_t offset;
    size_t size;
  };
  void run();
  void done(size_t index, std::exception_ptr error);  // under mutex_

  AtomicFile& out_;
  size_t blockBytes_;
  std::vector<Storage> storage_;
  std::mutex mutex_;
  // Two conditions, each notified only when its waiters can go on: a wake-up of a thread on
  // another core costs microseconds (more in a VM), and one per block for every thread showed as
  // 9% of an e2e .f32 job's CPU time.
  std::condition_variable queued_;  // the writer thread: a block to write, or stop
  std::condition_variable freed_;   // acquire() and finish(): a block written, or a failure
  size_t acquirers_ = 0;            // threads waiting in acquire()
  std::vector<size_t> free_;
  std::vector<Pending> queue_;  // FIFO through head_
  size_t head_ = 0;
  bool writing_ = false, stop_ = false;
  std::exception_ptr failure_;
  std::thread thread_;  // none for Writes::OnCaller
};

}  // namespace shapespline::io
