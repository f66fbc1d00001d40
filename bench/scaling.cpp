// scaling.cpp — the benchmark's scaling section (clhair_bench --only scaling):
// Strands 16k -> 256k at a fixed view; resolution 720p -> 4K at a fixed groom.
#include "harness.h"

#include <cstdio>
#include <memory>
#include <vector>

namespace clhair::bench {

void runScaling(Run& r) {
  const bool quick = r.opt.quick;
  Bench& b = r.b;
  std::ostringstream& md = r.md;
  json& report = r.report;
  const auto& scenes = r.scenes;
  const auto& groomNames = r.groomNames;
  auto csvRow = [&r](auto&&... a) { r.csvRow(a...); };
  md << "\n## Scaling (groom1 at mid, LOD off, MSAA 1)\n\n| strands | width x height | frame "
        "ms | strand pass ms | "
        "segments | ms per M segments | ms per megapixel |\n|---|---|---|---|---|---|---|\n";
  std::vector<std::int64_t> counts =
      quick ? std::vector<std::int64_t>{16000, 64000}
            : std::vector<std::int64_t>{16000, 32000, 64000, 128000, 256000};
  std::vector<std::pair<int, int>> sizes =
      quick
          ? std::vector<std::pair<int, int>>{{1280, 720}, {1920, 1080}}
          : std::vector<std::pair<int, int>>{{1280, 720}, {1920, 1080}, {2560, 1440}, {3840, 2160}};
  auto row = [&](std::int64_t n, int w, int h) {
    Scene s = framed(scenes[0], CameraPreset::Mid, w, h);
    HairMesh m = *s.grooms[0].mesh;
    m.strandCount = n;
    s.grooms[0].mesh = std::make_shared<const HairMesh>(m);
    RenderOptions o;
    o.lod = 0;
    Measured r = b.measure(s, o);
    double strandsMs = stageMedian(r, "strands");
    double perSeg = r.counts.segmentsDrawn ? strandsMs / (r.counts.segmentsDrawn * 1e-6) : 0.0;
    double perMp = r.total.median / (w * h * 1e-6);
    md << "| " << n << " | " << w << "x" << h << " | " << fmt(r.total.median) << " | "
       << fmt(strandsMs) << " | " << r.counts.segmentsDrawn << " | " << fmt(perSeg) << " | "
       << fmt(perMp) << " |\n";
    json j = measuredJson(r);
    j["strands_target"] = n;
    j["width"] = w;
    j["height"] = h;
    j["ms_per_million_segments"] = perSeg;
    j["ms_per_megapixel"] = perMp;
    report["scaling"].push_back(j);
    csvRow("scaling", groomNames[0], 0, 1, "mid", n, w, h, "auto", r);
    std::fprintf(stderr, "scaling %lld strands %dx%d: %.1f ms\n", static_cast<long long>(n), w, h,
                 r.total.median);
  };
  for (std::int64_t n : counts) row(n, 1920, 1080);
  for (auto [w, h] : sizes) row(127000, w, h);
}

}  // namespace clhair::bench
