// crowd.h — the benchmark's crowd section (clhair_bench --only crowd): assets/scenes/
// crowd.json (100 groom instances) under the segment budget, both rules, against the full
// render (bench/README.md, "Crowd").
#pragma once

#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "clhair/renderer.h"

namespace clhair::bench {

struct CrowdOptions {
  int runs = 3, warmup = 1;
  int pairs = 9;         // interleaved uniform / screen pairs at the default budget (timing)
  bool quick = false;    // 480x270 only, one budget sweep, a 12-frame dolly
  std::string refCache;  // folder for the full renders and the LOD-only dolly (kept)
  std::string out;       // folder for the images (crowd_*.png)
  std::size_t maxAlloc = 0;
};

// Runs the section: appends its markdown to md and its numbers to report["crowd"], and
// writes crowd_budget.csv (size, rule, budget, ms, FLIP) into options.out for
// scripts/plot-crowd-budget.py.
void crowdSection(Renderer& renderer, const CrowdOptions& options, std::ostringstream& md,
                  nlohmann::json& report);

}  // namespace clhair::bench
