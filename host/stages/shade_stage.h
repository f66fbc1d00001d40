// shade_stage.h — binds and launches the deferred shading pass (kernels/shade.cl) over the
// center G-buffer, one work-item per pixel, into premultiplied hair RGBA.
#pragma once

#include <map>

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
    const cl::Buffer* shadows;  // ClhShadowGpu[CLH_MAX_SHADOWS]
    const cl::Buffer* shadowOpaque, *shadowHair, *shadowOpacity;
    const cl::Buffer* envTexels, *envLevels, *envSh;  // environment (dummies when none)
    const cl::Buffer* gbuffer;  // ulong per pixel, msaa + 1 layers
    const cl::Buffer* offsets;  // the groom's strand offsets (its total drawn at [bundles])
    cl::Buffer* hair;          // float4 per pixel
    int width, height;
    int msaa = 1;
  };
  cl::Event enqueue(const Params& p, Profiler* profiler);

 private:
  cl::Kernel& kernel(int msaa);
  Device::Impl& dev_;
  std::map<int, cl::Kernel> kernels_;
};

}  // namespace clhair
