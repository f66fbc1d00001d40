// clear_stage.h — fills a buffer of 64-bit words with one value (kernels/clear.cl): the
// G-buffers are cleared to the empty word before every strand pass, all of them or only a
// box of pixels in each layer (a groom's screen box).
#pragma once

#include "stages/stage_inputs.h"

namespace clhair {

class ClearStage {
 public:
  explicit ClearStage(Device::Impl& dev);
  void words(const cl::Buffer& buffer, std::size_t count, std::uint64_t value,
             const std::string& stage, Profiler* profiler);
  // The pixels of `box` (clipped to the image) in the first `layers` planes of a width x
  // height image.
  void box(const cl::Buffer& buffer, int width, int height, int layers, const PixelRect& box,
           std::uint64_t value, const std::string& stage, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_, box_;
};

}  // namespace clhair
