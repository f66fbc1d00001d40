// labels_stage.h — binds and launches kernels/labels.cl: a frame's tangent and hair alpha
// layers in, per pixel (angle, confidence, image direction x, y) out (clhair/labels.h).
#pragma once

#include <vector>

#include "cl/dispatch.h"
#include "clhair/gpu_types.h"

namespace clhair {

class LabelsStage {
 public:
  explicit LabelsStage(Device::Impl& dev) : dev_(dev) {}
  // `tangent` 3 and `alpha` 1 per pixel of view.width * view.height; returns 4 per pixel.
  std::vector<float> run(const gpu::ClhViewGpu& view, const std::vector<float>& tangent,
                         const std::vector<float>& alpha);

 private:
  Device::Impl& dev_;
  cl::Kernel kernel_;
  cl::Buffer view_, tangent_, alpha_, out_;
  std::size_t viewCap_ = 0, tangentCap_ = 0, alphaCap_ = 0, outCap_ = 0;
};

}  // namespace clhair
