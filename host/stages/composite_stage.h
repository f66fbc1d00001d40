// composite_stage.h — binds and launches composite_over (kernels/composite.cl): hair over
// the target colour, hair depth into the target depth for the next groom.
#pragma once

#include "stages/dispatch.h"

namespace clhair {

class CompositeStage {
 public:
  explicit CompositeStage(Device::Impl& dev);
  struct Params {
    const cl::Buffer* groom;
    const cl::Buffer* view;
    const cl::Buffer* hair;
    const cl::Buffer* center;
    cl::Buffer* color;
    cl::Buffer* depth;
    int width, height;
  };
  cl::Event enqueue(const Params& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_;
};

}  // namespace clhair
