#include "chunks.h"

namespace shapespline::python {
namespace {

struct Cancelled {};

}  // namespace

ChunkStream::ChunkStream(Job job, const GridSpec& grid, FieldMask fields, Precision output, size_t capacity,
                         bool surface)
    : grid_(grid), fields_(fields), output_(output), capacity_(capacity < 1 ? 1 : capacity), surface_(surface) {
  producer_ = std::thread([this, job = std::move(job)] {
    std::optional<sampling::Report> r;
    std::exception_ptr error;
    try {
      r = job([this](const GridChunk& c) { consume(c); });
    } catch (const Cancelled&) {
    } catch (...) {
      error = std::current_exception();
    }
    std::lock_guard lock(mutex_);
    report_ = r;
    error_ = error;
    done_ = true;
    data_.notify_all();
  });
}

ChunkStream::~ChunkStream() { close(); }

void ChunkStream::consume(const GridChunk& chunk) {
  ChunkData d;
  d.firstItem = chunk.firstItem;
  d.itemCount = chunk.itemCount;
  d.firstRow = chunk.firstRow;
  d.rowCount = chunk.rowCount;
  d.points = chunk.pointCount();
  d.firstPoint = (chunk.firstItem - grid_.firstItem) * grid_.pointsPerItem() + chunk.firstItemPoint();
  const size_t n = d.points * 3;
  for (int f = 0; f < kFieldCount; ++f) {
    if (!(fields_ & (1u << f)) || !chunk.planes[size_t(f)]) continue;
    const void* src = chunk.planes[size_t(f)];
    if (output_ == Precision::Double) {
      auto& v = d.f64[size_t(f)];
      if (chunk.precision == Precision::Double) {
        const auto* s = static_cast<const double*>(src);
        v.assign(s, s + n);
      } else {
        const auto* s = static_cast<const float*>(src);
        v.assign(s, s + n);
      }
    } else {
      auto& v = d.f32[size_t(f)];
      if (chunk.precision == Precision::Float) {
        const auto* s = static_cast<const float*>(src);
        v.assign(s, s + n);
      } else {
        const auto* s = static_cast<const double*>(src);
        v.resize(n);
        for (size_t i = 0; i < n; ++i) v[i] = static_cast<float>(s[i]);
      }
    }
  }
  std::unique_lock lock(mutex_);
  space_.wait(lock, [&] { return queue_.size() < capacity_ || cancel_; });
  if (cancel_) throw Cancelled{};
  queue_.push_back(std::move(d));
  data_.notify_one();
}

std::optional<ChunkData> ChunkStream::next() {
  std::unique_lock lock(mutex_);
  data_.wait(lock, [&] { return !queue_.empty() || done_; });
  if (!queue_.empty()) {
    ChunkData d = std::move(queue_.front());
    queue_.pop_front();
    space_.notify_one();
    return d;
  }
  if (error_) {
    std::exception_ptr e = error_;
    error_ = nullptr;
    std::rethrow_exception(e);
  }
  return std::nullopt;
}

void ChunkStream::close() {
  {
    std::lock_guard lock(mutex_);
    cancel_ = true;
    queue_.clear();
    space_.notify_all();
  }
  if (producer_.joinable()) producer_.join();
}

std::optional<sampling::Report> ChunkStream::report() const {
  std::lock_guard lock(mutex_);
  return report_;
}

}  // namespace shapespline::python
