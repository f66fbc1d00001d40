// aov_builder.h — gathers the layers for compositing (Frame::aovs, clhair/aov.h) while a
// frame is drawn, on the host, from what each groom leaves on the device.
//
// Inputs, per frame: the view record, the depth of the opaque scene; per groom drawn (after
// its composite): its record (G-buffer depth mapping), its centre sample layers, its shaded
// (or filtered) premultiplied hair and the depth buffer after compositing. Outputs: Z, hair
// alpha, tangent, motion and the hair layer (premultiplied, composited like composite.cl).
// Invariants: the surface whose depth is in Z is the one whose motion is given: a pixel belongs to
// the last groom whose composite lowered its depth (composite.cl writes the depth of hair at least
// half opaque), otherwise to the opaque scene. A deforming groom hands in the motion its motion
// pass resolved per pixel (the strands evaluated at the previous frame, GroomGpu::motion); a rigid
// one's pixels are carried through its change of transform and the previous camera here.
#pragma once

#include <cstdint>
#include <vector>

#include "clhair/gpu_types.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"

namespace clhair {

class AovBuilder {
 public:
  AovBuilder(const gpu::ClhViewGpu& view, const std::vector<float>& opaqueDepth);

  // Groom `index` (its position in Scene::grooms) after its composite: `centre` holds
  // `layers` sample layers of width * height words, `hair` premultiplied RGBA per pixel,
  // `depth` the depth buffer after the composite; `motion` (or null) the groom's motion pass:
  // per pixel the packed screen motion (x, y down, float bits x << 32 | y), all ones where
  // it has none. `ids`, when given, holds the identity word of every pixel's centre word
  // (gpu_types.h).
  void addGroom(std::size_t index, const gpu::ClhGroomGpu& params,
                const std::vector<std::uint64_t>& centre, int layers,
                const std::vector<float>& hair, const std::vector<float>& depth,
                const std::vector<std::uint64_t>* motion = nullptr,
                const std::vector<std::uint64_t>* ids = nullptr);

  // The planes for the final depth buffer of `scene`'s frame; motion from `previous` (the
  // previous frame's still scene, grooms matched by index), zero without it.
  FrameAovs finish(const std::vector<float>& depth, const Scene& scene,
                   const Scene* previous) const;

 private:
  gpu::ClhViewGpu view_;
  std::size_t pixels_;
  std::vector<float> lastDepth_;            // depth buffer after the last groom seen
  std::vector<std::int32_t> owner_;         // groom owning the depth of each pixel, -1: opaque
  std::vector<std::uint64_t> ownerMotion_;  // the owner's motion-pass word, all ones: none
  std::vector<float> hairAlpha_;            // 1 - prod(1 - a_k)
  std::vector<float> centreZ_;              // depth of the nearest centre word so far (+inf: none)
  std::vector<float> tangent_;              // its decoded tangent, 3 per pixel
  std::vector<float> strand_;               // its groom, strand and u, 3 per pixel (with ids)
  std::vector<float> hair_;                 // the grooms' premultiplied RGBA, composited
  bool ids_ = false;
};

}  // namespace clhair
