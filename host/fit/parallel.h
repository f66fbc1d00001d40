// parallel.h — a blocking parallel loop for the fitter's per-strand and per-bundle work.
//
// parallelFor(n, threads, fn) calls fn(begin, end) on contiguous chunks of [0, n) from up to
// `threads` std::threads (0: the hardware's) and returns when all are done. Chunks are
// handed out dynamically, so uneven work balances; fn must only write to what its range
// owns. An exception thrown by fn is rethrown in the caller after every thread stopped.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace clhair::fit {

inline int resolveThreads(int threads) {
  if (threads > 0) return threads;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw > 0 ? static_cast<int>(hw) : 1;
}

template <class Fn>
void parallelFor(std::size_t n, int threads, Fn&& fn, std::size_t grain = 256) {
  if (n == 0) return;
  const int t =
      std::max(1, std::min(resolveThreads(threads), static_cast<int>((n + grain - 1) / grain)));
  if (t == 1) {
    fn(std::size_t{0}, n);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex errorMutex;
  auto work = [&]() {
    try {
      for (;;) {
        const std::size_t b = next.fetch_add(grain);
        if (b >= n) return;
        fn(b, std::min(n, b + grain));
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(errorMutex);
      if (!error) error = std::current_exception();
      next.store(n);
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < t; ++i) pool.emplace_back(work);
  work();
  for (std::thread& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace clhair::fit
