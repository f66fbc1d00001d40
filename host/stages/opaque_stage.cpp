// opaque_stage.cpp — see opaque_stage.h.
#include "stages/opaque_stage.h"

namespace clhair {

OpaqueStage::OpaqueStage(Device::Impl& dev)
    : dev_(dev), kernel_(dev.kernel("opaque.cl", "opaque_render")) {}

cl::Event OpaqueStage::enqueue(const Params& p, Profiler* profiler) {
  const std::uint64_t pixels = p.target.pixels();
  KernelArgs a(kernel_, "opaque");
  a.buffer("scene", *p.lighting.scene, sizeof(gpu::ClhSceneGpu))
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("spheres", *p.spheres, p.sphereCount * sizeof(gpu::ClhSphereGpu))
      .buffer("planes", *p.planes, p.planeCount * sizeof(gpu::ClhPlaneGpu));
  bindLightsAndShadows(a, p.lighting);
  bindEnvironment(a, p.lighting.env);
  a.buffer("background", *p.background, p.backgroundTexels * 4 * sizeof(float))
      .buffer("colour", *p.color, pixels * 4 * sizeof(float))
      .buffer("depth", *p.depth, pixels * sizeof(float))
      .value("shade", static_cast<cl_uint>(p.shade ? 1 : 0));
  return dispatch(dev_, kernel_, "opaque", cl::NDRange(p.target.width, p.target.height),
                  cl::NDRange(8, 8), profiler);
}

}  // namespace clhair
