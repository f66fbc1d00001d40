// write_queue.cpp — see clhair/write_queue.h.
#include "clhair/write_queue.h"

#include <algorithm>

namespace clhair {

WriteQueue::WriteQueue(unsigned threads, std::size_t capacity) {
  if (threads == 0) {
    const unsigned hw = std::thread::hardware_concurrency();
    threads = std::min(8u, std::max(1u, hw > 1 ? hw - 1 : 1u));
  }
  capacity_ = capacity > 0 ? capacity : 2 * static_cast<std::size_t>(threads);
  for (unsigned i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

WriteQueue::~WriteQueue() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [&] { return jobs_.empty() && running_ == 0; });
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

bool WriteQueue::submit(std::function<void()> job) {
  std::unique_lock<std::mutex> lock(mutex_);
  room_.wait(lock, [&] { return jobs_.size() < capacity_ || error_; });
  if (error_) return false;
  jobs_.push_back(std::move(job));
  wake_.notify_one();
  return true;
}

void WriteQueue::finish() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [&] { return jobs_.empty() && running_ == 0; });
  if (error_) std::rethrow_exception(error_);
}

bool WriteQueue::failed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return error_ != nullptr;
}

void WriteQueue::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || !jobs_.empty(); });
    if (jobs_.empty()) return;  // stop_
    std::function<void()> job = std::move(jobs_.front());
    jobs_.pop_front();
    ++running_;
    room_.notify_one();
    lock.unlock();
    std::exception_ptr failure;
    try {
      job();
    } catch (...) {
      failure = std::current_exception();
    }
    lock.lock();
    --running_;
    if (failure && !error_) {
      error_ = failure;
      jobs_.clear();  // what was not started is dropped
      room_.notify_all();
    }
    if (jobs_.empty() && running_ == 0) idle_.notify_all();
  }
}

}  // namespace clhair
