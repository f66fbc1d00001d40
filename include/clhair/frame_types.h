// frame_types.h — the small value types the renderer's stages and its public API share:
// how a strand dispatch is sized, what one stage cost in a frame, and the kinds of the
// RenderOptions (clhair/renderer.h) that may be left to the scene. It depends on nothing
// else in clhair, so the launch layer (host/cl/dispatch.h) can use it without reaching up
// to the renderer.
#pragma once

#include <cstdint>
#include <string>

namespace clhair {

// How the strand pass is sized from the LOD pre-pass (DESIGN.md, Atomics and dispatch
// sizing). OpenCL 1.2 has no indirect dispatch, so the host either reads the 4-byte total
// back, launches the host-known upper bound and lets surplus groups leave at once, or
// launches a persistent grid of a few groups per compute unit that walks the strands.
enum class DispatchMode { Auto, ReadBack, OverLaunch, Persistent };
const char* dispatchModeName(DispatchMode m);
DispatchMode parseDispatchMode(const std::string& name);  // auto, readback, overlaunch, persistent

// An on/off option that may be left open. Default: as the scene, the groom or the quality
// level says (each RenderOptions field's comment says which).
enum class Toggle : std::int8_t { Default = -1, Off = 0, On = 1 };
// Whether `t` is on, where Default takes `otherwise` (what the scene, groom or level says).
constexpr bool isOn(Toggle t, bool otherwise) {
  return t == Toggle::Default ? otherwise : t == Toggle::On;
}

// The path of quality final's passes (RenderOptions::finalPath): Default, the measured
// default (kFinalPassGood in clhair/progressive.h); OneSample, one sample per pixel without a
// filter; Good, the good level's path.
enum class FinalPath { Default, OneSample, Good };

// How the segment budget shares the segments out (RenderOptions::budgetRule; DESIGN.md "The
// segment budget"): Uniform, one factor for every groom; Screen, each groom's share by its
// screen need; Default, the screen rule.
enum class BudgetRule { Default, Uniform, Screen };

struct StageTime {
  std::string stage;
  double ms = 0.0;  // sum of the stage's profiled dispatches in this frame
  // With RenderOptions::stageCores: wall and process CPU time of the stage's dispatches,
  // each waited for on its own (CPU devices: cpuMs / wallMs = cores the stage used).
  double wallMs = 0.0, cpuMs = 0.0;
};

}  // namespace clhair
