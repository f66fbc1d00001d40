// composite_stage.h — binds and launches composite_over (kernels/composite.cl): hair over
// the target colour, hair depth into the target depth for the next groom.
#pragma once

#include <map>

#include "stages/dispatch.h"

namespace clhair {

class CompositeStage {
 public:
  explicit CompositeStage(Device::Impl& dev);
  struct Params {
    const cl::Buffer* groom;
    const cl::Buffer* view;
    const cl::Buffer* hair;
    const cl::Buffer* gbuffer;  // ulong per pixel, msaa + 1 layers
    cl::Buffer* color;
    cl::Buffer* depth;
    int width, height;
    int msaa = 1;
    int depthLayers = 1;  // G-buffer layers whose nearest word is the hair depth
  };
  cl::Event enqueue(const Params& p, Profiler* profiler);

 private:
  cl::Kernel& kernel(int msaa);
  Device::Impl& dev_;
  std::map<int, cl::Kernel> kernels_;
};

}  // namespace clhair
