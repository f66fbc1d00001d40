// opaque_stage.h — binds and launches opaque_render (kernels/opaque.cl): the analytic
// spheres and planes into the target colour and depth, one work-item per pixel.
#pragma once

#include "stages/dispatch.h"

namespace clhair {

class OpaqueStage {
 public:
  explicit OpaqueStage(Device::Impl& dev);
  struct Params {
    const cl::Buffer* scene;    // ClhSceneGpu
    const cl::Buffer* view;     // ClhViewGpu
    const cl::Buffer* spheres;  // ClhSphereGpu[]
    const cl::Buffer* planes;   // ClhPlaneGpu[]
    const cl::Buffer* lights;   // ClhLightGpu[]
    const cl::Buffer* shadows;  // ClhShadowGpu[CLH_MAX_SHADOWS]
    const cl::Buffer* shadowOpaque, *shadowHair, *shadowOpacity;  // deep opacity maps
    const cl::Buffer* envTexels, *envLevels, *envSh;  // environment (dummies when none)
    const cl::Buffer* background;  // float4 texels of the background image (dummy when none)
    cl::Buffer* color;          // float4 per pixel
    cl::Buffer* depth;          // float per pixel
    int width, height;
    bool shade = true;          // false: depth only (a light's view)
  };
  cl::Event enqueue(const Params& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_;
};

}  // namespace clhair
