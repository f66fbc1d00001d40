// budget_stage.h — binds the segment budget's kernels of kernels/budget.cl over the LOD
// records of every groom draw in one arena (FrameLod, host/frame/frame_lod.h, owns the
// arena, the draw table, the rule and the state and decides what they hold):
// budget_measure (one work-group per draw), budget_plan (one work-group), budget_apply (one
// work-group per draw).
#pragma once

#include <cstddef>
#include <cstdint>

#include "cl/dispatch.h"

namespace clhair {

class BudgetStage {
 public:
  explicit BudgetStage(Device::Impl& dev);

  struct Params {
    const cl::Buffer* table = nullptr;  // ClhBudgetDraw per draw
    std::uint32_t draws = 0;
    cl::Buffer* arena = nullptr;  // every draw's LOD records, counts and scans
    std::size_t arenaBytes = 0;
    std::uint64_t budget = 0;          // segments of all draws together (0: none)
    const cl::Buffer* rule = nullptr;  // ClhBudgetRule
    cl::Buffer* state = nullptr;       // FrameLod::stateWords(draws) words
    std::size_t stateWords = 0;
  };
  void enqueue(const Params& p, Profiler* profiler);

 private:
  Device::Impl& dev_;
  cl::Kernel measure_, plan_, apply_;
};

}  // namespace clhair
