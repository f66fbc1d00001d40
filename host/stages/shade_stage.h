// shade_stage.h — binds and launches the deferred shading pass (kernels/shade.cl) over the
// center G-buffer, one work-item per pixel, into premultiplied hair RGBA.
#pragma once

#include "stages/dispatch.h"

namespace clhair {

class ShadeStage {
 public:
  explicit ShadeStage(Device::Impl& dev);
  struct Params {
    const cl::Buffer* groom;
    const cl::Buffer* view;
    const cl::Buffer* scene;
    const cl::Buffer* lights;
    const cl::Buffer* center;  // ulong per pixel
    cl::Buffer* hair;          // float4 per pixel
    int width, height;
  };
  cl::Event enqueue(const Params& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_;
};

}  // namespace clhair
