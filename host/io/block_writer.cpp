// Positioned writes from a thread of their own (io/block_writer.h).
#include <shapespline/io/block_writer.h>

namespace shapespline::io {

BlockWriter::BlockWriter(AtomicFile& out, size_t blockBytes, size_t blocks) : out_(out), blockBytes_(blockBytes) {
  for (size_t k = 0; k < blocks; ++k) {
    storage_.push_back(std::make_unique_for_overwrite<char[]>(blockBytes));
    free_.push_back(k);
  }
  thread_ = std::thread([this] { run(); });
}

BlockWriter::~BlockWriter() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  queued_.notify_one();
  thread_.join();
}

BlockWriter::Block BlockWriter::acquire() {
  std::unique_lock lock(mutex_);
  ++acquirers_;
  freed_.wait(lock, [&] { return failure_ || !free_.empty(); });
  --acquirers_;
  if (failure_) std::rethrow_exception(failure_);
  const size_t k = free_.back();
  free_.pop_back();
  return {storage_[k].get(), k};
}

void BlockWriter::submit(Block block, uint64_t offset, size_t size) {
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
      out_.writeAt(p.offset, storage_[p.index].get(), p.size);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    writing_ = false;
    free_.push_back(p.index);
    if (error && !failure_) failure_ = error;
    if (acquirers_ > 0) freed_.notify_all();
  }
}

}  // namespace shapespline::io
