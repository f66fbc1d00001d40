// filter_stage.cpp — see filter_stage.h.
#include "stages/filter_stage.h"

#include "cl/buffers.h"

namespace clhair {

FilterStage::FilterStage(Device::Impl& dev)
    : dev_(dev), params_(makeBuffer<gpu::ClhFilterGpu>(dev, "filter parameters", 1)) {}

cl::Event FilterStage::enqueue(const FilterParams& f, const Params& p, Profiler* profiler) {
  if (f.radius < 0 || f.radius > 8)
    throw Error("filter radius " + std::to_string(f.radius) + " is outside 0..8");
  gpu::ClhFilterGpu g{};
  g.radius = static_cast<gpu::clh_u32>(f.radius);
  g.s_par = f.sPar;
  g.s_perp = f.sPerp;
  g.sigma_c = f.sigmaC;
  g.depth_reject = f.depthReject;
  g.depth_mismatch = f.depthMismatch;
  g.strip = f.strip;
  g.promote = f.promote ? 1u : 0u;
  uploadChanged(dev_, params_, sent_, &g, 1);
  // built on first use: a frame with Huang's filter (the default) never runs this kernel
  if (!kernel_()) kernel_ = dev_.kernel("filter.cl", "filter_reconstruct");
  const std::uint64_t pixels = p.target.pixels();
  KernelArgs(kernel_, "filter")
      .buffer("groom", *p.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("filter parameters", params_, sizeof(gpu::ClhFilterGpu))
      .buffer("G-buffer", *p.gbuffer, 2 * pixels * sizeof(cl_ulong))
      .buffer("hair colour", *p.hair, pixels * 4 * sizeof(float))
      .buffer("filtered colour", *p.out, pixels * 4 * sizeof(float));
  return dispatch(dev_, kernel_, "filter", cl::NDRange(p.target.width, p.target.height),
                  cl::NDRange(8, 8), profiler);
}

}  // namespace clhair
