// composite_stage.cpp — see composite_stage.h.
#include "stages/composite_stage.h"

namespace clhair {

CompositeStage::CompositeStage(Device::Impl& dev) : dev_(dev) {}  // kernels built on first use

cl::Kernel& CompositeStage::kernel(int msaa) {
  auto it = kernels_.find(msaa);
  if (it != kernels_.end()) return it->second;
  return kernels_[msaa] =
             dev_.kernel("composite.cl", "composite_over", "-DCLH_MSAA=" + std::to_string(msaa));
}

cl::Event CompositeStage::enqueue(const Params& p, Profiler* profiler) {
  if (p.depthLayers < 1 || p.depthLayers > p.msaa + 1)
    throw Error("composite: " + std::to_string(p.depthLayers) +
                " depth layers of a G-buffer with " + std::to_string(p.msaa + 1));
  cl::Kernel& k = kernel(p.msaa);
  const std::uint64_t pixels = p.target.pixels();
  const PixelRect box = p.box.clipped(p.target.width, p.target.height);
  KernelArgs(k, "composite")
      .buffer("groom", *p.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("hair colour", *p.hair, pixels * 4 * sizeof(float))
      .buffer("G-buffer", *p.gbuffer,
              pixels * static_cast<std::uint64_t>(p.msaa + 1) * sizeof(cl_ulong))
      .buffer("colour", *p.color, pixels * 4 * sizeof(float))
      .buffer("depth", *p.depth, pixels * sizeof(float))
      .value("depth layers", static_cast<cl_uint>(p.depthLayers))
      .value("box", box.arg());
  return dispatchBox(dev_, k, "composite", box, profiler);
}

}  // namespace clhair
