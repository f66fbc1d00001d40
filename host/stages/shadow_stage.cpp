// shadow_stage.cpp — see shadow_stage.h.
#include "stages/shadow_stage.h"

#include "clhair/gpu_types.h"
#include "stages/lod_stage.h"

namespace clhair {

ShadowStage::ShadowStage(Device::Impl& dev)
    : dev_(dev) {}  // the kernels are built on their first use: a frame without maps builds none

void ShadowStage::resolveDepth(const cl::Buffer& shadow, const cl::Buffer& gbuffer,
                               cl::Buffer& hairDepth, int res, std::size_t allTexels,
                               Profiler* profiler) {
  const std::uint64_t texels = std::uint64_t(res) * std::uint64_t(res);
  if (!resolve_()) resolve_ = dev_.kernel("shadow.cl", "shadow_resolve_depth");
  KernelArgs(resolve_, "shadow")
      .buffer("shadow", shadow, sizeof(gpu::ClhShadowGpu))
      .buffer("light G-buffer", gbuffer, 2 * texels * sizeof(cl_ulong))
      .buffer("hair depth", hairDepth, allTexels * sizeof(float));
  dispatch(dev_, resolve_, "shadow", cl::NDRange(res, res), cl::NDRange(8, 8), profiler);
}

void ShadowStage::capLod(cl::Buffer& lod, cl::Buffer& counts, cl::Buffer& offsets,
                         const cl::Buffer& camera, std::uint32_t cameraAt, std::uint32_t records,
                         bool stored, Profiler* profiler) {
  if (records == 0) return;
  if (!cap_())
    cap_ =
        dev_.kernel("lod.cl", "lod_cap", "-DSCAN_WG=" + std::to_string(LodStage::kScanWorkGroup));
  const std::uint64_t n = records;
  KernelArgs(cap_, "lod")
      .buffer("LOD records", lod, n * sizeof(gpu::ClhLodRecord))
      .buffer("counts", counts, std::uint64_t(gpu::clh_lod_counts_length(records)) * 4)
      .buffer("offsets", offsets, std::uint64_t(gpu::clh_lod_offsets_length(records)) * 4)
      .buffer("camera LOD records", camera,
              (std::uint64_t(cameraAt) + n) * sizeof(gpu::ClhLodRecord))
      .value("camera record", static_cast<cl_uint>(cameraAt))
      .value("records", static_cast<cl_uint>(records))
      .value("stored", static_cast<cl_uint>(stored ? 1 : 0));
  dispatch(dev_, cap_, "lod", cl::NDRange(LodStage::kScanWorkGroup),
           cl::NDRange(LodStage::kScanWorkGroup), profiler);
}

void ShadowStage::clearOpacity(const cl::Buffer& shadow, cl::Buffer& opacity,
                               std::size_t slotTexels, std::size_t allTexels, Profiler* profiler) {
  if (!clear_()) clear_ = dev_.kernel("shadow.cl", "shadow_clear");
  KernelArgs(clear_, "shadow")
      .buffer("shadow", shadow, sizeof(gpu::ClhShadowGpu))
      .buffer("opacity", opacity, allTexels * CLH_DOM_LAYERS * sizeof(cl_uint));
  dispatch(dev_, clear_, "shadow", cl::NDRange(slotTexels * CLH_DOM_LAYERS), cl::NDRange(256),
           profiler);
}

}  // namespace clhair
