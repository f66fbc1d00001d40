// buffers.h — creating, filling and reading device buffers with readable errors. Every
// allocation is checked against the device's largest single allocation before the driver
// sees it, so an oversized groom or target fails with the sizes instead of a bare
// CL_INVALID_BUFFER_SIZE.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>

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
    cl::Buffer b(dev.context, CL_MEM_READ_WRITE, bytes);
    if (data && count > 0) dev.queue.enqueueWriteBuffer(b, CL_TRUE, 0, count * sizeof(T), data);
    return b;
  });
}

// Blocking write of `count` T at the start of `buffer`.
template <typename T>
void upload(Device::Impl& dev, const cl::Buffer& buffer, const T* data, std::size_t count) {
  if (count == 0) return;
  clCall("uploading", [&] {
    dev.queue.enqueueWriteBuffer(buffer, CL_TRUE, 0, count * sizeof(T), data);
    return 0;
  });
}

// Blocking read of `count` T starting at element `first`.
template <typename T>
void readBack(Device::Impl& dev, const std::string& what, const cl::Buffer& buffer, T* out,
              std::size_t count, std::size_t first = 0) {
  if (count == 0) return;
  clCall("reading " + what, [&] {
    dev.queue.enqueueReadBuffer(buffer, CL_TRUE, first * sizeof(T), count * sizeof(T), out);
    return 0;
  });
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
