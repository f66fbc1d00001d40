// explicit_stage.cpp — see explicit_stage.h.
#include "stages/explicit_stage.h"

#include <algorithm>

#include "clhair/gpu_types.h"
#include "stages/lod_stage.h"

namespace clhair {

namespace {
const std::string kScanOptions = "-DSCAN_WG=" + std::to_string(LodStage::kScanWorkGroup);
}

ExplicitStage::ExplicitStage(Device::Impl& dev) : dev_(dev) {}

cl::Kernel& ExplicitStage::kernel(const std::string& name, const std::string& file,
                                  const std::string& options) {
  const std::string key = name + "|" + options;
  auto it = kernels_.find(key);
  if (it != kernels_.end()) return it->second;
  return kernels_[key] = dev_.kernel(file, name, options);
}

KernelArgs ExplicitStage::bindTables(cl::Kernel& k, const Inputs& in, const cl::Buffer& view,
                                     const std::string& stage, std::uint64_t viewBytes) {
  const std::uint64_t K = in.chunkCount, S = in.strandCount;
  KernelArgs a(k, stage);
  a.buffer("groom", *in.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", view, viewBytes)
      .buffer("points", *in.points, in.pointWords * 4 * sizeof(float))
      .buffer("strand offsets", *in.strandOffsets, (S + 1) * sizeof(cl_uint))
      .buffer("root uv", *in.uv, (in.hasUv ? S : 1) * sizeof(cl_uint))
      .buffer("chunks", *in.chunks, K * 4 * sizeof(cl_uint))
      .buffer("LOD records", *in.lod, K * sizeof(gpu::ClhLodRecord))
      .buffer("chunk offsets", *in.offsets,
              std::uint64_t(gpu::clh_lod_offsets_length(in.chunkCount)) * sizeof(cl_uint))
      .value("strand count", static_cast<cl_uint>(in.strandCount))
      .value("point count", static_cast<cl_uint>(in.pointCount))
      .value("has uv", static_cast<cl_uint>(in.hasUv ? 1 : 0))
      .buffer("children", *in.kids, sizeof(gpu::ClhChildrenGpu))
      .buffer("guide neighbours", *in.neighbours, in.neighbourWords * sizeof(cl_uint));
  return a;
}

void ExplicitStage::lod(const Inputs& in, const cl::Buffer& view, Profiler* profiler) {
  if (in.chunkCount == 0) return;
  const std::uint64_t K = in.chunkCount;
  cl::Kernel& lk = kernel("lod_chunks", "lod.cl", kScanOptions);
  KernelArgs(lk, "lod")
      .buffer("groom", *in.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", view, sizeof(gpu::ClhViewGpu))
      .buffer("chunk bounds", *in.chunkBounds, 2 * K * 4 * sizeof(float))
      .buffer("chunks", *in.chunks, K * 4 * sizeof(cl_uint))
      .buffer("strand offsets", *in.strandOffsets,
              (std::uint64_t(in.strandCount) + 1) * sizeof(cl_uint))
      .value("strand count", static_cast<cl_uint>(in.strandCount))
      .value("point count", static_cast<cl_uint>(in.pointCount))
      .buffer("LOD records", *in.lod, K * sizeof(gpu::ClhLodRecord))
      .buffer("counts", *in.counts,
              std::uint64_t(gpu::clh_lod_counts_length(in.chunkCount)) * sizeof(cl_uint));
  dispatch(dev_, lk, "lod", cl::NDRange(in.chunkCount), cl::NDRange(64), profiler);
  enqueueScan(dev_, kernel("scan_bundles", "lod.cl", kScanOptions), *in.counts, *in.offsets,
              in.chunkCount, profiler);
}

void ExplicitStage::motion(const Inputs& in, const cl::Buffer& previous, const MotionDraw& m,
                           const StrandRaster& r, Profiler* profiler) {
  cl::Kernel& k = kernel("strands_explicit_motion", "strands_explicit.cl",
                         "-DCLH_MSAA=" + std::to_string(r.msaa) + " -DCLH_RASTER_MOTION=1");
  KernelArgs a = bindTables(k, in, *r.view, "motion", sizeof(gpu::ClhViewGpu));
  a.buffer("scene depth", *r.sceneDepth, r.pixels * sizeof(float))
      .buffer("G-buffer", *r.gbuffer,
              r.pixels * static_cast<std::uint64_t>(r.msaa + 1) * sizeof(cl_ulong))
      .buffer("previous points", previous, std::uint64_t(in.pointCount) * 4 * sizeof(float))
      .buffer("motion parameters", *m.params, sizeof(gpu::ClhMotionGpu))
      .buffer("motion", *m.motion, r.pixels * sizeof(cl_ulong));
  const cl_uint last = a.next();
  if (r.strands == 0) return;
  dispatchStrands(dev_, k, "motion", r.strands, last, profiler);
}

void ExplicitStage::raster(const Inputs& in, const StrandRaster& r, Profiler* profiler) {
  r.check();
  const bool persistent = r.mode == DispatchMode::Persistent && !r.curve && !r.points;
  cl::Kernel& k =
      kernel(persistent ? "strands_explicit_raster_persistent" : "strands_explicit_raster",
             "strands_explicit.cl", r.entryOptions(persistent));
  KernelArgs a = bindTables(k, in, *r.view, r.stage(), sizeof(gpu::ClhViewGpu));
  a.buffer("scene depth", *r.sceneDepth, r.pixels * sizeof(float))
      .buffer("G-buffer", *r.gbuffer, r.gbufferBytes())
      .buffer("raster counters", *r.counters, 4 * sizeof(cl_uint));
  // the first strand of a chunked launch, or the persistent grid's size
  const cl_uint last = a.next();
  a.value("strand base", 0u);
  r.bindExtras(a);
  if (r.strands == 0) return;
  if (persistent)
    dispatchStrandsPersistent(dev_, k, r.stage(), r.strands, last, profiler);
  else
    dispatchStrands(dev_, k, r.stage(), r.strands, last, profiler);
}

void ExplicitStage::opacity(const Inputs& in, const OpacityDraw& o, std::uint32_t strands,
                            Profiler* profiler) {
  cl::Kernel& k =
      kernel("strands_explicit_opacity", "strands_explicit.cl", "-DCLH_RASTER_OPACITY=1");
  KernelArgs a = bindTables(k, in, *o.lightView, "shadow", sizeof(gpu::ClhViewGpu));
  a.buffer("opaque depth", *o.opaqueDepth, o.texels * sizeof(float))
      .buffer("shadow", *o.shadow, sizeof(gpu::ClhShadowGpu))
      .buffer("hair depth", *o.hairDepth, o.texels * sizeof(float))
      .buffer("opacity", *o.opacity, o.texels * CLH_DOM_LAYERS * sizeof(cl_uint));
  dispatchStrands(dev_, k, "shadow", strands, a.next(), profiler);
}

void ExplicitStage::exportStrands(const Inputs& in, std::uint32_t strands, cl::Buffer& outPoints,
                                  cl::Buffer& outTangents, cl::Buffer& outCounts,
                                  Profiler* profiler) {
  cl::Kernel& k =
      kernel("strands_explicit_export", "strands_explicit.cl", entryOption(CLH_ENTRY_EXPORT));
  // the kernel reads no view: the groom record fills the slot
  KernelArgs a = bindTables(k, in, *in.groom, "strands", sizeof(gpu::ClhGroomGpu));
  const std::uint64_t copies = std::uint64_t(in.children) + 1;
  a.buffer("points out", outPoints, copies * in.pointCount * 4 * sizeof(float))
      .buffer("tangents out", outTangents, copies * in.pointCount * 4 * sizeof(float))
      .buffer("point counts out", outCounts, copies * in.strandCount * sizeof(cl_uint));
  dispatchStrands(dev_, k, "strands", strands, a.next(), profiler);
}

}  // namespace clhair
