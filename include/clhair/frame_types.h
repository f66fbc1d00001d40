// frame_types.h — the small value types the renderer's stages and its public API share:
// how a strand dispatch is sized and what one stage cost in a frame. It depends on nothing
// else in clhair, so the launch layer (host/cl/dispatch.h) can use it without reaching up
// to the renderer.
#pragma once

#include <string>

namespace clhair {

// How the strand pass is sized from the LOD pre-pass (DESIGN.md, Atomics and dispatch
// sizing). OpenCL 1.2 has no indirect dispatch, so the host either reads the 4-byte total
// back, launches the host-known upper bound and lets surplus groups leave at once, or
// launches a persistent grid of a few groups per compute unit that walks the strands.
enum class DispatchMode { Auto, ReadBack, OverLaunch, Persistent };
const char* dispatchModeName(DispatchMode m);
DispatchMode parseDispatchMode(const std::string& name);  // auto, readback, overlaunch, persistent

struct StageTime {
  std::string stage;
  double ms = 0.0;  // sum of the stage's profiled dispatches in this frame
  // With RenderOptions::stageCores: wall and process CPU time of the stage's dispatches,
  // each waited for on its own (CPU devices: cpuMs / wallMs = cores the stage used).
  double wallMs = 0.0, cpuMs = 0.0;
};

}  // namespace clhair
