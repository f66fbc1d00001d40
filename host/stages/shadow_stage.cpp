// shadow_stage.cpp — see shadow_stage.h.
#include "stages/shadow_stage.h"

#include "clhair/gpu_types.h"

namespace clhair {

ShadowStage::ShadowStage(Device::Impl& dev)
    : dev_(dev),
      resolve_(dev.kernel("shadow.cl", "shadow_resolve_depth")),
      clear_(dev.kernel("shadow.cl", "shadow_clear")) {}

void ShadowStage::resolveDepth(const cl::Buffer& shadow, const cl::Buffer& gbuffer,
                               cl::Buffer& hairDepth, int res, std::size_t allTexels,
                               Profiler* profiler) {
  const std::uint64_t texels = std::uint64_t(res) * std::uint64_t(res);
  KernelArgs(resolve_, "shadow")
      .buffer("shadow", shadow, sizeof(gpu::ClhShadowGpu))
      .buffer("light G-buffer", gbuffer, 2 * texels * sizeof(cl_ulong))
      .buffer("hair depth", hairDepth, allTexels * sizeof(float));
  dispatch(dev_, resolve_, "shadow", cl::NDRange(res, res), cl::NDRange(8, 8), profiler);
}

void ShadowStage::clearOpacity(const cl::Buffer& shadow, cl::Buffer& opacity,
                               std::size_t slotTexels, std::size_t allTexels, Profiler* profiler) {
  KernelArgs(clear_, "shadow")
      .buffer("shadow", shadow, sizeof(gpu::ClhShadowGpu))
      .buffer("opacity", opacity, allTexels * CLH_DOM_LAYERS * sizeof(cl_uint));
  dispatch(dev_, clear_, "shadow", cl::NDRange(slotTexels * CLH_DOM_LAYERS), cl::NDRange(256),
           profiler);
}

}  // namespace clhair
