// filter_stage.h — binds and launches filter_reconstruct (kernels/filter.cl): strand
// reconnection, oriented bilateral and alpha from the center and conservative layers
// (Lipp §3.3), one work-item per pixel, into premultiplied RGBA.
#pragma once

#include "stages/dispatch.h"

namespace clhair {

class FilterStage {
 public:
  explicit FilterStage(Device::Impl& dev);
  struct Params {
    const cl::Buffer* groom;
    const cl::Buffer* view;
    const cl::Buffer* filter;   // ClhFilterGpu
    const cl::Buffer* gbuffer;  // 2 layers: center, conservative
    const cl::Buffer* hair;     // shaded center colour, float4 per pixel
    cl::Buffer* out;            // premultiplied RGBA, float4 per pixel
    int width, height;
  };
  cl::Event enqueue(const Params& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_;
};

}  // namespace clhair
