// pending_frame.h — a frame in flight: everything the host keeps of a submitted frame until
// Renderer::wait hands it out, and the read-back of its results without blocking.
//
// A frame's results are read back by non-blocking reads enqueued after its last pass: on a
// device working in host memory (DeviceInfo::hostUnified) straight into the Frame's own
// vectors, otherwise into pinned staging memory (CL_MEM_ALLOC_HOST_PTR, mapped once), copied
// into the Frame when it completes. A marker after the reads is the frame's event. At
// completion the host decodes what it read (statistics, AOV planes) with the finishers the
// passes left, and collects the profiling events when timings were asked for.
// Invariant: nothing a pending frame's reads write into is freed or moved before the frame
// completes (the vectors are sized before the reads and not touched until then).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "cl/dispatch.h"
#include "clhair/renderer.h"

namespace clhair {

// Pinned host blocks for read-backs, kept between frames.
class PinnedPool {
 public:
  explicit PinnedPool(Device::Impl& dev) : dev_(dev) {}
  ~PinnedPool();
  PinnedPool(const PinnedPool&) = delete;
  PinnedPool& operator=(const PinnedPool&) = delete;
  struct Block {
    cl::Buffer buffer;
    void* host = nullptr;
    std::size_t bytes = 0;
  };
  Block acquire(std::size_t bytes);
  void release(Block b);

 private:
  Device::Impl& dev_;
  std::vector<Block> free_;
};

struct PendingFrame {
  std::uint64_t ticket = 0;
  std::vector<Frame> frames;  // one per view
  cl::Event done;
  Profiler profiler;  // the frame's profiling events (empty without timings)
  bool timings = false;
  std::vector<std::uint32_t> stats;  // the frame statistics words
  // host work once the reads completed, in order (statistics, AOV planes)
  std::vector<std::function<void(PendingFrame&)>> finishers;
  // pinned blocks to copy from at completion: block, destination, bytes
  struct Copy {
    PinnedPool::Block block;
    void* dst = nullptr;
    std::size_t bytes = 0;
  };
  std::vector<Copy> copies;
  std::uint64_t waits = 0;  // host waits made while the frame was built and run
  bool complete = false;

  // Enqueues a non-blocking read of `bytes` bytes at byte `offset` of `buffer` into `dst`,
  // directly or through `pinned` (see above).
  void read(Device::Impl& dev, PinnedPool& pinned, const cl::Buffer& buffer, std::size_t offset,
            void* dst, std::size_t bytes);
  // After the last read: the marker the frame completes with.
  void seal(Device::Impl& dev);
  // Waits for the marker (one host wait), copies the pinned blocks, runs the finishers and
  // collects the timings; idempotent.
  void finish(Device::Impl& dev, PinnedPool& pinned);
};

}  // namespace clhair
