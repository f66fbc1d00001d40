// render_target.h — the buffers sized to the output that outlive a frame: colour and depth of
// the opaque scene (the hair is composited into them), the G-buffer (MSAA sample layers plus
// the conservative layer), the raster counters and the camera's view record (each groom's
// shaded and filtered hair are the frame graph's own buffers); plus the clear of the
// G-buffer before each groom's strand pass (the layers a groom uses: the samples, the
// conservative layer and, when asked, the identity and hair linking layers), bounded to the
// screen box of the groom before. Buffers are reallocated only when the size or sample count
// changes.
#pragma once

#include <vector>

#include "cl/dispatch.h"
#include "stages/clear_stage.h"
#include "stages/stage_inputs.h"

namespace clhair {

class RenderTarget {
 public:
  explicit RenderTarget(Device::Impl& dev);
  // Checks the size (1..kMaxImageSide per side) and sample count (1, 2, 4, 8).
  void ensure(int width, int height, int msaa);
  // At least `layers` G-buffer layers (the identity and hair linking layers follow the
  // conservative one, gpu_types.h); clearGBuffer then clears the first `layers`.
  void useLayers(int layers);
  // Makes the used layers empty for a groom that writes only inside `box` (its screen box;
  // the default box: anywhere). Only what may hold words is cleared: the box of the groom
  // before, in every layer known empty outside it, or the whole of the used layers when
  // that box was the whole image or more layers are used than are known empty (new
  // buffers, a groom with linking layers after one without). `box` is remembered for the
  // next groom; a caller writing elsewhere (a given G-buffer) passes the default box.
  void clearGBuffer(const PixelRect& box, Profiler* profiler);
  // Fills `count` words of `buffer` with the empty G-buffer word.
  void clearWords(const cl::Buffer& buffer, std::size_t count, Profiler* profiler);
  // `count` 32-bit words of `buffer` set to 0 (counters).
  void clearUints(const cl::Buffer& buffer, std::size_t count, Profiler* profiler);
  // `count` 32-bit words of `src` from word `srcFirst` into `dst` from word `dstFirst`.
  void copyUints(const cl::Buffer& src, std::size_t srcFirst, const cl::Buffer& dst,
                 std::size_t dstFirst, std::size_t count, Profiler* profiler);
  int usedLayers() const { return used_; }

  ViewTarget viewTarget() const { return {&view, width_, height_}; }
  std::size_t pixels() const {
    return static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  }
  int layers() const { return layers_; }

  cl::Buffer view;                      // ClhViewGpu of the camera
  std::vector<unsigned char> viewSent;  // what `view` holds
  cl::Buffer color, depth;              // float4, float per pixel
  cl::Buffer hair, filtered;            // float4 per pixel
  cl::Buffer gbuffer;                   // ulong per pixel and layer
  cl::Buffer stats;                     // uint[4] raster counters
  cl::Buffer motionParams;              // one ClhMotionGpu

 private:
  Device::Impl& dev_;
  ClearStage clear_;
  int width_ = 0, height_ = 0, layers_ = 0, used_ = 0, msaa_ = 1;
  // outside dirty_ the first cleanLayers_ G-buffer layers hold the empty word
  PixelRect dirty_;
  int cleanLayers_ = 0;
};

}  // namespace clhair
