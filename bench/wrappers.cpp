// wrappers.cpp — the sections whose code lives in files of their own with option structs of
// their own (crowd.h, lod_far.h, throughput.h): the run's options mapped onto them; and after
// the crowd, its cost against the single default groom at close.
#include "harness.h"

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "crowd.h"
#include "lod_far.h"
#include "throughput.h"

namespace clhair::bench {

void runCrowd(Run& r) {
  const std::string& out = r.opt.out;
  const int runs = r.opt.runs;
  const int warmup = r.opt.warmup;
  const bool quick = r.opt.quick;
  const std::string& refCache = r.opt.refCache;
  Device& dev = r.dev;
  Bench& b = r.b;
  std::ostringstream& md = r.md;
  json& report = r.report;
  const auto& scenes = r.scenes;
  // Kulikov 2025: many grooms at a fixed cost (bench/crowd.cpp), then the crowd's cost
  // against the single default groom at close at the crowd's first size
  bench::CrowdOptions co;
  co.runs = runs;
  co.warmup = warmup;
  co.quick = quick;
  co.pairs = quick ? 3 : 9;
  co.refCache = refCache;
  co.out = out;
  co.maxAlloc = dev.info().maxAlloc;
  bench::crowdSection(b.renderer, co, md, report);
  const int cw = quick ? 480 : 960, ch = quick ? 270 : 540;
  Scene single = framed(scenes[0], CameraPreset::Close, cw, ch);
  RenderOptions so;
  so.lod = -1;
  so.segmentBudget = 0;
  std::vector<double> wall;
  for (int i = 0; i < warmup; ++i) b.renderer.render(single, so);
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    b.renderer.render(single, so);
    wall.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  const double one = summarize(wall).median;
  const std::string tag = std::to_string(cw) + "x" + std::to_string(ch);
  const double crowdMs =
      report["crowd"]["sizes"][tag]["budgets"]["2000000"]["screen"]["wall_ms"].get<double>();
  md << "\nThe single default groom at close (" << tag << ", no budget): " << fmt(one, 0)
     << " ms; the crowd under the screen rule at 2 M costs " << fmt(crowdMs / one)
     << "x it (target <= 2x: " << (crowdMs / one <= 2.0 ? "met" : "not met") << ").\n";
  report["crowd"]["single_close_ms"] = one;
  report["crowd"]["cost_vs_single_close"] = crowdMs / one;
}

void runLodFar(Run& r) {
  const int runs = r.opt.runs;
  const int warmup = r.opt.warmup;
  const bool quick = r.opt.quick;
  const int qualityWidth = r.opt.qualityWidth;
  const int qualityHeight = r.opt.qualityHeight;
  Bench& b = r.b;
  std::ostringstream& md = r.md;
  json& report = r.report;
  bench::LodFarOptions lf;
  lf.scene = std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json";
  lf.width = quick ? 320 : qualityWidth;
  lf.height = quick ? 180 : qualityHeight;
  lf.runs = std::max(runs, 1);
  lf.warmup = warmup;
  bench::lodFarSection(b.renderer, lf, md, report);
}

void runThroughput(Run& r) {
  const std::string& out = r.opt.out;
  const int width = r.opt.width;
  const int height = r.opt.height;
  const bool quick = r.opt.quick;
  const int tpWidth = r.opt.tpWidth;
  const int tpHeight = r.opt.tpHeight;
  Device& dev = r.dev;
  std::ostringstream& md = r.md;
  json& report = r.report;
  ThroughputOptions tp = r.opt.tp;
  tp.width = tpWidth > 0 ? tpWidth : width;
  tp.height = tpHeight > 0 ? tpHeight : height;
  if (quick) tp.frames = std::min(tp.frames, 12);
  tp.outDir = out + "/throughput-frames";
  bench::throughputSection(dev, tp, md, report);
}

}  // namespace clhair::bench
