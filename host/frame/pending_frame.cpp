// pending_frame.cpp — see pending_frame.h.
#include "frame/pending_frame.h"

#include <cstring>

#include "cl/buffers.h"

namespace clhair {

PinnedPool::~PinnedPool() {
  for (Block& b : free_) {
    try {
      dev_.queue.enqueueUnmapMemObject(b.buffer, b.host);
    } catch (...) {  // destructors never throw; the buffer goes with the context
    }
  }
  try {
    if (!free_.empty()) dev_.queue.finish();
  } catch (...) {
  }
}

PinnedPool::Block PinnedPool::acquire(std::size_t bytes) {
  for (std::size_t i = 0; i < free_.size(); ++i)
    if (free_[i].bytes >= bytes) {
      Block b = std::move(free_[i]);
      free_.erase(free_.begin() + static_cast<std::ptrdiff_t>(i));
      return b;
    }
  Block b;
  b.bytes = std::max<std::size_t>(bytes, 1);
  if (b.bytes > dev_.info.maxAlloc)
    throw Error("a read-back of " + std::to_string(b.bytes >> 20) + " MiB exceeds " +
                dev_.info.name + "'s largest allocation");
  clCall("allocating pinned read-back memory", [&] {
    b.buffer = cl::Buffer(dev_.context, CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR, b.bytes);
    // mapped once, for the block's whole life, without waiting: the queue is in order, so
    // the map completes before any read enqueued after it writes into the block
    b.host =
        dev_.queue.enqueueMapBuffer(b.buffer, CL_FALSE, CL_MAP_READ | CL_MAP_WRITE, 0, b.bytes);
    return 0;
  });
  return b;
}

void PinnedPool::release(Block b) { free_.push_back(std::move(b)); }

void PendingFrame::read(Device::Impl& dev, PinnedPool& pinned, const cl::Buffer& buffer,
                        std::size_t offset, void* dst, std::size_t bytes) {
  if (bytes == 0) return;
  if (dev.info.hostUnified && !dev.pinnedReadBack) {
    clCall("reading the frame back",
           [&] { return dev.queue.enqueueReadBuffer(buffer, CL_FALSE, offset, bytes, dst); });
    return;
  }
  Copy c;
  c.block = pinned.acquire(bytes);
  c.dst = dst;
  c.bytes = bytes;
  clCall("reading the frame back", [&] {
    return dev.queue.enqueueReadBuffer(buffer, CL_FALSE, offset, bytes, c.block.host);
  });
  copies.push_back(std::move(c));
}

void PendingFrame::seal(Device::Impl& dev) {
  clCall("marking the frame's end",
         [&] { return dev.queue.enqueueMarkerWithWaitList(nullptr, &done); });
  clCall("submitting the frame", [&] { return dev.queue.flush(); });
}

void PendingFrame::finish(Device::Impl& dev, PinnedPool& pinned) {
  if (complete) return;
  dev.transfers.countWait();
  clCall("waiting for the frame", [&] { return done.wait(); });
  ++waits;
  for (Copy& c : copies) {
    std::memcpy(c.dst, c.block.host, c.bytes);
    pinned.release(std::move(c.block));
  }
  copies.clear();
  for (auto& f : finishers) f(*this);
  finishers.clear();
  if (timings && !frames.empty()) frames[0].timings = profiler.collect();
  complete = true;
}

}  // namespace clhair
