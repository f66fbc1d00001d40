// shade_stage.cpp — see shade_stage.h.
#include "stages/shade_stage.h"

namespace clhair {

ShadeStage::ShadeStage(Device::Impl& dev) : dev_(dev) { kernel(1); }

cl::Kernel& ShadeStage::kernel(int msaa) {
  auto it = kernels_.find(msaa);
  if (it != kernels_.end()) return it->second;
  return kernels_[msaa] = dev_.kernel("shade.cl", "shade_deferred", "-DCLH_MSAA=" + std::to_string(msaa));
}

cl::Event ShadeStage::enqueue(const Params& p, Profiler* profiler) {
  cl::Kernel& k = kernel(p.msaa);
  k.setArg(0, *p.groom);
  k.setArg(1, *p.view);
  k.setArg(2, *p.scene);
  k.setArg(3, *p.lights);
  k.setArg(4, *p.shadows);
  k.setArg(5, *p.shadowOpaque);
  k.setArg(6, *p.shadowHair);
  k.setArg(7, *p.shadowOpacity);
  k.setArg(8, *p.envTexels);
  k.setArg(9, *p.envLevels);
  k.setArg(10, *p.envSh);
  k.setArg(11, *p.gbuffer);
  k.setArg(12, *p.offsets);
  k.setArg(13, *p.hair);
  return dispatch(dev_, k, "shade", cl::NDRange(p.width, p.height), cl::NDRange(8, 8), profiler);
}

}  // namespace clhair
