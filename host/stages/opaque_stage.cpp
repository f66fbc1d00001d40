// opaque_stage.cpp — see opaque_stage.h.
#include "stages/opaque_stage.h"

namespace clhair {

OpaqueStage::OpaqueStage(Device::Impl& dev) : dev_(dev), kernel_(dev.kernel("opaque.cl", "opaque_render")) {}

cl::Event OpaqueStage::enqueue(const Params& p, Profiler* profiler) {
  kernel_.setArg(0, *p.scene);
  kernel_.setArg(1, *p.view);
  kernel_.setArg(2, *p.spheres);
  kernel_.setArg(3, *p.planes);
  kernel_.setArg(4, *p.lights);
  kernel_.setArg(5, *p.shadows);
  kernel_.setArg(6, *p.shadowOpaque);
  kernel_.setArg(7, *p.shadowHair);
  kernel_.setArg(8, *p.shadowOpacity);
  kernel_.setArg(9, *p.envTexels);
  kernel_.setArg(10, *p.envLevels);
  kernel_.setArg(11, *p.envSh);
  kernel_.setArg(12, *p.background);
  kernel_.setArg(13, *p.color);
  kernel_.setArg(14, *p.depth);
  kernel_.setArg(15, static_cast<cl_uint>(p.shade ? 1 : 0));
  return dispatch(dev_, kernel_, "opaque", cl::NDRange(p.width, p.height), cl::NDRange(8, 8), profiler);
}

}  // namespace clhair
