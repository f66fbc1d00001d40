// clear_stage.h — fills a buffer of 64-bit words with one value (kernels/clear.cl): the
// G-buffers are cleared to the empty word before every strand pass.
#pragma once

#include "cl/dispatch.h"

namespace clhair {

class ClearStage {
 public:
  explicit ClearStage(Device::Impl& dev);
  void words(const cl::Buffer& buffer, std::size_t count, std::uint64_t value,
             const std::string& stage, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_;
};

}  // namespace clhair
