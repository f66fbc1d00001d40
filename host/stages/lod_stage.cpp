// lod_stage.cpp — see lod_stage.h.
#include "stages/lod_stage.h"

#include "clhair/gpu_types.h"

namespace clhair {

LodStage::LodStage(Device::Impl& dev)
    : dev_(dev),
      lod_(dev.kernel("lod.cl", "lod_bundles", "-DSCAN_WG=" + std::to_string(kScanWorkGroup))),
      scan_(dev.kernel("lod.cl", "scan_bundles", "-DSCAN_WG=" + std::to_string(kScanWorkGroup))) {}

void enqueueScan(Device::Impl& dev, cl::Kernel& scan, const cl::Buffer& counts,
                 const cl::Buffer& offsets, std::uint32_t n, Profiler* profiler) {
  KernelArgs(scan, "lod")
      .buffer("counts", counts, std::uint64_t(gpu::clh_lod_counts_length(n)) * sizeof(cl_uint))
      .buffer("offsets", offsets, std::uint64_t(gpu::clh_lod_offsets_length(n)) * sizeof(cl_uint))
      .value("count", static_cast<cl_uint>(n));
  dispatch(dev, scan, "lod", cl::NDRange(LodStage::kScanWorkGroup),
           cl::NDRange(LodStage::kScanWorkGroup), profiler);
}

void LodStage::enqueue(const Params& p, Profiler* profiler) {
  if (p.bundleCount == 0) return;
  const std::uint64_t B = p.bundleCount;
  KernelArgs(lod_, "lod")
      .buffer("groom", *p.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *p.view, sizeof(gpu::ClhViewGpu))
      .buffer("bundles", *p.bundles, B * sizeof(gpu::ClhBundle))
      .buffer("vertices", *p.vertices, p.vertexTotal * sizeof(gpu::ClhMeshVertex))
      .value("reach", p.reach)
      .buffer("LOD records", *p.lod, B * sizeof(gpu::ClhLodRecord))
      .buffer("counts", *p.counts,
              std::uint64_t(gpu::clh_lod_counts_length(p.bundleCount)) * sizeof(cl_uint));
  dispatch(dev_, lod_, "lod", cl::NDRange(p.bundleCount), cl::NDRange(64), profiler);
  enqueueScan(dev_, scan_, *p.counts, *p.offsets, p.bundleCount, profiler);
}

}  // namespace clhair
