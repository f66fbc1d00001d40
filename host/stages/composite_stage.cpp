// composite_stage.cpp — see composite_stage.h.
#include "stages/composite_stage.h"

namespace clhair {

CompositeStage::CompositeStage(Device::Impl& dev) : dev_(dev), kernel_(dev.kernel("composite.cl", "composite_over")) {}

cl::Event CompositeStage::enqueue(const Params& p, Profiler* profiler) {
  kernel_.setArg(0, *p.groom);
  kernel_.setArg(1, *p.view);
  kernel_.setArg(2, *p.hair);
  kernel_.setArg(3, *p.center);
  kernel_.setArg(4, *p.color);
  kernel_.setArg(5, *p.depth);
  return dispatch(dev_, kernel_, "composite", cl::NDRange(p.width, p.height), cl::NDRange(8, 8), profiler);
}

}  // namespace clhair
