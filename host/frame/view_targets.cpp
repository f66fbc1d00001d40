// view_targets.cpp — see view_targets.h.
#include "frame/view_targets.h"

#include <algorithm>

#include "cl/buffers.h"

namespace clhair {

void ViewTargets::ensure(RenderTarget& first, std::size_t V, int width, int height, int msaa) {
  first_ = &first;
  count_ = V;
  while (targets_.size() + 1 < V) targets_.push_back(std::make_unique<RenderTarget>(dev_));
  for (std::size_t v = 0; v < V; ++v) target(v).ensure(width, height, msaa);
  const std::size_t pixels = first.pixels();
  const std::size_t layers = static_cast<std::size_t>(msaa) + 1;
  if (!align_) {
    const cl_uint bits = clCall("querying the sub-buffer alignment", [&] {
      return dev_.device.getInfo<CL_DEVICE_MEM_BASE_ADDR_ALIGN>();
    });
    align_ = std::max<std::size_t>(bits / 8, sizeof(cl_ulong));
  }
  auto strideOf = [&](std::size_t count, std::size_t bytes) {  // elements per slice, padded
    return (count * bytes + align_ - 1) / align_ * align_ / bytes;
  };
  depthStride = strideOf(pixels, sizeof(cl_float));
  gbufferStride = strideOf(pixels * layers, sizeof(cl_ulong));
  if (depthWords_ != V * depthStride || gbufferWords_ != V * gbufferStride ||
      depthSlices.size() != V || slicePixels_ != pixels * layers) {
    depths = makeBuffer<cl_float>(dev_, "the scene depth of every view", V * depthStride);
    gbuffers = makeBuffer<cl_ulong>(dev_, "the G-buffers of every view", V * gbufferStride);
    depthWords_ = V * depthStride;
    gbufferWords_ = V * gbufferStride;
    slicePixels_ = pixels * layers;
    depthSlices.clear();
    gbufferSlices.clear();
    auto slice = [&](cl::Buffer& whole, std::size_t origin, std::size_t size) {
      cl_buffer_region region{origin, size};
      return clCall("creating a view's slice", [&] {
        return whole.createSubBuffer(CL_MEM_READ_WRITE, CL_BUFFER_CREATE_TYPE_REGION, &region);
      });
    };
    for (std::size_t v = 0; v < V; ++v) {
      depthSlices.push_back(
          slice(depths, v * depthStride * sizeof(cl_float), pixels * sizeof(cl_float)));
      gbufferSlices.push_back(slice(gbuffers, v * gbufferStride * sizeof(cl_ulong),
                                    pixels * layers * sizeof(cl_ulong)));
    }
  }
  if (slots_ != V) {
    records = makeBuffer<gpu::ClhViewGpu>(dev_, "view parameters of every view", V);
    grooms = makeBuffer<gpu::ClhGroomGpu>(dev_, "groom parameters of every view", V);
    recordsSent.clear();
    slots_ = V;
  }
}

}  // namespace clhair
