// explicit_stage.cpp — see explicit_stage.h.
#include "stages/explicit_stage.h"

#include <algorithm>

#include "cl/cl_error.h"
#include "clhair/error.h"
#include "stages/lod_stage.h"

namespace clhair {

namespace {
const std::string kScanOptions = "-DSCAN_WG=" + std::to_string(LodStage::kScanWorkGroup);
}

ExplicitStage::ExplicitStage(Device::Impl& dev) : dev_(dev) {}

cl::Kernel& ExplicitStage::kernel(const std::string& name, const std::string& file, const std::string& options) {
  const std::string key = name + "|" + options;
  auto it = kernels_.find(key);
  if (it != kernels_.end()) return it->second;
  return kernels_[key] = dev_.kernel(file, name, options);
}

void ExplicitStage::bindTables(cl::Kernel& k, const Inputs& in) {
  k.setArg(0, *in.groom);
  // 1: the view, set by the caller
  k.setArg(2, *in.points);
  k.setArg(3, *in.strandOffsets);
  k.setArg(4, *in.uv);
  k.setArg(5, *in.chunks);
  k.setArg(6, *in.lod);
  k.setArg(7, *in.offsets);
  k.setArg(8, static_cast<cl_uint>(in.strandCount));
  k.setArg(9, static_cast<cl_uint>(in.pointCount));
  k.setArg(10, static_cast<cl_uint>(in.hasUv ? 1 : 0));
}

void ExplicitStage::lod(const Inputs& in, const cl::Buffer& view, Profiler* profiler) {
  if (in.chunkCount == 0) return;
  cl::Kernel& lk = kernel("lod_chunks", "lod.cl", kScanOptions);
  lk.setArg(0, *in.groom);
  lk.setArg(1, view);
  lk.setArg(2, *in.chunkBounds);
  lk.setArg(3, *in.chunks);
  lk.setArg(4, *in.lod);
  lk.setArg(5, *in.counts);
  dispatch(dev_, lk, "lod", cl::NDRange(in.chunkCount), cl::NDRange(64), profiler);
  cl::Kernel& scan = kernel("scan_bundles", "lod.cl", kScanOptions);
  scan.setArg(0, *in.counts);
  scan.setArg(1, *in.offsets);
  scan.setArg(2, static_cast<cl_uint>(in.chunkCount));
  dispatch(dev_, scan, "lod", cl::NDRange(LodStage::kScanWorkGroup), cl::NDRange(LodStage::kScanWorkGroup), profiler);
}

std::uint32_t ExplicitStage::readTotal(const Inputs& in) {
  if (in.chunkCount == 0) return 0;
  std::uint32_t total = 0;
  clCall("lod: reading the explicit strand total", [&] {
    dev_.queue.enqueueReadBuffer(*in.offsets, CL_TRUE, sizeof(std::uint32_t) * in.chunkCount, sizeof(std::uint32_t),
                                 &total);
    return 0;
  });
  return total;
}

void ExplicitStage::raster(const Inputs& in, const StrandStage::Raster& r, Profiler* profiler) {
  if (r.msaa != 1 && r.msaa != 2 && r.msaa != 4 && r.msaa != 8)
    throw Error("MSAA must be 1, 2, 4 or 8 samples, not " + std::to_string(r.msaa));
  const bool persistent = r.mode == DispatchMode::Persistent;
  const std::string opts = "-DCLH_MSAA=" + std::to_string(r.msaa) + (r.stats ? " -DCLH_RASTER_STATS=1" : "");
  cl::Kernel& k = kernel(persistent ? "strands_explicit_raster_persistent" : "strands_explicit_raster",
                         "strands_explicit.cl", opts);
  bindTables(k, in);
  k.setArg(1, *r.view);
  k.setArg(11, *r.sceneDepth);
  k.setArg(12, *r.gbuffer);
  k.setArg(13, *r.counters);
  if (r.strands == 0) return;
  if (persistent) {
    dispatchStrandsPersistent(dev_, k, "strands", r.strands, 14, profiler);
    return;
  }
  dispatchStrands(dev_, k, "strands", r.strands, 14, profiler);
}

void ExplicitStage::opacity(const Inputs& in, const cl::Buffer& lightView, const cl::Buffer& opaqueDepth,
                            const cl::Buffer& shadow, const cl::Buffer& hairDepth, cl::Buffer& opacity,
                            std::uint32_t strands, Profiler* profiler) {
  cl::Kernel& k = kernel("strands_explicit_opacity", "strands_explicit.cl", "-DCLH_RASTER_OPACITY=1");
  bindTables(k, in);
  k.setArg(1, lightView);
  k.setArg(11, opaqueDepth);
  k.setArg(12, shadow);
  k.setArg(13, hairDepth);
  k.setArg(14, opacity);
  dispatchStrands(dev_, k, "shadow", strands, 15, profiler);
}

void ExplicitStage::exportStrands(const Inputs& in, std::uint32_t strands, cl::Buffer& outPoints,
                                  cl::Buffer& outTangents, cl::Buffer& outCounts, Profiler* profiler) {
  cl::Kernel& k = kernel("strands_explicit_export", "strands_explicit.cl", "-DCLH_MSAA=1");  // the raster program
  bindTables(k, in);
  k.setArg(1, *in.groom);  // unused view slot: any buffer
  k.setArg(11, outPoints);
  k.setArg(12, outTangents);
  k.setArg(13, outCounts);
  dispatchStrands(dev_, k, "strands", strands, 14, profiler);
}

}  // namespace clhair
