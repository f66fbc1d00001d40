// dispatch.cpp — the benchmark's dispatch section (clhair_bench --only dispatch):
// Read-back vs over-launch vs persistent sizing of the strand pass.
#include "harness.h"

#include <cstdio>

namespace clhair::bench {

void runDispatch(Run& r) {
  r.md << "\n## Dispatch sizing (groom1, LOD on, MSAA 1): frame wall ms (device-time sum; "
          "strands)\n\n"
          "| mode | close | mid | far |\n|---|---|---|---|\n";
  for (DispatchMode mode :
       {DispatchMode::ReadBack, DispatchMode::OverLaunch, DispatchMode::Persistent}) {
    r.md << "| " << dispatchModeName(mode) << " |";
    for (int d = 0; d < 3; ++d) {
      Scene s = framed(r.scenes[0], r.dists[d], r.opt.width, r.opt.height);
      RenderOptions o;
      o.lod = Toggle::On;
      o.dispatch = mode;
      Measured m = r.b.measure(s, o, false);
      r.md << " " << fmt(m.wall.median) << " (" << fmt(m.total.median) << "; "
           << fmt(stageMedian(m, "strands")) << ") |";
      r.report["dispatch"][dispatchModeName(mode)][r.distNames[d]] = measuredJson(m);
      r.csvRow("dispatch", r.groomNames[0], 1, 1, r.distNames[d],
               r.scenes[0].grooms[0].mesh->strandCount, r.opt.width, r.opt.height,
               dispatchModeName(mode), m);
      std::fprintf(stderr, "dispatch %s %s: wall %.1f ms, device %.1f ms\n", dispatchModeName(mode),
                   r.distNames[d], m.wall.median, m.total.median);
    }
    r.md << "\n";
  }
}

}  // namespace clhair::bench
