// Positioned writes from a thread of their own (io/block_writer.h).
#include <shapespline/io/block_writer.h>

namespace shapespline::io {

namespace {

// Blocks of finished writers, for the next ones. A batch of small models (`sample DIR`) otherwise
// allocated, faulted in and gave back to the kernel a writer's blocks for every model: 1,000 models
// of 614 KB: 4.9-6.2 ms per model, 3.1-3.5 ms with the blocks kept (docs/performance.md). Bounded
// by kPoolBytes.
class BlockPool {
 public:
  static constexpr size_t kPoolBytes = size_t{16} << 20;

  // A block of at least `bytes`: a kept one when there is one, else a new one.
  BlockWriter::Storage take(size_t bytes) {
    {
      std::lock_guard lock(mutex_);
      for (size_t k = 0; k < kept_.size(); ++k) {
        if (kept_[k].bytes < bytes) continue;
        BlockWriter::Storage block = std::move(kept_[k]);
        kept_[k] = std::move(kept_.back());
        kept_.pop_back();
        held_ -= block.bytes;
        return block;
      }
    }
    return {std::make_unique_for_overwrite<char[]>(bytes), bytes};
  }
  // Takes over what fits in kPoolBytes; the rest stays in `blocks` and is freed with them.
  void keep(std::vector<BlockWriter::Storage>& blocks) {
    std::lock_guard lock(mutex_);
    for (BlockWriter::Storage& block : blocks) {
      if (held_ + block.bytes > kPoolBytes) break;
      held_ += block.bytes;
      kept_.push_back(std::move(block));
    }
  }

 private:
  std::mutex mutex_;
  std::vector<BlockWriter::Storage> kept_;
  size_t held_ = 0;
};

BlockPool& pool() {
  static BlockPool* p = new BlockPool;  // never destroyed: a writer ending at exit still finds it
  return *p;
}

}  // namespace

BlockWriter::BlockWriter(AtomicFile& out, size_t blockBytes, size_t blocks, Writes writes)
    : out_(out), blockBytes_(blockBytes) {
  for (size_t k = 0; k < blocks; ++k) {
    storage_.push_back(pool().take(blockBytes));
    free_.push_back(k);
  }
  if (writes == Writes::OnOwnThread) thread_ = std::thread([this] { run(); });
}

BlockWriter::~BlockWriter() {
  if (ownThread()) {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    queued_.notify_one();
    thread_.join();
  }
  pool().keep(storage_);
}

BlockWriter::Block BlockWriter::acquire() {
  std::unique_lock lock(mutex_);
  ++acquirers_;
  freed_.wait(lock, [&] { return failure_ || !free_.empty(); });
  --acquirers_;
  if (failure_) std::rethrow_exception(failure_);
  const size_t k = free_.back();
  free_.pop_back();
  return {storage_[k].data.get(), k};
}

void BlockWriter::submit(Block block, uint64_t offset, size_t size) {
  if (!ownThread()) {  // Writes::OnCaller: positioned writes of disjoint ranges need no lock
    std::exception_ptr error;
    try {
      out_.writeAt(offset, block.data, size);
    } catch (...) {
      error = std::current_exception();
    }
    std::lock_guard lock(mutex_);
    done(block.index, error);
    return;
  }
  bool idle;
  {
    std::lock_guard lock(mutex_);
    idle = head_ == queue_.size() && !writing_;  // the writer thread waits for work
    queue_.push_back({block.index, offset, size});
  }
  if (idle) queued_.notify_one();
}

void BlockWriter::finish() {
  std::unique_lock lock(mutex_);
  ++acquirers_;
  freed_.wait(lock, [&] { return failure_ || (head_ == queue_.size() && !writing_); });
  --acquirers_;
  if (failure_) std::rethrow_exception(failure_);
}

void BlockWriter::run() {
  std::unique_lock lock(mutex_);
  while (true) {
    queued_.wait(lock, [&] { return stop_ || head_ < queue_.size(); });
    if (stop_) return;
    const Pending p = queue_[head_++];
    if (head_ == queue_.size()) {  // drained: reuse the queue's storage
      queue_.clear();
      head_ = 0;
    }
    writing_ = true;
    lock.unlock();
    std::exception_ptr error;
    try {
      out_.writeAt(p.offset, storage_[p.index].data.get(), p.size);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    writing_ = false;
    done(p.index, error);
  }
}

void BlockWriter::done(size_t index, std::exception_ptr error) {
  free_.push_back(index);
  if (error && !failure_) failure_ = error;
  if (acquirers_ > 0) freed_.notify_all();
}

}  // namespace shapespline::io
