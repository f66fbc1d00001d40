// lod_stage.cpp — see lod_stage.h.
#include "stages/lod_stage.h"

#include "cl/cl_error.h"

namespace clhair {

LodStage::LodStage(Device::Impl& dev)
    : dev_(dev),
      lod_(dev.kernel("lod.cl", "lod_bundles", "-DSCAN_WG=" + std::to_string(kScanWorkGroup))),
      scan_(dev.kernel("lod.cl", "scan_bundles", "-DSCAN_WG=" + std::to_string(kScanWorkGroup))) {}

void LodStage::enqueue(const Params& p, Profiler* profiler) {
  if (p.bundleCount == 0) return;
  lod_.setArg(0, *p.groom);
  lod_.setArg(1, *p.view);
  lod_.setArg(2, *p.bundles);
  lod_.setArg(3, *p.vertices);
  lod_.setArg(4, p.reach);
  lod_.setArg(5, *p.lod);
  lod_.setArg(6, *p.counts);
  dispatch(dev_, lod_, "lod", cl::NDRange(p.bundleCount), cl::NDRange(64), profiler);
  scan_.setArg(0, *p.counts);
  scan_.setArg(1, *p.offsets);
  scan_.setArg(2, p.bundleCount);
  dispatch(dev_, scan_, "lod", cl::NDRange(kScanWorkGroup), cl::NDRange(kScanWorkGroup), profiler);
}

std::uint32_t LodStage::readTotal(const Params& p) {
  if (p.bundleCount == 0) return 0;
  std::uint32_t total = 0;
  clCall("lod: reading the strand total", [&] {
    dev_.queue.enqueueReadBuffer(*p.offsets, CL_TRUE, sizeof(std::uint32_t) * p.bundleCount,
                                 sizeof(std::uint32_t), &total);
    return 0;
  });
  return total;
}

}  // namespace clhair
