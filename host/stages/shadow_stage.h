// shadow_stage.h — binds the deep-opacity-map kernels of kernels/shadow.cl: the nearest
// hair depth per texel from a light's 2-layer G-buffer, and the clear of the opacity
// layers. The strand kernels' opacity variants are bound by StrandStage / ExplicitStage;
// ShadowMaps (host/frame/shadow_maps.h) drives the passes per shadowed light.
#pragma once

#include <cstdint>

#include "cl/dispatch.h"

namespace clhair {

class ShadowStage {
 public:
  explicit ShadowStage(Device::Impl& dev);
  // shadow: one ClhShadowGpu (its offset selects the slot); gbuffer: the light's 2-layer
  // G-buffer of res x res texels; hairDepth: all slots (`slotTexels` apart).
  void resolveDepth(const cl::Buffer& shadow, const cl::Buffer& gbuffer, cl::Buffer& hairDepth,
                    int res, std::size_t allTexels, Profiler* profiler);
  void clearOpacity(const cl::Buffer& shadow, cl::Buffer& opacity, std::size_t slotTexels,
                    std::size_t allTexels, Profiler* profiler);
  // The light pass's LOD of one groom instance (its `records` records, counts and scan, in
  // the light's view) capped per bundle by the camera's records, `records` of them from
  // record `cameraAt` of `camera` (lod.cl, lod_cap); `stored`: a strand file (its segments
  // are per strand).
  void capLod(cl::Buffer& lod, cl::Buffer& counts, cl::Buffer& offsets, const cl::Buffer& camera,
              std::uint32_t cameraAt, std::uint32_t records, bool stored, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel resolve_, clear_, cap_;
};

}  // namespace clhair
