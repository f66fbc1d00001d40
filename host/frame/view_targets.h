// view_targets.h — the buffers of a frame with several views of one assembly: a render
// target per view after the first (which draws into the renderer's own), and the per-view
// scene depths and G-buffers as slices of one buffer each, which the multi-view strand pass
// draws into side by side. Each slice starts on the device's sub-buffer alignment and is a
// sub-buffer of its own: the depth and G-buffer of that view's opaque pass, shading, filter,
// composite and read-back, so nothing is copied between them. Reallocated only when the
// view count, size or sample count changes.
#pragma once

#include <memory>
#include <vector>

#include "frame/render_target.h"

namespace clhair {

class ViewTargets {
 public:
  explicit ViewTargets(Device::Impl& dev) : dev_(dev) {}
  // `V` views of width x height with `msaa` samples; `first` is the target of view 0.
  void ensure(RenderTarget& first, std::size_t V, int width, int height, int msaa);
  RenderTarget& target(std::size_t v) { return v == 0 ? *first_ : *targets_[v - 1]; }
  std::size_t count() const { return count_; }
  std::size_t depthStride = 0, gbufferStride = 0;  // elements from one slice to the next
  cl::Buffer depths, gbuffers;                     // every view's slices
  std::vector<cl::Buffer> depthSlices, gbufferSlices;
  cl::Buffer records, grooms;  // ClhViewGpu and ClhGroomGpu per view
  std::vector<unsigned char> recordsSent;

 private:
  Device::Impl& dev_;
  RenderTarget* first_ = nullptr;
  std::vector<std::unique_ptr<RenderTarget>> targets_;
  std::size_t count_ = 0, align_ = 0, slicePixels_ = 0, depthWords_ = 0, gbufferWords_ = 0,
              slots_ = 0;
};

}  // namespace clhair
