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
  // Kulikov 2025: many grooms at a fixed cost (bench/crowd.cpp), then the crowd's cost
  // against the single default groom at close at the crowd's first size
  bench::CrowdOptions co;
  co.runs = r.opt.runs;
  co.warmup = r.opt.warmup;
  co.quick = r.opt.quick;
  co.pairs = r.opt.quick ? 3 : 9;
  co.refCache = r.opt.refCache;
  co.out = r.opt.out;
  co.maxAlloc = r.dev.info().maxAlloc;
  bench::crowdSection(r.b.renderer, co, r.md, r.report);
  const int cw = r.opt.quick ? 480 : 960, ch = r.opt.quick ? 270 : 540;
  Scene single = framed(r.scenes[0], CameraPreset::Close, cw, ch);
  RenderOptions so;
  so.lod = Toggle::Default;
  so.segmentBudget = 0;
  std::vector<double> wall;
  for (int i = 0; i < r.opt.warmup; ++i) r.b.renderer.render(single, so);
  for (int k = 0; k < r.opt.runs; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    r.b.renderer.render(single, so);
    wall.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  const double one = summarize(wall).median;
  const std::string tag = std::to_string(cw) + "x" + std::to_string(ch);
  const double crowdMs = r.report["crowd"]["sizes"][tag]["budgets"][std::to_string(
      r.report["crowd"]["default_budget"].get<std::uint64_t>())]["screen"]["wall_ms"]
                             .get<double>();
  r.md << "\nThe single default groom at close (" << tag << ", no budget): " << fmt(one, 0)
       << " ms; the crowd under the screen rule at 2 M costs " << fmt(crowdMs / one)
       << "x it (target <= 2x: " << (crowdMs / one <= 2.0 ? "met" : "not met") << ").\n";
  r.report["crowd"]["single_close_ms"] = one;
  r.report["crowd"]["cost_vs_single_close"] = crowdMs / one;
}

void runLodFar(Run& r) {
  bench::LodFarOptions lf;
  lf.scene = std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json";
  lf.width = r.opt.quick ? 320 : r.opt.qualityWidth;
  lf.height = r.opt.quick ? 180 : r.opt.qualityHeight;
  lf.runs = std::max(r.opt.runs, 1);
  lf.warmup = r.opt.warmup;
  bench::lodFarSection(r.b.renderer, lf, r.md, r.report);
}

void runThroughput(Run& r) {
  ThroughputOptions tp = r.opt.tp;
  tp.width = r.opt.tpWidth > 0 ? r.opt.tpWidth : r.opt.width;
  tp.height = r.opt.tpHeight > 0 ? r.opt.tpHeight : r.opt.height;
  if (r.opt.quick) tp.frames = std::min(tp.frames, 12);
  tp.outDir = r.opt.out + "/throughput-frames";
  bench::throughputSection(r.dev, tp, r.md, r.report);
}

}  // namespace clhair::bench
