// frame_types.cpp — names of the dispatch modes and the sums of a frame's stage times
// (include/clhair/frame_types.h, include/clhair/renderer.h).
#include "clhair/frame_types.h"
#include "clhair/error.h"
#include "clhair/renderer.h"

namespace clhair {

const char* dispatchModeName(DispatchMode m) {
  switch (m) {
    case DispatchMode::Auto:
      return "auto";
    case DispatchMode::ReadBack:
      return "readback";
    case DispatchMode::OverLaunch:
      return "overlaunch";
    case DispatchMode::Persistent:
      return "persistent";
  }
  return "?";
}

DispatchMode parseDispatchMode(const std::string& name) {
  for (DispatchMode m : {DispatchMode::Auto, DispatchMode::ReadBack, DispatchMode::OverLaunch,
                         DispatchMode::Persistent})
    if (name == dispatchModeName(m)) return m;
  throw Error("unknown dispatch mode \"" + name +
              "\"; expected auto, readback, overlaunch or persistent");
}

double Frame::stageMs(const std::string& stage) const {
  for (const StageTime& t : timings)
    if (t.stage == stage) return t.ms;
  return 0.0;
}

double Frame::totalMs() const {
  double s = 0.0;
  for (const StageTime& t : timings) s += t.ms;
  return s;
}

}  // namespace clhair
