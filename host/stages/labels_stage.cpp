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
  cl::Buffer v = makeBuffer<gpu::ClhViewGpu>(dev_, "the labels' view", 1, &view);
  cl::Buffer t = makeBuffer<cl_float>(dev_, "the tangent layer", 3 * n, tangent.data());
  cl::Buffer a = makeBuffer<cl_float>(dev_, "the hair alpha layer", n, alpha.data());
  cl::Buffer out = makeBuffer<cl_float4>(dev_, "the labels", n);
  KernelArgs k(kernel_, "labels");
  k.buffer("view", v, sizeof(gpu::ClhViewGpu))
      .value("width", static_cast<cl_uint>(view.width))
      .value("pixels", static_cast<cl_uint>(n))
      .buffer("tangent", t, 3 * n * sizeof(float))
      .buffer("alpha", a, n * sizeof(float))
      .buffer("labels", out, n * 4 * sizeof(float));
  dispatch(dev_, kernel_, "labels", cl::NDRange(n), cl::NDRange(64), nullptr);
  std::vector<float> host(4 * n);
  readBack(dev_, "the labels", out, host.data(), host.size());
  return host;
}

}  // namespace clhair
