// strand_stage.cpp — see strand_stage.h.
#include "stages/strand_stage.h"

#include <algorithm>

#include "clhair/gpu_types.h"

namespace clhair {

StrandStage::StrandStage(Device::Impl& dev)
    : dev_(dev) {}  // every kernel is built on its first use: a frame builds what it runs

// groom, [view], bundles, vertices, lod, offsets, roots: the leading arguments of every
// strands.cl kernel (the raster and opacity kernels take the view second).
void StrandStage::bindGroom(KernelArgs& a, const Inputs& in) {
  const std::uint64_t B = in.bundleCount;
  a.buffer("bundles", *in.bundles, B * sizeof(gpu::ClhBundle))
      .buffer("vertices", *in.vertices, in.vertexTotal * sizeof(gpu::ClhMeshVertex))
      .buffer("LOD records", *in.lod, B * sizeof(gpu::ClhLodRecord))
      .buffer("strand offsets", *in.offsets,
              std::uint64_t(gpu::clh_lod_offsets_length(in.bundleCount)) * sizeof(cl_uint))
      .buffer("quad root set", *in.rootsQuad, in.rootSetSize * 2 * sizeof(float))
      .buffer("triangle root set", *in.rootsTri, in.rootSetSize * 2 * sizeof(float));
}

cl_uint StrandStage::bindRaster(KernelArgs& a, const Inputs& in, const StrandRaster& r) {
  a.buffer("groom", *in.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *r.view, sizeof(gpu::ClhViewGpu));
  bindGroom(a, in);
  a.buffer("scene depth", *r.sceneDepth, r.pixels * sizeof(float))
      .buffer("G-buffer", *r.gbuffer, r.gbufferBytes())
      .buffer("raster counters", *r.counters, 4 * sizeof(cl_uint));
  const cl_uint baseArg = a.next();
  a.value("strand base", 0u).value("strand stride", 0u);
  r.bindExtras(a);
  return baseArg;
}

// the point bases, points, tangents and root coordinates of s, and its point count
void StrandStage::bindStored(KernelArgs& a, const Inputs& in, const StoredStrands& s) {
  a.buffer("stored point bases", s.pointBase, std::uint64_t(in.bundleCount) * sizeof(cl_uint))
      .buffer("stored points", s.points, s.pointCount * 4 * sizeof(float))
      .buffer("stored tangents", s.tangents, s.pointCount * 4 * sizeof(float))
      .buffer("stored root coordinates", s.uvs, std::uint64_t(s.strands) * 2 * sizeof(float))
      .value("stored points", static_cast<cl_ulong>(s.pointCount));
}

void StrandStage::raster(const Inputs& in, const StrandRaster& r, Profiler* profiler) {
  r.check();
  const bool persistent = r.mode == DispatchMode::Persistent && !r.curve && !r.points;
  const std::string key = r.options() + (persistent ? "|1" : "|0");
  auto it = raster_.find(key);
  if (it == raster_.end())
    it = raster_
             .emplace(key, dev_.kernel("strands.cl",
                                       persistent ? "strands_raster_persistent" : "strands_raster",
                                       r.entryOptions(persistent)))
             .first;
  cl::Kernel& k = it->second;
  KernelArgs a(k, r.stage());
  const cl_uint baseArg = bindRaster(a, in, r);
  if (r.strands == 0) return;
  if (persistent)
    dispatchStrandsPersistent(dev_, k, r.stage(), r.strands, baseArg + 1, profiler);
  else
    dispatchStrands(dev_, k, r.stage(), r.strands, baseArg, profiler);
}

void StrandStage::opacity(const Inputs& in, const OpacityDraw& o, std::uint32_t strands,
                          Profiler* profiler) {
  if (!opacity_())
    opacity_ = dev_.kernel("strands.cl", "strands_opacity", "-DCLH_RASTER_OPACITY=1");
  KernelArgs a(opacity_, "shadow");
  a.buffer("groom", *in.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("light view", *o.lightView, sizeof(gpu::ClhViewGpu));
  bindGroom(a, in);
  a.buffer("opaque depth", *o.opaqueDepth, o.texels * sizeof(float))
      .buffer("shadow", *o.shadow, sizeof(gpu::ClhShadowGpu))
      .buffer("hair depth", *o.hairDepth, o.texels * sizeof(float))
      .buffer("opacity", *o.opacity, o.texels * CLH_DOM_LAYERS * sizeof(cl_uint));
  dispatchStrands(dev_, opacity_, "shadow", strands, a.next(), profiler);
}

void StrandStage::rasterViews(const Inputs& in, const StrandRaster& r, const cl::Buffer& viewGrooms,
                              const cl::Buffer& views, std::uint32_t count, Profiler* profiler) {
  auto it = views_.find(r.msaa);
  if (it == views_.end())
    it = views_
             .emplace(r.msaa, dev_.kernel("strands.cl", "strands_raster_views",
                                          "-DCLH_MSAA=" + std::to_string(r.msaa) +
                                              entryOption(CLH_ENTRY_RASTER_VIEWS)))
             .first;
  cl::Kernel& k = it->second;
  const std::uint64_t V = count;
  if (V == 0) throw Error("several views: the strand pass was given no view");
  const std::uint64_t words = r.pixels * static_cast<std::uint64_t>(r.msaa + 1);
  const std::uint64_t depthStride = r.depthStride ? r.depthStride : r.pixels;
  const std::uint64_t gbufferStride = r.gbufferStride ? r.gbufferStride : words;
  if (depthStride < r.pixels || gbufferStride < words)
    throw Error("several views: slices of " + std::to_string(depthStride) + " depths and " +
                std::to_string(gbufferStride) + " words are shorter than a view's " +
                std::to_string(r.pixels) + " pixels and " + std::to_string(words) + " words");
  KernelArgs a(k, "strands");
  a.buffer("groom", *in.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *r.view, sizeof(gpu::ClhViewGpu));
  bindGroom(a, in);
  // the last view's slice ends at its own size: the padding after it need not exist
  a.buffer("scene depth of every view", *r.sceneDepth,
           ((V - 1) * depthStride + r.pixels) * sizeof(float))
      .buffer("G-buffers of every view", *r.gbuffer,
              ((V - 1) * gbufferStride + words) * sizeof(cl_ulong))
      .buffer("raster counters", *r.counters, 4 * sizeof(cl_uint));
  const cl_uint baseArg = a.next();
  a.value("strand base", 0u).value("strand stride", 0u);
  a.buffer("view grooms", viewGrooms, V * sizeof(gpu::ClhGroomGpu))
      .buffer("views", views, V * sizeof(gpu::ClhViewGpu))
      .value("view count", static_cast<cl_uint>(count))
      .value("depth slice stride", static_cast<cl_ulong>(depthStride))
      .value("G-buffer slice stride", static_cast<cl_ulong>(gbufferStride));
  if (r.strands == 0) return;
  dispatchStrands(dev_, k, "strands", r.strands, baseArg, profiler);
}

void StrandStage::motion(const Inputs& in, const cl::Buffer& previous, const MotionDraw& m,
                         const StrandRaster& r, Profiler* profiler) {
  auto it = motion_.find(r.msaa);
  if (it == motion_.end())
    it = motion_
             .emplace(r.msaa, dev_.kernel("strands.cl", "strands_motion",
                                          "-DCLH_MSAA=" + std::to_string(r.msaa) +
                                              " -DCLH_RASTER_MOTION=1"))
             .first;
  cl::Kernel& k = it->second;
  KernelArgs a(k, "motion");
  a.buffer("groom", *in.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *r.view, sizeof(gpu::ClhViewGpu));
  bindGroom(a, in);
  a.buffer("scene depth", *r.sceneDepth, r.pixels * sizeof(float))
      .buffer("G-buffer", *r.gbuffer,
              r.pixels * static_cast<std::uint64_t>(r.msaa + 1) * sizeof(cl_ulong))
      .buffer("raster counters", *r.counters, 4 * sizeof(cl_uint));
  const cl_uint baseArg = a.next();
  a.value("strand base", 0u).value("strand stride", 0u);
  a.buffer("previous vertices", previous, in.vertexTotal * sizeof(gpu::ClhMeshVertex))
      .buffer("motion parameters", *m.params, sizeof(gpu::ClhMotionGpu))
      .buffer("motion", *m.motion, r.pixels * sizeof(cl_ulong));
  if (r.strands == 0) return;
  dispatchStrands(dev_, k, "motion", r.strands, baseArg, profiler);
}

void StrandStage::exportStrands(const Inputs& in, std::uint32_t strands, cl::Buffer& points,
                                cl::Buffer& tangents, cl::Buffer& counts, Profiler* profiler) {
  const std::uint64_t slots = std::uint64_t(strands) * CLH_MAX_CONTROL_POINTS;
  if (!export_())
    export_ = dev_.kernel("strands.cl", "strands_export", entryOption(CLH_ENTRY_EXPORT));
  KernelArgs a(export_, "strands");
  a.buffer("groom", *in.groom, sizeof(gpu::ClhGroomGpu));
  bindGroom(a, in);
  a.buffer("points", points, slots * 4 * sizeof(float))
      .buffer("tangents", tangents, slots * 4 * sizeof(float))
      .buffer("point counts", counts, std::uint64_t(strands) * sizeof(cl_uint));
  const cl_uint baseArg = a.next();
  a.value("strand base", 0u).value("strand capacity", strands);
  dispatchStrands(dev_, export_, "strands", strands, baseArg, profiler);
}

void StrandStage::store(const Inputs& in, StoredStrands& s, Profiler* profiler) {
  if (!store_()) store_ = dev_.kernel("strands.cl", "strands_store", entryOption(CLH_ENTRY_STORE));
  KernelArgs a(store_, "strands");
  a.buffer("groom", *in.groom, sizeof(gpu::ClhGroomGpu));
  bindGroom(a, in);
  bindStored(a, in, s);
  const cl_uint baseArg = a.next();
  a.value("strand base", 0u).value("strand capacity", s.strands);
  if (s.strands == 0) return;
  dispatchStrands(dev_, store_, "strands", s.strands, baseArg, profiler);
}

void StrandStage::rasterStored(const Inputs& in, const StrandRaster& r, const StoredStrands& s,
                               Profiler* profiler, std::uint32_t subset, std::uint32_t pass) {
  r.check();
  auto it = stored_.find(r.options());
  if (it == stored_.end())
    it = stored_
             .emplace(r.options(), dev_.kernel("strands.cl", "strands_raster_stored",
                                               r.options() + entryOption(CLH_ENTRY_RASTER_STORED)))
             .first;
  cl::Kernel& k = it->second;
  KernelArgs a(k, r.stage());
  const cl_uint baseArg = bindRaster(a, in, r);
  bindStored(a, in, s);
  a.value("stored strands", s.strands)
      .value("subset", static_cast<cl_uint>(subset))
      .value("subset pass", static_cast<cl_uint>(pass));
  if (s.strands == 0) return;
  dispatchStrands(dev_, k, r.stage(), s.strands, baseArg, profiler);
}

}  // namespace clhair
