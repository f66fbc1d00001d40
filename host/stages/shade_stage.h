// shade_stage.h — binds and launches the deferred shading pass (kernels/shade.cl) over the
// center G-buffer, one work-item per pixel, into premultiplied hair RGBA.
#pragma once

#include <map>
#include <utility>

#include "stages/point_stage.h"
#include "stages/stage_inputs.h"

namespace clhair {

class ShadeStage {
 public:
  explicit ShadeStage(Device::Impl& dev);
  struct Params {
    ViewTarget target;
    LightingInputs lighting;
    const cl::Buffer* groom = nullptr;    // ClhGroomGpu of the groom being drawn
    const cl::Buffer* offsets = nullptr;  // its strand scan and totals (gpu_types.h, scan layout)
    std::uint32_t records = 0;            // bundles or chunks of the scan
    const cl::Buffer* gbuffer = nullptr;  // ulong per pixel, msaa + 1 layers
    cl::Buffer* hair = nullptr;           // float4 per pixel
    const cl::Buffer* visibility = nullptr;       // ClhVisibilityGpu of the groom instance
    const cl::Buffer* visibilityTable = nullptr;  // float4 per SH cell (one when it has none)
    std::uint32_t visibilityCells = 0;
    const cl::Buffer* aoField = nullptr;  // float per voxel of the groom's AO field (one: none)
    std::uint64_t aoFieldVoxels = 1;
    int msaa = 1;
    bool cover = false;  // coverage mode: three layers and the coverage plane (coverage.h)
  };
  cl::Event enqueue(const Params& p, Profiler* profiler);
  // Per-point shading: every point listed in `lists` shaded once at its own position into
  // lists.colors (shade_points; p.gbuffer, p.hair and p.msaa are not read). A grid of at
  // most a few thousand work-items per compute unit walks the slots up to the count the
  // device holds.
  cl::Event enqueuePoints(const Params& p, const PointStage::Lists& lists, Profiler* profiler);

 private:
  cl::Kernel& kernel(int msaa, bool cover);
  Device::Impl& dev_;
  std::map<std::pair<int, bool>, cl::Kernel> kernels_;
  cl::Kernel points_;
};

}  // namespace clhair
