// shade_stage.cpp — see shade_stage.h.
#include "stages/shade_stage.h"

namespace clhair {

ShadeStage::ShadeStage(Device::Impl& dev) : dev_(dev), kernel_(dev.kernel("shade.cl", "shade_placeholder")) {}

cl::Event ShadeStage::enqueue(const Params& p, Profiler* profiler) {
  kernel_.setArg(0, *p.groom);
  kernel_.setArg(1, *p.view);
  kernel_.setArg(2, *p.scene);
  kernel_.setArg(3, *p.lights);
  kernel_.setArg(4, *p.center);
  kernel_.setArg(5, *p.hair);
  return dispatch(dev_, kernel_, "shade", cl::NDRange(p.width, p.height), cl::NDRange(8, 8), profiler);
}

}  // namespace clhair
