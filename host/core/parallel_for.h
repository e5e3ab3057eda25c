#pragma once
// Runs body(i) for i in [0, count) on `threads` threads (0: the process's cores), each taking the
// next index as it finishes one, so faces of very different sizes balance. The first exception
// thrown stops the remaining indices and is rethrown on the caller's thread.
#include <shapespline/core/cores.h>

#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace shapespline {

template <typename Body>
void parallelFor(size_t count, int threads, const Body& body) {
  const size_t workers = std::min<size_t>(count, threads > 0 ? static_cast<size_t>(threads) : static_cast<size_t>(availableCores()));
  if (workers <= 1) {
    for (size_t i = 0; i < count; ++i) body(i);
    return;
  }
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex errorMutex;
  const auto run = [&] {
    for (size_t i; !failed && (i = next++) < count;) {
      try {
        body(i);
      } catch (...) {
        std::lock_guard lock(errorMutex);
        if (!error) error = std::current_exception();
        failed = true;
      }
    }
  };
  std::vector<std::thread> pool;
  for (size_t w = 1; w < workers; ++w) pool.emplace_back(run);
  run();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace shapespline
