// write_queue.h — images converted and written on worker threads, so the thread that renders
// never encodes: the frames of a sequence are encoded while the device draws the next ones.
//
// A WriteQueue runs jobs (each writes its files through the library's writers, which write
// a temporary and rename it into place) on a few threads. submit() blocks while `capacity`
// jobs wait, so a renderer faster than its encoders holds a bounded number of frames. The
// first job that fails stops the queue: later jobs are dropped, failed() turns true and
// finish() rethrows that job's error; the files earlier jobs wrote are kept.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace clhair {

class WriteQueue {
 public:
  // `threads` 0: one per hardware thread but one, at least 1 and at most 8. `capacity` 0:
  // twice the threads.
  explicit WriteQueue(unsigned threads = 0, std::size_t capacity = 0);
  ~WriteQueue();  // finishes the queued jobs; errors are dropped (call finish() to see them)
  WriteQueue(const WriteQueue&) = delete;
  WriteQueue& operator=(const WriteQueue&) = delete;

  // Queues `job` (false when the queue has failed: the job is dropped).
  bool submit(std::function<void()> job);
  // Waits for every queued job; rethrows the first failure.
  void finish();
  bool failed() const;
  unsigned threads() const { return static_cast<unsigned>(workers_.size()); }

 private:
  void work();
  mutable std::mutex mutex_;
  std::condition_variable wake_, room_, idle_;
  std::deque<std::function<void()>> jobs_;
  std::vector<std::thread> workers_;
  std::size_t capacity_ = 1, running_ = 0;
  std::exception_ptr error_;
  bool stop_ = false;
};

}  // namespace clhair
