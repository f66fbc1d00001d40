// temporal.h — temporal reprojection of the hair over a finite window of frames, and the
// frame sequence that renders it without depending on what the process rendered before.
//
// Frame t with a history of K frames (TemporalParams, RenderOptions::temporal) blends the hair
// of frames t-K .. t (never before the shot's first frame): starting from frame t-K's own
// hair, each later frame j carries the running result to itself along its motion vectors
// (Frame::aovs.motion, which point to frame j-1), drops it where its depth or its own 3x3
// neighbourhood contradicts it, and blends it with its own hair (weight `blend` for frame j).
// The opaque scene is never blended: the frame is recomposed as blended hair over frame t's
// opaque colour. Each frame of the window is a frame rendered on its own (with its AOVs and its
// motion to the frame before), so frame t depends only on the scene and t: FrameSequence
// renders the frames of the window it does not hold and reuses those it rendered for an earlier
// output of the same sequence, which are the same frames (DESIGN.md, "Temporal reprojection").
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include "clhair/renderer.h"
#include "clhair/scene.h"

namespace clhair {

// What one reprojection step did, in pixels.
struct TemporalStats {
  std::uint64_t blended = 0;   // history carried and blended
  std::uint64_t outside = 0;   // carried from outside the previous image: own hair kept
  std::uint64_t rejected = 0;  // dropped by the depth rule: own hair kept
  std::uint64_t clamped = 0;   // history changed by the neighbourhood clamp (any channel)
};

// One step of the window. `now` and `before` are the AOVs of frames j and j-1 (rendered with
// RenderOptions::aovs, `now` with its motion to j-1); `history` is frame j-1's blended hair
// (premultiplied RGBA, 4 per pixel; before.hair for the window's first frame). Returns frame
// j's blended hair. Per pixel p of frame j:
//   - the motion and depth are those of the nearest surface (smallest Z) in p's 3x3
//     neighbourhood, so that the thin hair's faint edges move with the hair;
//   - the history is sampled bilinearly at p + motion (x right, y up; outside the image: none);
//   - it is dropped (rejectDepth) when the nearest Z in the 3x3 neighbourhood of the sample's
//     pixel in frame j-1 and p's differ by more than depthTolerance of the nearer, or exactly
//     one of them is the background;
//   - it is clamped (clamp) channel by channel to the range of frame j's own hair over p's 3x3
//     neighbourhood (Karis 2014's TAA clamp, on premultiplied RGBA);
//   - the result is blend * own + (1 - blend) * history.
std::vector<float> reprojectHair(const FrameAovs& now, const FrameAovs& before,
                                 const std::vector<float>& history, int width, int height,
                                 const TemporalParams& params, TemporalStats* stats = nullptr);

// The frame's colour with its hair replaced by `hair` (premultiplied RGBA): hair + (1 - alpha)
// * the opaque colour (FrameAovs::opaque). Pixels whose hair is unchanged keep the rendered
// colour exactly. The frame needs its AOVs.
Image recomposeHair(const Frame& frame, const std::vector<float>& hair);

// Renders frames of one shot by number, each frame the same whatever this object rendered
// before. With reprojection off (RenderOptions::temporal 0, or -1 with the scene's
// temporal.history 0) render() is Renderer::render of the still (with AOVs and the previous
// frame when options.aovs asks): the frame is bit-identical to one rendered without this.
class FrameSequence {
 public:
  // stillAt(n): the still scene of frame n (sceneAtFrame and the caller's camera choice).
  // Frames up to firstFrame are their own previous frame (zero motion) and have no history.
  FrameSequence(Renderer& renderer, std::function<Scene(long long)> stillAt,
                const RenderOptions& options, long long firstFrame = 1);

  // Frame n. With reprojection: its colour (and the hair alpha and hair layers when options.aovs
  // asks for AOVs) are the blended ones; everything else is frame n's own.
  Frame render(long long n);

  // Frames rendered so far (outputs and history), for reporting the cost of the window.
  std::uint64_t framesRendered() const { return rendered_; }
  // The summed statistics of every reprojection step of the last render().
  const TemporalStats& lastStats() const { return stats_; }
  // The history length the last render() used (0: off).
  int lastHistory() const { return lastHistory_; }

 private:
  const Frame& own(long long n, const Scene* still);

  Renderer& renderer_;
  std::function<Scene(long long)> stillAt_;
  RenderOptions options_;
  long long first_;
  std::map<long long, Frame> held_;  // frames rendered with AOVs, by number (the window)
  std::uint64_t rendered_ = 0;
  TemporalStats stats_;
  int lastHistory_ = 0;
};

}  // namespace clhair
