// opaque_stage.h — binds and launches opaque_render (kernels/opaque.cl): the analytic
// spheres and planes into the target colour and depth, one work-item per pixel.
#pragma once

#include "stages/stage_inputs.h"

namespace clhair {

class OpaqueStage {
 public:
  explicit OpaqueStage(Device::Impl& dev);
  struct Params {
    ViewTarget target;
    LightingInputs lighting;
    const cl::Buffer* spheres = nullptr;  // ClhSphereGpu[sphereCount]
    const cl::Buffer* planes = nullptr;   // ClhPlaneGpu[planeCount]
    std::uint32_t sphereCount = 0, planeCount = 0;
    const cl::Buffer* background = nullptr;  // float4[backgroundTexels] (a placeholder when none)
    std::size_t backgroundTexels = 1;
    cl::Buffer* color = nullptr;  // float4 per pixel
    cl::Buffer* depth = nullptr;  // float per pixel
    bool shade = true;            // false: depth only (a light's view)
  };
  cl::Event enqueue(const Params& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_;
};

}  // namespace clhair
