// filter_stage.cpp — see filter_stage.h.
#include "stages/filter_stage.h"

namespace clhair {

FilterStage::FilterStage(Device::Impl& dev) : dev_(dev), kernel_(dev.kernel("filter.cl", "filter_reconstruct")) {}

cl::Event FilterStage::enqueue(const Params& p, Profiler* profiler) {
  kernel_.setArg(0, *p.groom);
  kernel_.setArg(1, *p.view);
  kernel_.setArg(2, *p.filter);
  kernel_.setArg(3, *p.gbuffer);
  kernel_.setArg(4, *p.hair);
  kernel_.setArg(5, *p.out);
  return dispatch(dev_, kernel_, "filter", cl::NDRange(p.width, p.height), cl::NDRange(8, 8), profiler);
}

}  // namespace clhair
