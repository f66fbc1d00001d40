// progressive.h — quality levels (clhair/scene.h, Quality) and the still of quality final:
// jittered passes accumulated progressively.
//
// A pass of final is one frame of the pass path (kFinalPassGood: the good path, else one
// sample per pixel without a filter) with the image plane shifted by the pass's offset (an
// R2 low-discrepancy sequence around the pixel centre, the first at the centre, as the
// reference's). Passes are added in any grouping: the sums are fixed point (2^-24 of a unit
// of linear radiance per pass, integers), so adding passes [0, k) and [k, 2k) to two
// accumulations and merging them gives exactly the sums of one accumulation of [0, 2k), and
// the same passes give the same bytes.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "clhair/renderer.h"

namespace clhair {

// The quality level a frame of `scene` renders at with `options`.
Quality qualityLevel(const Scene& scene, const RenderOptions& options);
// Passes of final (RenderOptions::spp, else the scene's, else kDefaultFinalPasses).
int finalPasses(const Scene& scene, const RenderOptions& options);
// The options of one frame at its level: draft keeps them; good sets MSAA (kGoodMsaa unless
// more than one sample is given), point shading as kGoodPointShading says unless
// RenderOptions::pointShading does, and the filter off; for final, the
// options of its passes (the pass path, without the offset). The level is then fixed (0 or
// 1), so the result renders one frame.
RenderOptions qualityOptions(const Scene& scene, const RenderOptions& options);
// Whether final's passes take the good path (else one sample per pixel, unfiltered) unless
// RenderOptions::finalPath says. One sample per pixel: 64 such passes measured 0.0119
// against 0.0111 for 64 good passes (groom1 close, 960x540), at 0.5-0.6 of their time a pass
// (DESIGN.md, "Quality levels").
constexpr bool kFinalPassGood = false;
// The most RenderOptions::finalSubset may be.
constexpr int kMaxFinalSubset = 16;
// The image-plane offset of pass `pass` of final, pixels in x and y (-0.5..0.5).
void finalJitter(int pass, float& x, float& y);

class ProgressiveStill {
 public:
  // `options` as for Renderer::render (the level is not read: the passes are final's). The
  // scene is held by reference and must not change between passes: with
  // RenderOptions::reuseAssembly the passes draw the strands the first one assembled.
  ProgressiveStill(Renderer& renderer, const Scene& scene, const RenderOptions& options);
  // Renders passes [first, first + count) and adds them; `progress` after each, if set.
  void add(int first, int count);
  // Adds the passes another accumulation of the same still and options holds.
  void merge(const ProgressiveStill& other);
  int passes() const { return passes_; }
  // The mean of the passes added: colour (the fixed-point sums over the passes), depth the
  // nearest of the passes', timings the sums per stage, statistics those of the first pass
  // (but FrameStats::shadowMapsBuilt: the sum over the passes).
  // Throws when no pass was added.
  Frame frame() const;
  std::function<void(int done)> progress;

 private:
  Renderer& renderer_;
  const Scene& scene_;
  RenderOptions options_;
  std::uint64_t id_ = 0;  // RenderOptions::still of its passes (unique per still)
  int passes_ = 0;
  int width_ = 0, height_ = 0;
  std::vector<std::int64_t> sums_;  // per pixel and channel, fixed point
  Frame first_;                     // depth (nearest so far), timings (summed), statistics
};

}  // namespace clhair
