// aov_stage.cpp — see aov_stage.h.
#include "stages/aov_stage.h"

#include "clhair/gpu_types.h"

namespace clhair {

namespace {
constexpr std::size_t kGroup = 64;

// The planes, in the order both kernels take them.
void bindPlanes(KernelArgs& a, std::uint64_t n, const AovStage::Planes& p) {
  a.buffer("last depth", *p.lastDepth, n * 4)
      .buffer("owner", *p.owner, n * 4)
      .buffer("owner motion", *p.ownerMotion, n * 8)
      .buffer("hair alpha", *p.alpha, n * 4)
      .buffer("hair", *p.hair, n * 16)
      .buffer("centre depth", *p.centreZ, n * 4)
      .buffer("tangent", *p.tangent, n * 16)
      .buffer("strand", *p.strand, n * 16);
}
}  // namespace

void AovStage::begin(const cl::Buffer& opaqueDepth, std::size_t pixels, const Planes& p,
                     Profiler* profiler) {
  if (!begin_()) begin_ = dev_.kernel("aov.cl", "aov_begin");
  const std::uint64_t n = pixels;
  KernelArgs a(begin_, "aov");
  a.buffer("opaque depth", opaqueDepth, n * 4).value("pixels", static_cast<cl_uint>(pixels));
  bindPlanes(a, n, p);
  dispatch(dev_, begin_, "aov", cl::NDRange(pixels), cl::NDRange(kGroup), profiler);
}

void AovStage::groom(const Groom& g, std::size_t pixels, const Planes& p, Profiler* profiler) {
  if (!groom_()) groom_ = dev_.kernel("aov.cl", "aov_groom");
  const std::uint64_t n = pixels;
  const std::uint64_t idsAt = g.ids ? n * CLH_LAYER_ID : 0;
  KernelArgs a(groom_, "aov");
  a.buffer("groom", *g.groom, sizeof(gpu::ClhGroomGpu))
      .value("pixels", static_cast<cl_uint>(pixels))
      .value("groom index", static_cast<cl_uint>(g.index))
      .buffer("G-buffer", *g.gbuffer, n * g.layers * 8)
      .value("samples", static_cast<cl_uint>(g.samples))
      .value("identity layer", static_cast<cl_ulong>(idsAt))
      .value("has identities", static_cast<cl_uint>(g.ids ? 1 : 0))
      .buffer("hair result", *g.result, n * 16)
      .buffer("depth", *g.depth, n * 4)
      .buffer("motion", g.motion ? *g.motion : *g.gbuffer, n * 8)
      .value("has motion", static_cast<cl_uint>(g.motion ? 1 : 0));
  bindPlanes(a, n, p);
  dispatch(dev_, groom_, "aov", cl::NDRange(pixels), cl::NDRange(kGroup), profiler);
}

}  // namespace clhair
