// filter_stage.h — binds and launches filter_reconstruct (kernels/filter.cl): strand
// reconnection, oriented bilateral and alpha from the center and conservative layers
// (Lipp §3.3), one work-item per pixel, into premultiplied RGBA. The stage owns the
// filter's parameter record and uploads it when the settings change.
#pragma once

#include <vector>

#include "clhair/scene.h"
#include "stages/stage_inputs.h"

namespace clhair {

class FilterStage {
 public:
  explicit FilterStage(Device::Impl& dev);
  struct Params {
    ViewTarget target;
    const cl::Buffer* groom = nullptr;    // ClhGroomGpu
    const cl::Buffer* gbuffer = nullptr;  // 2 layers: center, conservative
    const cl::Buffer* hair = nullptr;     // shaded center colour, float4 per pixel
    cl::Buffer* out = nullptr;            // premultiplied RGBA, float4 per pixel
  };
  // Checks and uploads `settings` (radius 0..8), then filters.
  cl::Event enqueue(const FilterParams& settings, const Params& p, Profiler* profiler);
  const cl::Buffer& params() const { return params_; }  // the settings record

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_;  // built by the first enqueue
  cl::Buffer params_;
  std::vector<unsigned char> sent_;  // what params_ holds
};

}  // namespace clhair
