// budget_stage.cpp — see budget_stage.h.
#include "stages/budget_stage.h"

#include <string>

#include "clhair/gpu_types.h"
#include "stages/lod_stage.h"

namespace clhair {

namespace {
const std::string kOptions = "-DSCAN_WG=" + std::to_string(LodStage::kScanWorkGroup);
}  // namespace

BudgetStage::BudgetStage(Device::Impl& dev)
    : dev_(dev),
      measure_(dev.kernel("budget.cl", "budget_measure", kOptions)),
      plan_(dev.kernel("budget.cl", "budget_plan", kOptions)),
      apply_(dev.kernel("budget.cl", "budget_apply", kOptions)) {}

void BudgetStage::enqueue(const Params& p, Profiler* profiler) {
  const std::size_t D = p.draws;
  const cl::NDRange wg(LodStage::kScanWorkGroup);
  const cl::NDRange perDraw(D * LodStage::kScanWorkGroup);
  const std::size_t tableBytes = D * sizeof(gpu::ClhBudgetDraw);
  const std::size_t stateBytes = p.stateWords * sizeof(cl_uint);
  KernelArgs(measure_, "lod")
      .buffer("draws", *p.table, tableBytes)
      .value("draw count", static_cast<cl_uint>(D))
      .buffer("LOD records", *p.arena, p.arenaBytes)
      .buffer("counts and offsets", *p.arena, p.arenaBytes)
      .buffer("state", *p.state, stateBytes);
  dispatch(dev_, measure_, "lod", perDraw, wg, profiler);
  KernelArgs(plan_, "lod")
      .buffer("draws", *p.table, tableBytes)
      .value("draw count", static_cast<cl_uint>(D))
      .buffer("LOD records", *p.arena, p.arenaBytes)
      .buffer("counts and offsets", *p.arena, p.arenaBytes)
      .value("budget", static_cast<cl_ulong>(p.budget))
      .buffer("rule", *p.rule, sizeof(gpu::ClhBudgetRule))
      .buffer("state", *p.state, stateBytes);
  dispatch(dev_, plan_, "lod", wg, wg, profiler);
  KernelArgs(apply_, "lod")
      .buffer("draws", *p.table, tableBytes)
      .value("draw count", static_cast<cl_uint>(D))
      .buffer("LOD records", *p.arena, p.arenaBytes)
      .buffer("counts and offsets", *p.arena, p.arenaBytes)
      .buffer("rule", *p.rule, sizeof(gpu::ClhBudgetRule))
      .buffer("state", *p.state, stateBytes);
  dispatch(dev_, apply_, "lod", perDraw, wg, profiler);
}

}  // namespace clhair
