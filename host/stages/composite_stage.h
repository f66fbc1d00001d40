// composite_stage.h — binds and launches composite_over (kernels/composite.cl): hair over
// the target colour, hair depth into the target depth for the next groom.
#pragma once

#include <map>

#include "stages/stage_inputs.h"

namespace clhair {

class CompositeStage {
 public:
  explicit CompositeStage(Device::Impl& dev);
  struct Params {
    ViewTarget target;
    const cl::Buffer* groom = nullptr;    // ClhGroomGpu
    const cl::Buffer* hair = nullptr;     // premultiplied hair RGBA, float4 per pixel
    const cl::Buffer* gbuffer = nullptr;  // ulong per pixel, msaa + 1 layers
    cl::Buffer* color = nullptr;          // float4 per pixel
    cl::Buffer* depth = nullptr;          // float per pixel
    int msaa = 1;
    int depthLayers = 1;  // G-buffer layers whose nearest word is the hair depth
    // Where the hair may be non-transparent (the default: the whole target); outside it
    // `hair` is not read, so it may hold anything there.
    PixelRect box;
  };
  cl::Event enqueue(const Params& p, Profiler* profiler);

 private:
  cl::Kernel& kernel(int msaa);
  Device::Impl& dev_;
  std::map<int, cl::Kernel> kernels_;
};

}  // namespace clhair
