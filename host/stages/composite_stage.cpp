// composite_stage.cpp — see composite_stage.h.
#include "stages/composite_stage.h"

namespace clhair {

CompositeStage::CompositeStage(Device::Impl& dev) : dev_(dev) { kernel(1); }

cl::Kernel& CompositeStage::kernel(int msaa) {
  auto it = kernels_.find(msaa);
  if (it != kernels_.end()) return it->second;
  return kernels_[msaa] = dev_.kernel("composite.cl", "composite_over", "-DCLH_MSAA=" + std::to_string(msaa));
}

cl::Event CompositeStage::enqueue(const Params& p, Profiler* profiler) {
  cl::Kernel& k = kernel(p.msaa);
  k.setArg(0, *p.groom);
  k.setArg(1, *p.view);
  k.setArg(2, *p.hair);
  k.setArg(3, *p.gbuffer);
  k.setArg(4, *p.color);
  k.setArg(5, *p.depth);
  k.setArg(6, static_cast<cl_uint>(p.depthLayers));
  return dispatch(dev_, k, "composite", cl::NDRange(p.width, p.height), cl::NDRange(8, 8), profiler);
}

}  // namespace clhair
