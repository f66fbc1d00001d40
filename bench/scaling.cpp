// scaling.cpp — the benchmark's scaling section (clhair_bench --only scaling):
// Strands 16k -> 256k at a fixed view; resolution 720p -> 4K at a fixed groom.
#include "harness.h"

#include <cstdio>
#include <memory>
#include <vector>

namespace clhair::bench {

void runScaling(Run& r) {
  r.md << "\n## Scaling (groom1 at mid, LOD off, MSAA 1)\n\n| strands | width x height | frame "
          "ms | strand pass ms | "
          "segments | ms per M segments | ms per megapixel |\n|---|---|---|---|---|---|---|\n";
  std::vector<std::int64_t> counts =
      r.opt.quick ? std::vector<std::int64_t>{16000, 64000}
                  : std::vector<std::int64_t>{16000, 32000, 64000, 128000, 256000};
  std::vector<std::pair<int, int>> sizes =
      r.opt.quick
          ? std::vector<std::pair<int, int>>{{1280, 720}, {1920, 1080}}
          : std::vector<std::pair<int, int>>{{1280, 720}, {1920, 1080}, {2560, 1440}, {3840, 2160}};
  auto row = [&](std::int64_t n, int w, int h) {
    Scene s = framed(r.scenes[0], CameraPreset::Mid, w, h);
    HairMesh m = *s.grooms[0].mesh;
    m.strandCount = n;
    s.grooms[0].mesh = std::make_shared<const HairMesh>(m);
    RenderOptions o;
    o.lod = Toggle::Off;
    Measured res = r.b.measure(s, o);
    double strandsMs = stageMedian(res, "strands");
    double perSeg = res.counts.segmentsDrawn ? strandsMs / (res.counts.segmentsDrawn * 1e-6) : 0.0;
    double perMp = res.total.median / (w * h * 1e-6);
    r.md << "| " << n << " | " << w << "x" << h << " | " << fmt(res.total.median) << " | "
         << fmt(strandsMs) << " | " << res.counts.segmentsDrawn << " | " << fmt(perSeg) << " | "
         << fmt(perMp) << " |\n";
    json j = measuredJson(res);
    j["strands_target"] = n;
    j["width"] = w;
    j["height"] = h;
    j["ms_per_million_segments"] = perSeg;
    j["ms_per_megapixel"] = perMp;
    r.report["scaling"].push_back(j);
    r.csvRow("scaling", r.groomNames[0], 0, 1, "mid", n, w, h, "auto", res);
    std::fprintf(stderr, "scaling %lld strands %dx%d: %.1f ms\n", static_cast<long long>(n), w, h,
                 res.total.median);
  };
  for (std::int64_t n : counts) row(n, 1920, 1080);
  for (auto [w, h] : sizes) row(127000, w, h);
}

}  // namespace clhair::bench
