// transfer.cpp — see transfer.h.
#include "cl/transfer.h"

#include <cstring>

#include "cl/cl_error.h"

namespace clhair {

namespace {
// Staged bytes beyond which an upload first waits for the oldest block: a host far ahead of
// the device (several frames in flight, each uploading a wind-blown cage) stays bounded.
constexpr std::size_t kMaxStagedBytes = std::size_t(256) << 20;
}  // namespace

void Transfers::reclaim(bool waitOldest) {
  while (!blocks_.empty()) {
    cl::Event& e = blocks_.front().done;
    if (waitOldest) {
      clCall("waiting for a staged upload", [&] { return e.wait(); });
      ++waits_;
      waitOldest = false;
    } else {
      const cl_int status = clCall("reading an upload's status",
                                   [&] { return e.getInfo<CL_EVENT_COMMAND_EXECUTION_STATUS>(); });
      if (status < 0)
        throw Error("an upload to the device failed (status " + std::to_string(status) + ")");
      if (status != CL_COMPLETE) return;
    }
    staged_ -= blocks_.front().bytes.size();
    blocks_.pop_front();
  }
}

void Transfers::upload(cl::CommandQueue& queue, const cl::Buffer& buffer, std::size_t offset,
                       const void* data, std::size_t bytes) {
  if (bytes == 0) return;
  std::lock_guard<std::mutex> lock(mutex_);
  reclaim(false);
  while (!blocks_.empty() && staged_ + bytes > kMaxStagedBytes) reclaim(true);
  std::vector<unsigned char> block(bytes);
  std::memcpy(block.data(), data, bytes);
  cl::Event done;
  clCall("uploading", [&] {
    return queue.enqueueWriteBuffer(buffer, CL_FALSE, offset, bytes, block.data(), nullptr, &done);
  });
  staged_ += bytes;
  blocks_.push_back({std::move(done), std::move(block), buffer});
}

}  // namespace clhair
