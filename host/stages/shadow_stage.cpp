// shadow_stage.cpp — see shadow_stage.h.
#include "stages/shadow_stage.h"

#include <algorithm>

#include "clhair/gpu_types.h"

namespace clhair {

ShadowStage::ShadowStage(Device::Impl& dev)
    : dev_(dev),
      resolve_(dev.kernel("shadow.cl", "shadow_resolve_depth")),
      clear_(dev.kernel("shadow.cl", "shadow_clear")),
      opacity_(dev.kernel("strands.cl", "strands_opacity", "-DCLH_RASTER_OPACITY=1")) {}

void ShadowStage::resolveDepth(const cl::Buffer& shadow, const cl::Buffer& gbuffer, cl::Buffer& hairDepth, int width,
                               int height, Profiler* profiler) {
  resolve_.setArg(0, shadow);
  resolve_.setArg(1, gbuffer);
  resolve_.setArg(2, hairDepth);
  dispatch(dev_, resolve_, "shadow", cl::NDRange(width, height), cl::NDRange(8, 8), profiler);
}

void ShadowStage::clearOpacity(const cl::Buffer& shadow, cl::Buffer& opacity, std::size_t texels, Profiler* profiler) {
  clear_.setArg(0, shadow);
  clear_.setArg(1, opacity);
  dispatch(dev_, clear_, "shadow", cl::NDRange(texels * CLH_DOM_LAYERS), cl::NDRange(256), profiler);
}

void ShadowStage::opacity(const StrandStage::Inputs& in, const cl::Buffer& lightView, const cl::Buffer& opaqueDepth,
                          const cl::Buffer& shadow, const cl::Buffer& hairDepth, cl::Buffer& opacity,
                          std::uint32_t strands, Profiler* profiler) {
  opacity_.setArg(0, *in.groom);
  opacity_.setArg(1, lightView);
  opacity_.setArg(2, *in.bundles);
  opacity_.setArg(3, *in.vertices);
  opacity_.setArg(4, *in.lod);
  opacity_.setArg(5, *in.offsets);
  opacity_.setArg(6, *in.rootsQuad);
  opacity_.setArg(7, *in.rootsTri);
  opacity_.setArg(8, opaqueDepth);
  opacity_.setArg(9, shadow);
  opacity_.setArg(10, hairDepth);
  opacity_.setArg(11, opacity);
  dispatchStrands(dev_, opacity_, "shadow", strands, 12, profiler);
}

}  // namespace clhair
