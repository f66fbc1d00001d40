// frame_plan.h — what a frame decides before any of its passes runs, and the handles of
// the frame's resources its passes hand on (a feature's own go on the graph's Blackboard).
//
// planFrame() reads the scene and the options once: the raster mode, the dispatch sizing,
// the view record, and per groom instance whether it is drawn (in front of the camera),
// which filter, G-buffer layers, screen box, motion pass and budget role it gets. The pass
// files (host/passes/) add their passes from the plan and store the graph handles of what
// they produce in it, for the passes after them; nothing about a frame lives in members of
// the renderer. A plan holds references to the scene and options: it lives while its
// graph is built and executed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "clhair/renderer.h"
#include "graph/frame_graph.h"
#include "groom/groom_gpu.h"
#include "stages/stage_inputs.h"

namespace clhair {

class GBufferSource;
class RenderTarget;

// One view of the frame: the target it draws into and the buffers its passes use. A frame of
// one view draws into the renderer's target; a frame of several into a target per view, whose
// scene depth and G-buffer are slices of buffers the views share (frame/view_targets.h), so
// that one strand pass can draw every view. The passes of a view (opaque, shade, filter,
// composite) are added once per view from these; the features of one view alone (LOD and
// the segment budget, linking, motion, per-point shading, AOVs, capture) use the first.
struct ViewPlan {
  std::size_t index = 0;
  std::string suffix;  // after the name of each of its passes: "" in a frame of one view
  RenderTarget* target = nullptr;
  cl::Buffer* depthBuffer = nullptr;  // the target's own, or its slice
  cl::Buffer* gbufferBuffer = nullptr;
  gpu::ClhViewGpu view{};
  ViewDraw draw;  // how the grooms are drawn in it
  // handles: its record, colour, scene depth and G-buffer
  FrameGraph::Handle record, color, depth, gbuffer;
};

// A groom instance in one view: whether it is in front of the view's camera, and its
// shaded hair, the filter's output and the buffer its composite reads.
struct GroomView {
  bool inFront = false;
  FrameGraph::Handle hair, filteredHair, result;
};

// One groom instance of the frame.
struct GroomPlan {
  std::size_t index = 0;  // in Scene::grooms
  GroomDraw draw;
  // 0: entirely behind the camera (no pass of its own runs); CLH_BUDGET_DRAW_FIXED: drawn
  // without LOD; CLH_BUDGET_DRAW_BUDGETED: drawn with LOD, under the segment budget
  char active = 0;
  char far = 0;  // small on screen: drops every other control point when over budget
  const FilterParams* filter = nullptr;
  bool filtered = false;  // Lipp's or Huang's filter (MSAA 1, lines raster)
  bool huang = false;     // Huang's: hair linking (when `linking`), alpha fix, anisotropic
  bool linking = false;
  bool ids = false;  // the strand pass writes the identity layer
  // shaded once per visible strand point (RenderOptions::pointShading; host/passes/
  // point_passes.cpp): the strand pass writes the sample identity layers, no filter
  bool points = false;
  bool motion = false;  // a deforming groom's motion pass (AOVs with a previous frame)
  // G-buffer layers the composite takes the hair's depth from
  std::uint32_t depthLayers = 1;
  int layers = 2;  // G-buffer layers the groom uses
  // its screen box (the default: the whole target) and where its filtered hair is right
  PixelRect box, hairBox;
  // handles: its parameter record, LOD records + scan, geometry tables and motion plane
  FrameGraph::Handle params, lod, tables, motionPlane;
  std::vector<GroomView> views;  // per view of the frame
  // A frame of several views: the view whose LOD and culling its strands follow (the first
  // it is in front of), its record in each view, and whether one strand pass drew it into
  // every view (GroomGpu::rasterViews; else each view draws it on its own before shading).
  std::size_t lodView = 0;
  std::vector<gpu::ClhGroomGpu> viewRecords;
  bool together = true;
  // a pass of a still (RenderOptions::still): the strands its first pass assembled and
  // kept (GroomGpu::rasterStill), which later passes read
  FrameGraph::Handle stored;
};

// Words of the frame's statistics buffer (counters gathered on the device, read back once
// with the frame).
struct StatsLayout {
  std::size_t words = 0;
  std::size_t take(std::size_t n) {
    const std::size_t at = words;
    words += n;
    return at;
  }
};

struct FramePlan {
  FramePlan(const Scene& s, const RenderOptions& o) : scene(s), options(o) {}
  const Scene& scene;
  const RenderOptions& options;
  GBufferSource* source = nullptr;  // the traced reference's centre layers
  bool cover = false;               // the coverage raster
  bool aovs = false;
  bool lodCorrection = true;
  bool shadowsRebuilt = false;
  DispatchMode mode = DispatchMode::OverLaunch;
  std::uint64_t budget = 0;
  std::size_t pixels = 0;  // of each view
  std::vector<ViewPlan> views;
  ViewPlan& camera() { return views.front(); }
  const ViewPlan& camera() const { return views.front(); }
  bool severalViews() const { return views.size() > 1; }
  std::vector<GroomPlan> grooms;
  // the index of the last groom drawn (captureGBuffer keeps its layers), grooms.size(): none
  std::size_t lastDrawn = 0;
  StatsLayout stats;
  std::size_t rasterStatsAt = 0, budgetAt = 0, linkAt = 0, pointsAt = 0, shadowAt = 0;
  // handles of the frame's shared resources (viewRecords, viewGrooms: every view's record and a
  // groom's record in every view, for the strand pass of several views)
  FrameGraph::Handle scene_, shadowMaps, rasterCounters, frameStats, lodArena, visibility,
      linkState, filterParams, motionParams, viewRecords, viewGrooms;
};

// Whether a frame draws in the coverage mode (clhair/coverage.h), and the option checks
// that mode asks for.
bool coverMode(const Scene& s, const RenderOptions& options);
// Whether a groom with filter settings `fp` is filtered with Huang's filter (rather than
// Lipp's), as --filter says, else as the groom's method ("auto" is Huang's).
bool huangMethod(const FilterParams& fp, const RenderOptions& options);
// Whether a frame's grooms are shaded once per visible strand point: asked for
// (RenderOptions::pointShading, resolved from the quality level) and possible (the lines
// raster of the strand pass, not a given G-buffer, not raster-only runs).
bool pointShading(const RenderOptions& options, bool given, bool cover);
// G-buffer layers a groom with filter settings `fp` uses (gpu_types.h).
int gbufferLayers(const FilterParams& fp, const RenderOptions& options, bool given, bool cover);

// The decisions of a frame seen by `cameras` (one or more), drawn into `targets` (one per
// camera, with `depths` and `gbuffers` the buffers of each view's passes); `draws` are the
// scene's groom instances in order.
void planFrame(FramePlan& plan, const std::vector<GroomDraw>& draws, DispatchMode mode,
               const std::vector<Camera>& cameras, const std::vector<RenderTarget*>& targets,
               const std::vector<cl::Buffer*>& depths, const std::vector<cl::Buffer*>& gbuffers);
// The statistics words of a frame of `views` views: raster counters, the budget's outcome,
// 4 linking counters per groom (one view) or a strand total per view and groom (several),
// the points shaded per groom (one view), and the shadow passes' strand totals for
// `shadowSlots` groom slots (last: the read-back takes the rest of the words for them).
void layoutStats(FramePlan& plan, std::size_t views, std::size_t shadowSlots);

}  // namespace clhair
