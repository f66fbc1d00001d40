// dispatch.cpp — the benchmark's dispatch section (clhair_bench --only dispatch):
// Read-back vs over-launch vs persistent sizing of the strand pass.
#include "harness.h"

#include <cstdio>

namespace clhair::bench {

void runDispatch(Run& r) {
  const int width = r.opt.width;
  const int height = r.opt.height;
  Bench& b = r.b;
  std::ostringstream& md = r.md;
  json& report = r.report;
  const auto& scenes = r.scenes;
  const auto& groomNames = r.groomNames;
  const auto& dists = r.dists;
  const auto& distNames = r.distNames;
  auto csvRow = [&r](auto&&... a) { r.csvRow(a...); };
  md << "\n## Dispatch sizing (groom1, LOD on, MSAA 1): frame wall ms (device-time sum; "
        "strands)\n\n"
        "| mode | close | mid | far |\n|---|---|---|---|\n";
  for (DispatchMode mode :
       {DispatchMode::ReadBack, DispatchMode::OverLaunch, DispatchMode::Persistent}) {
    md << "| " << dispatchModeName(mode) << " |";
    for (int d = 0; d < 3; ++d) {
      Scene s = framed(scenes[0], dists[d], width, height);
      RenderOptions o;
      o.lod = 1;
      o.dispatch = mode;
      Measured m = b.measure(s, o, false);
      md << " " << fmt(m.wall.median) << " (" << fmt(m.total.median) << "; "
         << fmt(stageMedian(m, "strands")) << ") |";
      report["dispatch"][dispatchModeName(mode)][distNames[d]] = measuredJson(m);
      csvRow("dispatch", groomNames[0], 1, 1, distNames[d], scenes[0].grooms[0].mesh->strandCount,
             width, height, dispatchModeName(mode), m);
      std::fprintf(stderr, "dispatch %s %s: wall %.1f ms, device %.1f ms\n", dispatchModeName(mode),
                   distNames[d], m.wall.median, m.total.median);
    }
    md << "\n";
  }
}

}  // namespace clhair::bench
