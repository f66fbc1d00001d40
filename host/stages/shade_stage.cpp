// shade_stage.cpp — see shade_stage.h.
#include "stages/shade_stage.h"

#include <algorithm>
#include <utility>

#include "clhair/coverage.h"

namespace clhair {

ShadeStage::ShadeStage(Device::Impl& dev) : dev_(dev) {}  // kernels built on first use

cl::Kernel& ShadeStage::kernel(int msaa, bool cover) {
  auto it = kernels_.find({msaa, cover});
  if (it != kernels_.end()) return it->second;
  return kernels_[{msaa, cover}] = dev_.kernel(
             "shade.cl", "shade_deferred",
             "-DCLH_MSAA=" + std::to_string(msaa) + (cover ? " -DCLH_RASTER_COVER=1" : ""));
}

namespace {

// The arguments both shading kernels open with (shade.cl, SHADE_PARAMS): the groom, view
// and scene, the lights with their maps, the environment, the baked visibility and the AO
// field.
void bindShadeInputs(KernelArgs& a, const ShadeStage::Params& p) {
  a.buffer("groom", *p.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("scene", *p.lighting.scene, sizeof(gpu::ClhSceneGpu));
  bindLightsAndShadows(a, p.lighting);
  bindEnvironment(a, p.lighting.env);
  a.buffer("visibility", *p.visibility, sizeof(gpu::ClhVisibilityGpu))
      .buffer("visibility table", *p.visibilityTable,
              std::uint64_t(std::max<std::uint32_t>(p.visibilityCells, 1)) * 4 * sizeof(float))
      .buffer("AO field", *p.aoField, std::max<std::uint64_t>(p.aoFieldVoxels, 1) * sizeof(float));
}

}  // namespace

cl::Event ShadeStage::enqueue(const Params& p, Profiler* profiler) {
  if (p.cover && p.msaa != 1)
    throw Error("the coverage mode shades one sample per pixel, not MSAA " +
                std::to_string(p.msaa));
  cl::Kernel& k = kernel(p.msaa, p.cover);
  // the coverage mode's three layers and coverage plane; otherwise the samples and the
  // conservative layer
  const std::uint64_t layers =
      p.cover ? CLH_LAYER_COVERAGE + 1u : static_cast<std::uint64_t>(p.msaa + 1);
  const std::uint64_t pixels = p.target.pixels();
  KernelArgs a(k, "shade");
  bindShadeInputs(a, p);
  a.buffer("G-buffer", *p.gbuffer, pixels * layers * sizeof(cl_ulong))
      .buffer("strand offsets", *p.offsets,
              std::uint64_t(gpu::clh_lod_offsets_length(p.records)) * sizeof(cl_uint))
      .buffer("hair colour", *p.hair, pixels * 4 * sizeof(float));
  return dispatch(dev_, k, "shade", cl::NDRange(p.target.width, p.target.height), cl::NDRange(8, 8),
                  profiler);
}

cl::Event ShadeStage::enqueuePoints(const Params& p, const PointStage::Lists& lists,
                                    Profiler* profiler) {
  if (!points_()) points_ = dev_.kernel("shade.cl", "shade_points");
  const PointStage::Sizes& s = lists.sizes;
  KernelArgs a(points_, "shade");
  bindShadeInputs(a, p);
  a.buffer("strand offsets", *p.offsets,
           std::uint64_t(gpu::clh_lod_offsets_length(p.records)) * sizeof(cl_uint))
      .buffer("point records", *lists.records, s.recordsBytes())
      .buffer("point ranks", *lists.offsets, s.offsetsBytes())
      .value("point words", static_cast<cl_uint>(s.words))
      .value("point capacity", static_cast<cl_uint>(s.capacity))
      .buffer("point colours", *lists.colors, s.colorsBytes());
  // the count is known on the device only: a grid that walks the slots, as wide as the
  // device keeps busy and no wider than the capacity
  const std::size_t local = 64;
  const std::size_t wide = std::size_t(std::max<std::uint32_t>(dev_.info.computeUnits, 1)) * 2048;
  const std::size_t global =
      roundUp(std::max<std::size_t>(std::min<std::size_t>(s.capacity, wide), 1), local);
  return dispatch(dev_, points_, "shade", cl::NDRange(global), cl::NDRange(local), profiler);
}

}  // namespace clhair
