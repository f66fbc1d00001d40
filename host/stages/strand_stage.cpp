// strand_stage.cpp — see strand_stage.h.
#include "stages/strand_stage.h"

#include <algorithm>

namespace clhair {

StrandStage::StrandStage(Device::Impl& dev)
    : dev_(dev),
      raster_(dev.kernel("strands.cl", "strands_raster")),
      export_(dev.kernel("strands.cl", "strands_export")) {}

void StrandStage::raster(const Inputs& in, const cl::Buffer& view, const cl::Buffer& sceneDepth,
                         cl::Buffer& center, Profiler* profiler) {
  raster_.setArg(0, *in.groom);
  raster_.setArg(1, view);
  raster_.setArg(2, *in.bundles);
  raster_.setArg(3, *in.vertices);
  raster_.setArg(4, *in.lod);
  raster_.setArg(5, *in.offsets);
  raster_.setArg(6, *in.rootsQuad);
  raster_.setArg(7, *in.rootsTri);
  raster_.setArg(8, sceneDepth);
  raster_.setArg(9, center);
  for (std::uint32_t base = 0; base < in.strands; base += kMaxGroupsPerDispatch) {
    std::uint32_t groups = std::min(kMaxGroupsPerDispatch, in.strands - base);
    raster_.setArg(10, base);
    dispatch(dev_, raster_, "strands", cl::NDRange(std::size_t(groups) * kLanes), cl::NDRange(kLanes), profiler);
  }
}

void StrandStage::exportStrands(const Inputs& in, cl::Buffer& points, cl::Buffer& tangents,
                                cl::Buffer& counts, Profiler* profiler) {
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
  export_.setArg(11, in.strands);
  for (std::uint32_t base = 0; base < in.strands; base += kMaxGroupsPerDispatch) {
    std::uint32_t groups = std::min(kMaxGroupsPerDispatch, in.strands - base);
    export_.setArg(10, base);
    dispatch(dev_, export_, "strands", cl::NDRange(std::size_t(groups) * kLanes), cl::NDRange(kLanes), profiler);
  }
}

}  // namespace clhair
