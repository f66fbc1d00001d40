// strand_stage.cpp — see strand_stage.h.
#include "stages/strand_stage.h"

#include <algorithm>

#include "clhair/error.h"

namespace clhair {

StrandStage::StrandStage(Device::Impl& dev)
    : dev_(dev), export_(dev.kernel("strands.cl", "strands_export")) {
  rasterKernel(1, false, false);  // build the common variant up front
}

cl::Kernel& StrandStage::rasterKernel(int msaa, bool stats, bool persistent) {
  int key = msaa * 4 + (stats ? 2 : 0) + (persistent ? 1 : 0);
  auto it = raster_.find(key);
  if (it != raster_.end()) return it->second;
  std::string opts = "-DCLH_MSAA=" + std::to_string(msaa) + (stats ? " -DCLH_RASTER_STATS=1" : "");
  return raster_[key] = dev_.kernel("strands.cl", persistent ? "strands_raster_persistent" : "strands_raster", opts);
}

void StrandStage::raster(const Inputs& in, const Raster& r, Profiler* profiler) {
  if (r.msaa != 1 && r.msaa != 2 && r.msaa != 4 && r.msaa != 8)
    throw Error("MSAA must be 1, 2, 4 or 8 samples, not " + std::to_string(r.msaa));
  cl::Kernel& k = rasterKernel(r.msaa, r.stats, r.mode == DispatchMode::Persistent);
  k.setArg(0, *in.groom);
  k.setArg(1, *r.view);
  k.setArg(2, *in.bundles);
  k.setArg(3, *in.vertices);
  k.setArg(4, *in.lod);
  k.setArg(5, *in.offsets);
  k.setArg(6, *in.rootsQuad);
  k.setArg(7, *in.rootsTri);
  k.setArg(8, *r.sceneDepth);
  k.setArg(9, *r.gbuffer);
  k.setArg(10, *r.counters);
  if (r.strands == 0) return;
  if (r.mode == DispatchMode::Persistent) {
    k.setArg(11, 0u);
    dispatchStrandsPersistent(dev_, k, "strands", r.strands, 12, profiler);
    return;
  }
  k.setArg(12, 0u);
  dispatchStrands(dev_, k, "strands", r.strands, 11, profiler);
}

void StrandStage::exportStrands(const Inputs& in, std::uint32_t strands, cl::Buffer& points,
                                cl::Buffer& tangents, cl::Buffer& counts, Profiler* profiler) {
  export_.setArg(0, *in.groom);
  export_.setArg(1, *in.bundles);
  export_.setArg(2, *in.vertices);
  export_.setArg(3, *in.lod);
  export_.setArg(4, *in.offsets);
  export_.setArg(5, *in.rootsQuad);
  export_.setArg(6, *in.rootsTri);
  export_.setArg(7, points);
  export_.setArg(8, tangents);
  export_.setArg(9, counts);
  export_.setArg(11, strands);
  dispatchStrands(dev_, export_, "strands", strands, 10, profiler);
}

}  // namespace clhair
