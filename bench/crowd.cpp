// crowd.cpp — see crowd.h. What the section measures, per image size (960x540 and
// 1920x1080; 480x270 with --quick):
//   - the full render (LOD off, no budget): its wall time, once, and its image, the
//     reference of every FLIP here (kept in --ref-cache when given, with its time);
//   - LOD alone (no budget): wall time (one run) and FLIP against the full render;
//   - budgets of 1, 2, 4 and 8 million segments under the uniform rule and the screen rule
//     (RenderOptions::budgetRule): median wall time of the runs (interleaved, so a load
//     change on the machine hits every variant) and FLIP against the full render;
//   - the targets at the scene's default budget: FLIP(screen) <= 2 FLIP(LOD alone), the
//     screen rule's time within 1.2x the uniform rule's, LOD off >= 10x the screen rule's.
// At 960x540 also: the thinning under the screen rule at the default budget (survivors
// widened in full, widening capped at 2x, width kept: RenderOptions::budgetWidenCap) with
// FLIP and images; the strands and segments of every groom; the single default groom at
// close for the cost comparison; and a 60-frame dolly 6 m into the crowd, where each
// rule's consecutive-frame FLIP is compared with LOD alone's (popping) and every frame's
// segments are checked against the budget.
#include "crowd.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <glm/geometric.hpp>

#include "clhair/error.h"
#include "clhair/image.h"
#include "clhair/scene.h"
#include "metrics/image_metrics.h"

namespace clhair::bench {
namespace {

using nlohmann::json;

std::string fmt(double v, int digits = 2) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Timed {
  Frame frame;
  double wallMs = 0.0;
};

Timed renderTimed(Renderer& r, const Scene& s, const RenderOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  Timed t;
  t.frame = r.render(s, o);
  t.wallMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return t;
}

// A render kept in the cache folder as EXR with its wall time beside it (name.exr,
// name.ms); read back when both are there. The image is always the one read back from the
// file, so a first run and a cached run compare the same pixels.
Image cachedRender(Renderer& r, const Scene& s, const RenderOptions& o, const std::string& cache,
                   const std::string& name, double* wallMs) {
  const std::string dir = cache.empty() ? std::filesystem::temp_directory_path().string() : cache;
  const std::string exr = dir + "/" + name + ".exr", ms = dir + "/" + name + ".ms";
  if (!cache.empty() && std::filesystem::exists(exr) && std::filesystem::exists(ms)) {
    std::ifstream in(ms);
    double t = 0.0;
    if (in >> t) {
      if (wallMs) *wallMs = t;
      return readImage(exr);
    }
  }
  const Timed t = renderTimed(r, s, o);
  writeImage(t.frame.color, exr);
  std::ofstream(ms) << t.wallMs << "\n";
  if (wallMs) *wallMs = t.wallMs;
  Image back = readImage(exr);
  if (cache.empty()) {
    std::filesystem::remove(exr);
    std::filesystem::remove(ms);
  }
  return back;
}

double flip(const Image& ref, const Image& test) { return compareImages(ref, test).flip.mean; }

const char* ruleName(int rule) { return rule == 0 ? "uniform" : "screen"; }
// rule 0 or 1 (the index the tables below use) as RenderOptions::budgetRule
BudgetRule budgetRule(int rule) { return rule == 0 ? BudgetRule::Uniform : BudgetRule::Screen; }

std::string millions(std::uint64_t b) { return fmt(static_cast<double>(b) * 1e-6, 0) + " M"; }

}  // namespace

void crowdSection(Renderer& renderer, const CrowdOptions& opt, std::ostringstream& md,
                  json& report) {
  Scene crowd =
      loadScene(std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/crowd.json", opt.maxAlloc);
  // the scene's own budget, one of the swept ones at every size (a default would depend on
  // the size)
  if (!crowd.segmentBudget) throw Error("crowd.json gives no \"segment_budget\"");
  const std::uint64_t defaultBudget = *crowd.segmentBudget;
  const std::vector<std::pair<int, int>> sizes =
      opt.quick ? std::vector<std::pair<int, int>>{{480, 270}}
                : std::vector<std::pair<int, int>>{{960, 540}, {1920, 1080}};
  const std::vector<std::uint64_t> budgets = {1000000, 2000000, 4000000, 8000000};
  if (!opt.refCache.empty()) std::filesystem::create_directories(opt.refCache);
  if (!opt.out.empty()) std::filesystem::create_directories(opt.out);
  std::ofstream csv(opt.out + "/crowd_budget.csv");
  csv << "width,height,variant,rule,budget,wall_ms,flip\n";
  json& rep = report["crowd"];
  rep["grooms"] = crowd.grooms.size();
  rep["default_budget"] = defaultBudget;

  md << "\n## Crowd (assets/scenes/crowd.json, " << crowd.grooms.size()
     << " groom instances): the segment budget's rules against the full render\n\n"
     << "Wall-clock medians of " << opt.runs
     << " interleaved runs (LOD off and LOD alone: one run); FLIP against the full render "
        "(LOD off, no budget).\n";
  for (const auto& [w, h] : sizes) {
    Scene s = crowd;
    s.width = w;
    s.height = h;
    const std::string tag = std::to_string(w) + "x" + std::to_string(h);
    RenderOptions full;
    full.lod = Toggle::Off;
    full.segmentBudget = 0;
    double fullMs = 0.0, lodMs = 0.0;
    const Image ref = cachedRender(renderer, s, full, opt.refCache, "crowd_full_" + tag, &fullMs);
    RenderOptions lodOnly;
    lodOnly.lod = Toggle::On;
    lodOnly.segmentBudget = 0;
    const Image lodImage =
        cachedRender(renderer, s, lodOnly, opt.refCache, "crowd_lod_" + tag, &lodMs);
    const double lodFlip = flip(ref, lodImage);
    std::fprintf(stderr, "crowd %s: full %.0f ms, LOD alone %.0f ms, FLIP %.4f\n", tag.c_str(),
                 fullMs, lodMs, lodFlip);
    struct Variant {
      int rule;
      std::uint64_t budget;
      std::vector<double> wall;
      Image image;
      FrameStats stats;
    };
    std::vector<Variant> vs;
    for (std::uint64_t b : budgets)
      for (int rule : {0, 1}) vs.push_back({rule, b, {}, {}, {}});
    for (int i = 0; i < opt.warmup; ++i) {  // compiles, uploads
      RenderOptions o;
      o.segmentBudget = static_cast<std::int64_t>(defaultBudget);
      renderer.render(s, o);
    }
    for (int run = 0; run < opt.runs; ++run)
      for (Variant& v : vs) {
        RenderOptions o;
        o.lod = Toggle::On;
        o.segmentBudget = static_cast<std::int64_t>(v.budget);
        o.budgetRule = budgetRule(v.rule);
        Timed t = renderTimed(renderer, s, o);
        v.wall.push_back(t.wallMs);
        v.stats = t.frame.stats;
        v.image = std::move(t.frame.color);
        std::fprintf(stderr, "crowd %s: %s %s: %.0f ms\n", tag.c_str(), ruleName(v.rule),
                     millions(v.budget).c_str(), t.wallMs);
      }
    md << "\n### " << tag << "\n\nLOD off (the full render): " << fmt(fullMs, 0)
       << " ms. LOD alone: " << fmt(lodMs, 0) << " ms, FLIP " << fmt(lodFlip, 4) << ".\n\n"
       << "| budget | uniform ms | uniform FLIP | screen ms | screen FLIP | screen segments |\n"
       << "|---|---|---|---|---|---|\n";
    json& rs = rep["sizes"][tag];
    rs["full_ms"] = fullMs;
    rs["lod_ms"] = lodMs;
    rs["lod_flip"] = lodFlip;
    csv << w << "," << h << ",full,,0," << fullMs << ",0\n";
    csv << w << "," << h << ",lod,,0," << lodMs << "," << lodFlip << "\n";
    std::map<std::pair<int, std::uint64_t>, std::pair<double, double>> cell;  // ms, FLIP
    for (Variant& v : vs) {
      const double ms = median(v.wall), f = flip(ref, v.image);
      cell[{v.rule, v.budget}] = {ms, f};
      csv << w << "," << h << ",budget," << ruleName(v.rule) << "," << v.budget << "," << ms << ","
          << f << std::endl;  // flushed: an interrupted run keeps its rows
      std::fprintf(stderr, "crowd %s: %s %s: FLIP %.4f\n", tag.c_str(), ruleName(v.rule),
                   millions(v.budget).c_str(), f);
      rs["budgets"][std::to_string(v.budget)][ruleName(v.rule)] = {
          {"wall_ms", ms}, {"flip", f}, {"segments", v.stats.segmentsPlanned}};
      if (!opt.out.empty() && v.budget == defaultBudget && w == sizes.front().first)
        writeImage(v.image, opt.out + "/crowd_" + ruleName(v.rule) + ".png");
    }
    for (std::uint64_t b : budgets) {
      const auto u = cell[{0, b}], sc = cell[{1, b}];
      std::uint64_t segs = 0;
      for (const Variant& v : vs)
        if (v.rule == 1 && v.budget == b) segs = v.stats.segmentsPlanned;
      md << "| " << millions(b) << " | " << fmt(u.first, 0) << " | " << fmt(u.second, 4) << " | "
         << fmt(sc.first, 0) << " | " << fmt(sc.second, 4) << " | " << segs << " |\n";
    }
    // the frame time at the default budget: interleaved pairs (the order alternating), the
    // median of the pairs' ratios, wall clock and device time, and the stages' medians
    std::vector<double> pairWall[2], pairDevice[2], wallRatio, deviceRatio;
    std::map<std::string, std::vector<double>> stages[2];
    for (int pr = 0; pr < opt.pairs; ++pr) {
      double wall[2] = {0.0, 0.0}, device[2] = {0.0, 0.0};
      for (int j = 0; j < 2; ++j) {
        const int rule = (pr % 2 == 0) ? j : 1 - j;
        RenderOptions o;
        o.lod = Toggle::On;
        o.segmentBudget = static_cast<std::int64_t>(defaultBudget);
        o.budgetRule = budgetRule(rule);
        const Timed t = renderTimed(renderer, s, o);
        wall[rule] = t.wallMs;
        device[rule] = t.frame.totalMs();
        for (const StageTime& st : t.frame.timings) stages[rule][st.stage].push_back(st.ms);
      }
      for (int rule : {0, 1}) {
        pairWall[rule].push_back(wall[rule]);
        pairDevice[rule].push_back(device[rule]);
      }
      wallRatio.push_back(wall[1] / wall[0]);
      deviceRatio.push_back(device[1] / device[0]);
    }
    md << "\nFrame time at " << millions(defaultBudget) << ", " << opt.pairs
       << " interleaved pairs: uniform " << fmt(median(pairWall[0]), 0) << " ms wall ("
       << fmt(median(pairDevice[0]), 0) << " device), screen " << fmt(median(pairWall[1]), 0)
       << " ms wall (" << fmt(median(pairDevice[1]), 0) << " device); median ratio of the pairs "
       << fmt(median(wallRatio)) << " wall, " << fmt(median(deviceRatio)) << " device.\n\n"
       << "| stage | uniform ms | screen ms |\n|---|---|---|\n";
    for (const auto& [stage, v] : stages[0]) {
      md << "| " << stage << " | " << fmt(median(v), 0) << " | " << fmt(median(stages[1][stage]), 0)
         << " |\n";
      rs["stages"][stage] = {{"uniform_ms", median(v)}, {"screen_ms", median(stages[1][stage])}};
    }
    rs["pairs"] = {{"uniform_wall_ms", median(pairWall[0])},
                   {"screen_wall_ms", median(pairWall[1])},
                   {"uniform_device_ms", median(pairDevice[0])},
                   {"screen_device_ms", median(pairDevice[1])},
                   {"wall_ratio", median(wallRatio)},
                   {"device_ratio", median(deviceRatio)},
                   {"wall_ratios", wallRatio}};
    const auto u = cell[{0, defaultBudget}], sc = cell[{1, defaultBudget}];
    const double flipRatio = lodFlip > 0.0 ? sc.second / lodFlip : 0.0;
    const double timeRatio = median(wallRatio);
    const double speedup = median(pairWall[1]) > 0.0 ? fullMs / median(pairWall[1]) : 0.0;
    md << "\nAt the default budget (" << millions(defaultBudget) << "): FLIP of the screen rule "
       << fmt(sc.second, 4) << " = " << fmt(flipRatio)
       << "x LOD alone's (target <= 2x: " << (flipRatio <= 2.0 ? "met" : "not met")
       << "; the uniform rule " << fmt(u.second, 4) << "); its frame " << fmt(timeRatio)
       << "x the uniform rule's (target <= 1.2x: " << (timeRatio <= 1.2 ? "met" : "not met")
       << "); LOD off " << fmt(speedup)
       << "x slower (target >= 10x: " << (speedup >= 10.0 ? "met" : "not met") << ").\n";
    rs["targets"] = {{"flip_vs_lod", flipRatio},
                     {"time_vs_uniform", timeRatio},
                     {"speedup_vs_lod_off", speedup}};
    std::fprintf(stderr, "crowd %s: FLIP %.4f (%.2fx LOD), time %.2fx uniform, %.1fx vs LOD off\n",
                 tag.c_str(), sc.second, flipRatio, timeRatio, speedup);
    if (w != sizes.front().first) continue;

    // thinning: widened in full, widening capped, width kept
    md << "\nThinning under the screen rule at " << millions(defaultBudget) << ", " << tag
       << " (survivors widened by N_LOD / N' in full, at most 2x, or not at all):\n\n"
       << "| thinning | ms | FLIP |\n|---|---|---|\n";
    for (const auto& [name, cap] : std::vector<std::pair<std::string, float>>{
             {"widened (default)", 0.0f}, {"widening capped at 2x", 2.0f}, {"width kept", 1.0f}}) {
      RenderOptions o;
      o.lod = Toggle::On;
      o.segmentBudget = static_cast<std::int64_t>(defaultBudget);
      o.budgetWidenCap = cap;
      std::vector<double> wall;
      Image image;
      for (int run = 0; run < opt.runs; ++run) {
        Timed t = renderTimed(renderer, s, o);
        wall.push_back(t.wallMs);
        image = std::move(t.frame.color);
      }
      const double f = flip(ref, image);
      md << "| " << name << " | " << fmt(median(wall), 0) << " | " << fmt(f, 4) << " |\n";
      rep["thinning"][name] = {{"wall_ms", median(wall)}, {"flip", f}, {"widen_cap", cap}};
      if (!opt.out.empty() && cap > 0.0f)
        writeImage(image, opt.out + "/crowd_thin_cap" + fmt(cap, 0) + ".png");
    }
    if (!opt.out.empty()) writeImage(ref, opt.out + "/crowd_full.png");

    // every groom under the screen rule at the default budget
    for (const Variant& v : vs) {
      if (v.rule != 1 || v.budget != defaultBudget) continue;
      md << "\nPer groom, screen rule at " << millions(defaultBudget) << ", " << tag
         << " (strands / segments / share of segments / screen box in pixels; h: every other "
            "control point):\n\n| groom | strands | segments | share | box "
            "|\n|---|---|---|---|---|\n";
      for (const GroomDrawStats& g : v.stats.grooms) {
        md << "| " << g.name << (g.halved ? " (h)" : "") << " | " << g.strands << " | "
           << g.segments << " | " << g.share << " | " << fmt(g.screenArea, 0) << " |\n";
        rep["per_groom"].push_back({{"name", g.name},
                                    {"strands", g.strands},
                                    {"segments", g.segments},
                                    {"share", g.share},
                                    {"requested", g.requested},
                                    {"floor", g.floor},
                                    {"box", g.screenArea},
                                    {"halved", g.halved}});
      }
    }
  }

  // the dolly: LOD alone against both rules at the default budget, frame to frame
  const int frames = opt.quick ? 12 : 60;
  const auto [dw, dh] = sizes.front();
  const std::string dtag = std::to_string(dw) + "x" + std::to_string(dh);
  const Camera start = crowd.camera;
  const glm::vec3 dir = glm::normalize(start.target - start.position);
  std::vector<double> popLod, popRule[2];
  Image prevLod, prevRule[2];
  std::uint64_t worstPlanned = 0, worstRaster = 0;
  int overBudget = 0;
  for (int k = 0; k < frames; ++k) {
    Scene s = crowd;
    s.width = dw;
    s.height = dh;
    s.camera.position = start.position + dir * (6.0f * static_cast<float>(k) / (frames - 1));
    RenderOptions lodOnly;
    lodOnly.lod = Toggle::On;
    lodOnly.segmentBudget = 0;
    char name[64];
    std::snprintf(name, sizeof name, "crowd_dolly_lod_%s_%d_%02d", dtag.c_str(), frames, k);
    Image lodImage = cachedRender(renderer, s, lodOnly, opt.refCache, name, nullptr);
    if (k > 0) popLod.push_back(flip(prevLod, lodImage));
    prevLod = std::move(lodImage);
    for (int rule : {0, 1}) {
      RenderOptions o;
      o.lod = Toggle::On;
      o.segmentBudget = static_cast<std::int64_t>(defaultBudget);
      o.budgetRule = budgetRule(rule);
      o.rasterStats = rule == 1;
      Frame f = renderer.render(s, o);
      if (rule == 1) {
        worstPlanned = std::max(worstPlanned, f.stats.segmentsPlanned);
        worstRaster = std::max(worstRaster, f.stats.segmentsDrawn);
        if (f.stats.segmentsPlanned > defaultBudget || f.stats.segmentsDrawn > defaultBudget)
          ++overBudget;
      }
      if (k > 0) popRule[rule].push_back(flip(prevRule[rule], f.color));
      prevRule[rule] = std::move(f.color);
    }
    std::fprintf(stderr, "crowd dolly %d/%d\n", k + 1, frames);
  }
  md << "\n"
     << frames << "-frame dolly (6 m toward the target, " << dtag << ", " << millions(defaultBudget)
     << "): FLIP between consecutive frames, each rule against LOD alone (popping = the "
        "rule's minus LOD alone's, per pair of frames):\n\n"
     << "| render | mean FLIP | max FLIP | popping mean | popping max |\n|---|---|---|---|---|\n";
  const double lodMean = popLod.empty() ? 0.0 : [&] {
    double s = 0.0;
    for (double v : popLod) s += v;
    return s / popLod.size();
  }();
  md << "| LOD alone | " << fmt(lodMean, 4) << " | "
     << fmt(popLod.empty() ? 0.0 : *std::max_element(popLod.begin(), popLod.end()), 4)
     << " | | |\n";
  for (int rule : {0, 1}) {
    double sum = 0.0, mx = 0.0, popSum = 0.0, popMax = -1.0;
    for (std::size_t i = 0; i < popRule[rule].size(); ++i) {
      sum += popRule[rule][i];
      mx = std::max(mx, popRule[rule][i]);
      const double d = popRule[rule][i] - popLod[i];
      popSum += d;
      popMax = std::max(popMax, d);
    }
    const double n = std::max<double>(1.0, static_cast<double>(popRule[rule].size()));
    md << "| " << ruleName(rule) << " rule | " << fmt(sum / n, 4) << " | " << fmt(mx, 4) << " | "
       << fmt(popSum / n, 4) << " | " << fmt(popMax, 4) << " |\n";
    rep["dolly"][ruleName(rule)] = {{"flip_mean", sum / n},
                                    {"flip_max", mx},
                                    {"popping_mean", popSum / n},
                                    {"popping_max", popMax},
                                    {"pairs", popRule[rule]}};
    if (rule == 1)
      md << "\nPopping of the screen rule (target <= 0.005, mean and worst pair): mean "
         << fmt(popSum / n, 4) << ", worst " << fmt(popMax, 4) << " ("
         << (popSum / n <= 0.005 && popMax <= 0.005 ? "met" : "not met") << ").\n";
  }
  rep["dolly"]["lod"] = {{"flip_mean", lodMean}, {"pairs", popLod}};
  md << "Screen rule along the dolly: at most " << worstPlanned << " segments scheduled and "
     << worstRaster << " counted by the raster in a frame; frames over the budget: " << overBudget
     << " (target 0: " << (overBudget == 0 ? "met" : "not met") << ").\n";
  rep["dolly"]["max_segments_scheduled"] = worstPlanned;
  rep["dolly"]["max_segments_rastered"] = worstRaster;
  rep["dolly"]["frames_over_budget"] = overBudget;
}

}  // namespace clhair::bench
