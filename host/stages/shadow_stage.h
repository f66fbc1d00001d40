// shadow_stage.h — binds the deep-opacity-map kernels (kernels/shadow.cl and the
// opacity variant of kernels/strands.cl). The renderer drives the passes per shadowed
// light: the light's view of the opaque scene and of the hair (strands_raster) give the
// depth maps, shadow_resolve_depth keeps the nearest hair depth, strands_opacity fills the
// opacity layers.
#pragma once

#include <cstdint>

#include "stages/dispatch.h"
#include "stages/strand_stage.h"

namespace clhair {

class ShadowStage {
 public:
  explicit ShadowStage(Device::Impl& dev);
  // shadow: one ClhShadowGpu; gbuffer: the light's 2-layer G-buffer
  void resolveDepth(const cl::Buffer& shadow, const cl::Buffer& gbuffer, cl::Buffer& hairDepth, int width, int height,
                    Profiler* profiler);
  void clearOpacity(const cl::Buffer& shadow, cl::Buffer& opacity, std::size_t texels, Profiler* profiler);
  void opacity(const StrandStage::Inputs& in, const cl::Buffer& lightView, const cl::Buffer& opaqueDepth,
               const cl::Buffer& shadow, const cl::Buffer& hairDepth, cl::Buffer& opacity, std::uint32_t strands,
               Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel resolve_, clear_, opacity_;
};

}  // namespace clhair
