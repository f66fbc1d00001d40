// labels_stage.cpp — see labels_stage.h.
#include "stages/labels_stage.h"

#include "cl/buffers.h"
#include "clhair/error.h"

namespace clhair {

std::vector<float> LabelsStage::run(const gpu::ClhViewGpu& view, const std::vector<float>& tangent,
                                    const std::vector<float>& alpha) {
  const std::size_t n = std::size_t(view.width) * view.height;
  if (n == 0) return {};
  if (tangent.size() != 3 * n || alpha.size() != n)
    throw Error("labels: the frame's tangent and alpha layers do not match its size");
  if (!kernel_()) kernel_ = dev_.kernel("labels.cl", "hair_labels");
  // the buffers follow the frame's size from call to call (ensureCapacity)
  ensureCapacity<gpu::ClhViewGpu>(dev_, view_, viewCap_, "the labels' view", 1);
  ensureCapacity<cl_float>(dev_, tangent_, tangentCap_, "the tangent layer", 3 * n);
  ensureCapacity<cl_float>(dev_, alpha_, alphaCap_, "the hair alpha layer", n);
  ensureCapacity<cl_float4>(dev_, out_, outCap_, "the labels", n);
  upload(dev_, view_, &view, 1);
  upload(dev_, tangent_, tangent.data(), 3 * n);
  upload(dev_, alpha_, alpha.data(), n);
  KernelArgs k(kernel_, "labels");
  k.buffer("view", view_, sizeof(gpu::ClhViewGpu))
      .value("width", static_cast<cl_uint>(view.width))
      .value("pixels", static_cast<cl_uint>(n))
      .buffer("tangent", tangent_, 3 * n * sizeof(float))
      .buffer("alpha", alpha_, n * sizeof(float))
      .buffer("labels", out_, n * 4 * sizeof(float));
  dispatch(dev_, kernel_, "labels", cl::NDRange(n), cl::NDRange(64), nullptr);
  std::vector<float> host(4 * n);
  readBack(dev_, "the labels", out_, host.data(), host.size());
  return host;
}

}  // namespace clhair
