// transfer.h — moving bytes between host and device without stalling the host.
//
// Uploads are copied into staging blocks and enqueued without blocking; a block is freed
// once its write has completed, which is checked without waiting (or, past a cap on the
// staged bytes, by waiting for the oldest). Read-backs whose values the host needs at once
// block and are counted as host waits; read-backs of a frame's results are enqueued without
// blocking into memory the frame owns and complete with the frame's event. Every call that
// makes the host wait for the device goes through countWait(), so the frame executor can
// count the waits of each pass and of each frame (host/graph/frame_graph.h).
// Invariant: the queue is in order, so a staged upload is seen by every command enqueued
// after it, and a non-blocking read sees every command enqueued before it.
// A staged upload also holds its destination buffer until the write completes: OpenCL
// keeps a released buffer alive for its pending commands, but a runtime that does not
// (Oclgrind 21.10 frees it at once, and the write then lands in whatever buffer takes its
// place) would otherwise see writes into the wrong buffer.
#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

#include "cl/opencl.h"

namespace clhair {

class Transfers {
 public:
  // Enqueues a non-blocking write of `bytes` bytes of `data` at byte `offset` of `buffer`
  // from a private copy of them; `data` may change as soon as this returns.
  void upload(cl::CommandQueue& queue, const cl::Buffer& buffer, std::size_t offset,
              const void* data, std::size_t bytes);
  // One more time the host waited for the device (a blocking read, finish, event wait).
  void countWait() { ++waits_; }
  std::uint64_t hostWaits() const { return waits_; }
  // Bytes held by staging blocks whose writes may not have completed yet.
  std::size_t stagedBytes() const { return staged_; }

 private:
  void reclaim(bool waitOldest);
  std::mutex mutex_;
  struct Block {
    cl::Event done;
    std::vector<unsigned char> bytes;
    cl::Buffer destination;  // held until the write has completed
  };
  std::deque<Block> blocks_;
  std::size_t staged_ = 0;
  std::uint64_t waits_ = 0;
};

}  // namespace clhair
