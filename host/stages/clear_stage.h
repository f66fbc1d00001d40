// clear_stage.h — fills a buffer of 64-bit or 32-bit words with one value (kernels/clear.cl):
// the G-buffers are cleared to the empty word before every strand pass, all of them or only a
// box of pixels in each layer (a groom's screen box); counters and bitmaps to zero.
#pragma once

#include "stages/stage_inputs.h"

namespace clhair {

class ClearStage {
 public:
  explicit ClearStage(Device::Impl& dev);
  void words(const cl::Buffer& buffer, std::size_t count, std::uint64_t value,
             const std::string& stage, Profiler* profiler);
  // `count` 32-bit words from the start of `buffer`.
  void uints(const cl::Buffer& buffer, std::size_t count, std::uint32_t value,
             const std::string& stage, Profiler* profiler);
  // `count` 32-bit words from word `srcFirst` of `src` to word `dstFirst` of `dst`.
  void copyUints(const cl::Buffer& src, std::size_t srcFirst, const cl::Buffer& dst,
                 std::size_t dstFirst, std::size_t count, const std::string& stage,
                 Profiler* profiler);
  // The pixels of `box` (clipped to the image) in the first `layers` planes of a width x
  // height image.
  void box(const cl::Buffer& buffer, int width, int height, int layers, const PixelRect& box,
           std::uint64_t value, const std::string& stage, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_, box_, uints_, copy_;
};

}  // namespace clhair
