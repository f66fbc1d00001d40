// frame_lod.h — the camera pass's LOD records of every groom draw in one device buffer,
// and the segment budget over them (Kulikov 2025, "LODs": a per-frame cap on the segments
// of all grooms together).
//
// bind() gives each draw's instance LOD records, counts and scan as sub-buffers of one
// arena, laid out in draw order (ClhBudgetDraw in gpu_types.h), so that after every
// groom's LOD pre-pass one kernel sees all of them: budget_plan (one work-group) sums the
// segments and picks the proportional factor, budget_apply (one work-group per draw)
// rewrites the records, counts and scans and writes each draw's strands and segments to a
// small state buffer. No host round trip happens between the pre-passes and the strand
// passes; read() is one blocking read of the state after the frame.
// Invariant: an instance keeps its sub-buffers while the arena and its place in the
// layout stay the same; a larger scene grows the arena and rebinds every draw.
#pragma once

#include <cstdint>
#include <vector>

#include "cl/dispatch.h"
#include "groom/groom_gpu.h"

namespace clhair {

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
               const std::vector<char>& far, std::uint64_t budget, Profiler* profiler);

  struct Result {
    float scale = 1.0f;               // the factor f applied to every bundle's strands
    bool over = false;                // the pre-passes exceeded the budget
    std::uint64_t lodSegments = 0;    // segments of the pre-passes, before the budget
    std::vector<std::uint32_t> draw;  // 4 per draw: strands, segments, visible, flags
  };
  // Blocking read of the last enqueue's outcome for `draws` draws.
  Result read(std::size_t draws);
  // The outcome's words for `draws` draws (read back with the frame), and their meaning.
  const cl::Buffer& state() const { return state_; }
  static std::size_t stateWords(std::size_t draws);
  static Result decode(const std::vector<std::uint32_t>& words, std::size_t draws);
  // The arena, draw table and state (what the budget pass declares).
  std::vector<const cl::Buffer*> buffers() const { return {&arena_, &table_, &state_}; }

 private:
  Device::Impl& dev_;
  cl::Kernel plan_, apply_;
  std::size_t align_ = 128;  // sub-buffer origin alignment, bytes
  cl::Buffer arena_;
  std::size_t arenaBytes_ = 0;
  std::uint64_t generation_ = 0;  // bumped whenever arena_ is reallocated
  cl::Buffer table_, state_;
  std::size_t tableCap_ = 0, stateCap_ = 0;
  std::vector<gpu::ClhBudgetDraw> layout_;
  std::vector<unsigned char> tableSent_;  // what table_ holds
};

}  // namespace clhair
