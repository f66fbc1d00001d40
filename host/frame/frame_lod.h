// frame_lod.h — the camera pass's LOD records of every groom draw in one device buffer,
// and the segment budget over them (Kulikov 2025, "LODs": a per-frame cap on the segments
// of all grooms together).
//
// bind() gives each draw's instance LOD records, counts and scan as sub-buffers of one
// arena, laid out in draw order (ClhBudgetDraw in gpu_types.h), so that after every
// groom's LOD pre-pass the budget's kernels (kernels/budget.cl, launched by BudgetStage)
// see all of them:
// budget_measure (one work-group per draw) sums each draw's request, floor and screen box,
// budget_plan (one work-group) shares the budget out by the rule (BudgetRuleParams: one factor
// for all, or each groom's share by its screen need), budget_apply (one work-group per
// draw) rewrites the records, counts and scans and writes each draw's strands and segments
// to a small state buffer. No host round trip happens between the pre-passes and the
// strand passes; read() is one blocking read of the state after the frame.
// Invariant: an instance keeps its sub-buffers while the arena and its place in the
// layout stay the same; a larger scene grows the arena and rebinds every draw.
#pragma once

#include <cstdint>
#include <vector>

#include "cl/dispatch.h"
#include "clhair/renderer.h"
#include "groom/groom_gpu.h"
#include "stages/budget_stage.h"

namespace clhair {

// How the segment budget shares the segments out (ClhBudgetRule, DESIGN.md "The segment
// budget").
struct BudgetRuleParams {
  bool screen = true;  // false: the uniform rule (one factor for every groom)
  // A groom whose screen box covers more than keepHigh of the image keeps its LOD count
  // while the other grooms' cuts down to their floors pay for it; the claim ramps in from
  // keepLow (smoothstep) and fades out as the room above the floors falls from the claims
  // to roomLow of them (RenderOptions::budgetKeepLow, budgetKeepHigh).
  float keepLow = 0.15f, keepHigh = 0.25f, roomLow = 0.5f;
  float widenCap = 0.0f;   // the most the budget widens a survivor over LOD (0: N_LOD / N')
  float imageArea = 0.0f;  // the view's width x height, pixels
};

// The rule RenderOptions::budgetRule asks for, in a view of `view`'s size.
BudgetRuleParams budgetRuleParams(const RenderOptions& options, const gpu::ClhViewGpu& view);

class FrameLod {
 public:
  explicit FrameLod(Device::Impl& dev);

  // Places every draw's LOD buffers in the arena (grown when needed).
  void bind(const std::vector<GroomDraw>& draws);
  // After the camera pass's pre-pass of every draw (active[k]: 0 not drawn,
  // CLH_BUDGET_DRAW_FIXED drawn without LOD, CLH_BUDGET_DRAW_BUDGETED drawn with LOD and
  // under the budget): the budget's plan and its application, on the device. budget 0:
  // none (the per-draw totals are still gathered). far[k]: draw k is small on screen and
  // drops every other control point when over budget.
  void enqueue(const std::vector<GroomDraw>& draws, const std::vector<char>& active,
               const std::vector<char>& far, std::uint64_t budget, Profiler* profiler,
               const BudgetRuleParams& rule = {});

  // What the budget measured and decided for one draw (state words 4.., gpu_types.h).
  struct DrawPlan {
    std::uint32_t request = 0;  // R: segments its LOD records asked (halved when halved)
    std::uint32_t floor = 0;    // F: one strand per drawn record (halved when halved)
    std::uint32_t share = 0;    // S: segments the screen rule gave it (else R)
    float factor = 1.0f;        // f_d: the share of its strands above the floor it keeps
    float area = 0.0f;          // A: its screen box, pixels
    float claim = 0.0f;         // p: its claim to keep its LOD count (0..1)
  };
  struct Result {
    float scale = 1.0f;               // the uniform rule's factor f (1 under the screen rule)
    bool over = false;                // the pre-passes exceeded the budget
    std::uint64_t lodSegments = 0;    // segments of the pre-passes, before the budget
    float level = 0.0f;               // the screen rule's level mu, segments per box pixel
    float claims = 1.0f;              // the strength phi of the claims (screen rule)
    std::vector<std::uint32_t> draw;  // 4 per draw: strands, segments, visible, flags
    std::vector<DrawPlan> plan;       // one per draw
  };
  // Blocking read of the last enqueue's outcome for `draws` draws.
  Result read(std::size_t draws);
  // The outcome's words for `draws` draws (read back with the frame), and their meaning.
  const cl::Buffer& state() const { return state_; }
  static std::size_t stateWords(std::size_t draws);
  static Result decode(const std::vector<std::uint32_t>& words, std::size_t draws);
  // The arena, draw table, rule and state (what the budget pass declares).
  std::vector<const cl::Buffer*> buffers() const { return {&arena_, &table_, &rule_, &state_}; }

 private:
  Device::Impl& dev_;
  BudgetStage stage_;
  std::size_t align_ = 128;  // sub-buffer origin alignment, bytes
  cl::Buffer arena_;
  std::size_t arenaBytes_ = 0;
  std::uint64_t generation_ = 0;  // bumped whenever arena_ is reallocated
  cl::Buffer table_, state_, rule_;
  std::size_t tableCap_ = 0, stateCap_ = 0;
  std::vector<gpu::ClhBudgetDraw> layout_;
  std::vector<unsigned char> tableSent_, ruleSent_;  // what table_ and rule_ hold
};

}  // namespace clhair
