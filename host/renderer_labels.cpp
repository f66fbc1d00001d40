// renderer_labels.cpp — Renderer::labels: the labels hair models learn from, on the device
// (clhair/labels.h, kernels/labels.cl), from a frame already read back.
#include "clhair/error.h"
#include "renderer_impl.h"
#include "stages/view_math.h"

namespace clhair {

HairLabels Renderer::labels(const Frame& frame, const Camera& camera) {
  const int w = frame.color.width, h = frame.color.height;
  const std::size_t n = static_cast<std::size_t>(std::max(w, 0)) * std::max(h, 0);
  if (n == 0 || frame.aovs.tangent.size() != 3 * n || frame.aovs.hairAlpha.size() != n)
    throw Error(
        "labels: the frame has no tangent and hair alpha layers of its size (render it with "
        "RenderOptions::aovs)");
  const std::vector<float> raw =
      impl_->labels.run(makeView(camera, w, h), frame.aovs.tangent, frame.aovs.hairAlpha);
  HairLabels out;
  out.width = w;
  out.height = h;
  out.angle.resize(n);
  out.confidence.resize(n);
  out.mask.resize(n);
  out.strandMap.assign(3 * n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const float ux = raw[4 * i + 2], uy = raw[4 * i + 3];
    out.angle[i] = raw[4 * i];
    out.confidence[i] = raw[4 * i + 1];
    out.mask[i] = frame.aovs.hairAlpha[i] >= kLabelMaskAlpha ? 1 : 0;
    if (!out.mask[i] || (ux == 0.0f && uy == 0.0f)) continue;
    out.strandMap[3 * i] = 1.0f;
    out.strandMap[3 * i + 1] = 0.5f * (ux + 1.0f);
    out.strandMap[3 * i + 2] = 0.5f * (uy + 1.0f);
  }
  return out;
}

}  // namespace clhair
