// buffers.h — creating, filling and reading device buffers with readable errors. Every
// allocation is checked against the device's largest single allocation before the driver
// sees it, so an oversized groom or target fails with the sizes instead of a bare
// CL_INVALID_BUFFER_SIZE. Uploads never block the host (host/cl/transfer.h); a blocking
// read-back is a host wait and is counted as one.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "cl/cl_error.h"
#include "cl/device_impl.h"

namespace clhair {

// A read-write buffer of `count` T (at least one element), filled from `data` when given.
template <typename T>
cl::Buffer makeBuffer(Device::Impl& dev, const std::string& what, std::size_t count,
                      const T* data = nullptr) {
  const std::size_t bytes = std::max<std::size_t>(count, 1) * sizeof(T);
  if (bytes > dev.info.maxAlloc)
    throw Error(what + " needs " + std::to_string(bytes >> 20) + " MiB in one buffer but " +
                dev.info.name + " allows at most " + std::to_string(dev.info.maxAlloc >> 20) +
                " MiB");
  return clCall("allocating " + what, [&] {
    // the initial contents are copied at creation: no command, no wait
    if (data && count > 0)
      return cl::Buffer(dev.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, bytes,
                        const_cast<T*>(data));
    if (dev.zeroNewBuffers) {
      std::vector<unsigned char> zeros(bytes, 0);
      return cl::Buffer(dev.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, bytes, zeros.data());
    }
    return cl::Buffer(dev.context, CL_MEM_READ_WRITE, bytes);
  });
}

// Non-blocking write of `count` T at element `first` of `buffer` (from a staged copy:
// `data` may change at once).
template <typename T>
void upload(Device::Impl& dev, const cl::Buffer& buffer, const T* data, std::size_t count,
            std::size_t first = 0) {
  dev.transfers.upload(dev.queue, buffer, first * sizeof(T), data, count * sizeof(T));
}

// Blocking read of `count` T starting at element `first`: a host wait.
template <typename T>
void readBack(Device::Impl& dev, const std::string& what, const cl::Buffer& buffer, T* out,
              std::size_t count, std::size_t first = 0) {
  if (count == 0) return;
  dev.transfers.countWait();
  clCall("reading " + what, [&] {
    dev.queue.enqueueReadBuffer(buffer, CL_TRUE, first * sizeof(T), count * sizeof(T), out);
    return 0;
  });
}

// Non-blocking read of `count` T starting at element `first` into `out`, which must stay
// valid until the queue has passed this command (a frame's event, Renderer::wait).
template <typename T>
void readBackAsync(Device::Impl& dev, const std::string& what, const cl::Buffer& buffer, T* out,
                   std::size_t count, std::size_t first = 0) {
  if (count == 0) return;
  clCall("reading " + what, [&] {
    dev.queue.enqueueReadBuffer(buffer, CL_FALSE, first * sizeof(T), count * sizeof(T), out);
    return 0;
  });
}

// Non-blocking write of `count` T to the start of `buffer` unless they are the bytes `last`
// holds (what was written there before; the owner of the buffer clears `last` when it
// makes a new buffer): per-frame records that did not change are not uploaded again.
template <typename T>
void uploadChanged(Device::Impl& dev, const cl::Buffer& buffer, std::vector<unsigned char>& last,
                   const T* data, std::size_t count) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(data);
  const std::size_t n = count * sizeof(T);
  if (last.size() == n && std::equal(bytes, bytes + n, last.begin())) return;
  upload(dev, buffer, data, count);
  last.assign(bytes, bytes + n);
}

// A buffer of at least `count` T, reallocated only when the current one is too small
// (buffers that follow the scene's size from frame to frame).
template <typename T>
void ensureCapacity(Device::Impl& dev, cl::Buffer& buffer, std::size_t& capacity,
                    const std::string& what, std::size_t count) {
  count = std::max<std::size_t>(count, 1);
  if (buffer() && capacity >= count) return;
  buffer = makeBuffer<T>(dev, what, count);
  capacity = count;
}

}  // namespace clhair
