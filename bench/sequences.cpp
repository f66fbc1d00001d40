// sequences.cpp — the benchmark's sequences section (clhair_bench --only sequences):
// A shot of the default groom in wind (assets/scenes/wind.json, 720p, --seq-frames frames, 120 by
// default) rendered frame after frame in one process: the time per frame after the first against
// the same scene as a still frame (interleaved; wall and process CPU time), start-up paid once; two
// views of one assembly against one view, on a still frame (maps kept) and on a frame of the shot
// (maps rebuilt), --view-pairs interleaved pairs each, with every pair's ratio and a per-stage
// split; the cost of the motion layer; the warped-mask IoU of the motion vectors
// (clhair::motionWarpIoU) on the wind shot and on a slow turntable.
#include "harness.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <glm/trigonometric.hpp>

#include "cl/dispatch.h"
#include "clhair/aov.h"

namespace clhair::bench {

void runSequences(Run& r) {
  Scene shot = loadScene(std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/wind.json");
  const int frames = r.opt.quick ? std::min(r.opt.seqFrames, 8) : r.opt.seqFrames;
  auto ms = [](std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  // the shot frame after frame (scene evaluation included: what `--frames` does), and
  // interleaved with it the still frame: frame 1 of the shot rendered again right after
  // itself (its deep opacity maps kept, as for any still) and after a shot frame (maps
  // rebuilt, as every frame of a moving groom must), every 4th shot frame. Each render's
  // process CPU time (every core) is kept beside its wall time: on a shared machine the
  // wall clock swings with the load, the CPU time far less; each rebuilt still is
  // compared with the shot frame right before it (interleaved pairs).
  const Scene still = sceneAtFrame(shot, 1.0);
  std::vector<double> shotMs, stillKept, stillCold, shotCpu, keptCpu, coldCpu, pairCpu;
  double firstMs = 0.0;
  for (int f = 1; f <= frames; ++f) {
    double c0 = processCpuMs();
    auto t0 = std::chrono::steady_clock::now();
    const Scene s = sceneAtFrame(shot, static_cast<double>(f));
    r.b.renderer.render(s, RenderOptions{});
    const double t = ms(t0), tc = processCpuMs() - c0;
    if (f == 1) {
      firstMs = t;
      continue;
    }
    shotMs.push_back(t);
    shotCpu.push_back(tc);
    if (f % 4 == 2) {
      c0 = processCpuMs();
      t0 = std::chrono::steady_clock::now();
      r.b.renderer.render(still, RenderOptions{});
      stillCold.push_back(ms(t0));
      coldCpu.push_back(processCpuMs() - c0);
      pairCpu.push_back(tc / coldCpu.back());
      c0 = processCpuMs();
      t0 = std::chrono::steady_clock::now();
      r.b.renderer.render(still, RenderOptions{});
      stillKept.push_back(ms(t0));
      keptCpu.push_back(processCpuMs() - c0);
    }
  }
  const Stats shotS = summarize(shotMs), keptS = summarize(stillKept), coldS = summarize(stillCold);
  const Stats shotC = summarize(shotCpu), keptC = summarize(keptCpu), coldC = summarize(coldCpu),
              pairC = summarize(pairCpu);
  double mean = 0.0;
  for (double v : shotMs) mean += v / static_cast<double>(shotMs.size());
  auto cpuCells = [&](const Stats& c, const Stats& ref) {
    return " | " + fmt(c.median, 0) + " | " + fmt(c.min, 0) + " | " + fmt(c.max, 0) + " | " +
           fmt(c.median / ref.median, 3) + "x |\n";
  };
  r.md << "\n## Sequences (assets/scenes/wind.json: the default groom in wind, " << still.width
       << "x" << still.height << ", " << frames
       << " frames in one process)\n\nStart-up (device, kernel compilation) " << fmt(r.compileMs, 0)
       << " ms, once per process; first frame " << fmt(firstMs, 0)
       << " ms.\n\n| | renders | median ms | min | max | vs still (maps kept) | CPU ms median "
          "| min | max | CPU vs still (maps kept) |\n|---|---|---|---|---|---|---|---|---|---|\n"
       << "| shot frames 2.." << frames << " (mean " << fmt(mean, 0) << ") | " << shotMs.size()
       << " | " << fmt(shotS.median, 0) << " | " << fmt(shotS.min, 0) << " | " << fmt(shotS.max, 0)
       << " | " << fmt(shotS.median / keptS.median, 3) << "x" << cpuCells(shotC, keptC)
       << "| still frame, maps kept | " << stillKept.size() << " | " << fmt(keptS.median, 0)
       << " | " << fmt(keptS.min, 0) << " | " << fmt(keptS.max, 0) << " | 1x"
       << cpuCells(keptC, keptC) << "| still frame, maps rebuilt | " << stillCold.size() << " | "
       << fmt(coldS.median, 0) << " | " << fmt(coldS.min, 0) << " | " << fmt(coldS.max, 0) << " | "
       << fmt(coldS.median / keptS.median, 3) << "x" << cpuCells(coldC, keptC)
       << "\nShot frame against the still frame that rebuilds its "
       << "maps: " << fmt(shotS.median / coldS.median, 3) << "x wall, "
       << fmt(shotC.median / coldC.median, 3) << "x process CPU (ratio of medians); pair by "
       << "pair (each rebuilt still against the shot frame before it, CPU) median "
       << fmt(pairC.median, 3) << "x, min " << fmt(pairC.min, 3) << "x, max " << fmt(pairC.max, 3)
       << "x over " << pairCpu.size() << " pairs (target within 5 %).\n";
  r.report["sequences"]["frames"] = frames;
  r.report["sequences"]["first_frame_ms"] = firstMs;
  r.report["sequences"]["shot_frame_ms"] = {
      {"median", shotS.median}, {"mean", mean}, {"min", shotS.min}, {"max", shotS.max}};
  r.report["sequences"]["still_maps_kept_ms"] = keptS.median;
  r.report["sequences"]["still_maps_rebuilt_ms"] = coldS.median;
  r.report["sequences"]["shot_vs_still"] = shotS.median / keptS.median;
  r.report["sequences"]["shot_vs_still_rebuilt"] = shotS.median / coldS.median;
  r.report["sequences"]["shot_frame_cpu_ms"] = shotC.median;
  r.report["sequences"]["still_maps_kept_cpu_ms"] = keptC.median;
  r.report["sequences"]["still_maps_rebuilt_cpu_ms"] = coldC.median;
  r.report["sequences"]["shot_vs_still_rebuilt_cpu"] = shotC.median / coldC.median;
  r.report["sequences"]["shot_vs_still_rebuilt_cpu_pairs"] = {
      {"median", pairC.median}, {"min", pairC.min}, {"max", pairC.max}};
  std::fprintf(stderr,
               "sequences: first %.0f ms, shot median %.0f ms, still kept %.0f ms, still "
               "rebuilt %.0f ms (%.3fx / %.3fx); CPU shot %.0f ms, still rebuilt %.0f ms "
               "(%.3fx, pairs %.3f-%.3fx)\n",
               firstMs, shotS.median, keptS.median, coldS.median, shotS.median / keptS.median,
               shotS.median / coldS.median, shotC.median, coldC.median, shotC.median / coldC.median,
               pairC.min, pairC.max);

  // Two views of one assembly (a stereo pair 6.4 cm apart, following the camera) against
  // one view (the left eye), in two settings measured in one interleaved loop:
  //  (a) still: the middle frame of the shot held, both sides drawing that one frame
  //      with its deep opacity maps kept from the previous render (a renderer keeps them
  //      while the lights, grooms, transforms and cage stay, whatever the camera);
  //  (b) wind: a frame of the shot, the next one in every pair (the cage moves), the maps
  //      rebuilt in every render (RenderOptions::reuseShadows off, as each frame of a
  //      moving groom must), once for both views of a two-view render. A renderer of its
  //      own, so that (a)'s renderer keeps the held frame's maps between its pairs.
  // One view: render() of the left eye (opaque scene, LOD pre-pass, G-buffer clear,
  // strand pass, shade, filter, composite, read-back of colour and depth). Two views:
  // renderViews() of both eyes (the opaque scene, shade, filter, composite and read-back
  // per view; the LOD pre-pass and the strand assembly once; every strand rasterised into
  // both G-buffers in one kernel). A pair is one view then two views of the same frame;
  // each pair's ratio is reported with the ratio of the medians.
  struct Side {
    std::vector<double> ms, cpu, dev;
    std::map<std::string, std::vector<double>> stages;
    int shadowRuns = 0;
  };
  struct Setting {
    Side one, two;
    std::vector<double> ratios;  // two / one, pair by pair (wall)
  };
  Setting still2, wind2;
  const int viewPairs = r.opt.quick ? std::min(r.opt.viewPairsOpt, 3) : r.opt.viewPairsOpt;
  const int midFrame = std::max(frames / 2, 1);
  auto stereo = [](const Scene& s) {
    View left, right;
    left.relative = right.relative = true;
    left.offset = glm::vec3(-0.032f, 0.0f, 0.0f);
    right.offset = glm::vec3(0.032f, 0.0f, 0.0f);
    return std::vector<Camera>{viewCamera(s, left), viewCamera(s, right)};
  };
  auto timed = [&](auto&& call, Side& side) {
    const double c0 = processCpuMs();
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<StageTime> t = call();
    side.ms.push_back(ms(t0));
    side.cpu.push_back(processCpuMs() - c0);
    double sum = 0.0;
    for (const StageTime& st : t) {
      side.stages[st.stage].push_back(st.ms);
      sum += st.ms;
      if (st.stage == "shadow") ++side.shadowRuns;
    }
    side.dev.push_back(sum);
  };
  Renderer windRenderer(r.b.device);
  auto pair = [&](Renderer& r, Setting& set, const Scene& s, const RenderOptions& o) {
    const std::vector<Camera> eyes = stereo(s);
    Scene one = s;
    one.camera = eyes[0];
    timed([&] { return r.render(one, o).timings; }, set.one);
    timed([&] { return r.renderViews(s, eyes, o)[0].timings; }, set.two);
    set.ratios.push_back(set.two.ms.back() / set.one.ms.back());
  };
  {
    const Scene held = sceneAtFrame(shot, static_cast<double>(midFrame));
    RenderOptions kept, rebuilt;
    rebuilt.reuseShadows = false;
    for (Renderer* r : {&r.b.renderer, &windRenderer}) {  // warm-up: both paths built
      const std::vector<Camera> eyes = stereo(held);
      Scene one = held;
      one.camera = eyes[0];
      r->render(one);
      r->renderViews(held, eyes);
    }
    for (int i = 0; i < viewPairs; ++i) {
      pair(r.b.renderer, still2, held, kept);
      // frames midFrame, midFrame + 1, ... (wrapping inside the shot)
      const int f = 2 + (midFrame - 2 + i) % std::max(frames - 1, 1);
      pair(windRenderer, wind2, sceneAtFrame(shot, static_cast<double>(f)), rebuilt);
    }
  }
  const double oneView = summarize(still2.one.ms).median,
               twoViews = summarize(still2.two.ms).median;
  const double windOne = summarize(wind2.one.ms).median, windTwo = summarize(wind2.two.ms).median;
  auto viewRow = [&](const std::string& name, const Side& side) {
    const Stats st = summarize(side.ms);
    r.md << "| " << name << " | " << fmt(st.median, 0) << " | " << fmt(st.min, 0) << " | "
         << fmt(st.max, 0) << " |";
  };
  r.md << "\n| stereo pair | median ms | min | max | two views / one |\n|---|---|---|---|---|\n";
  viewRow("(a) one view of a stereo pair, still frame, maps kept", still2.one);
  r.md << " |\n";
  viewRow("(a) both views, one assembly, still frame, maps kept", still2.two);
  r.md << " " << fmt(twoViews / oneView, 3) << "x of one view (target <= 1.6x) |\n";
  viewRow("(b) one view, wind shot frame, maps rebuilt", wind2.one);
  r.md << " |\n";
  viewRow("(b) both views, one assembly, wind shot frame, maps rebuilt once", wind2.two);
  r.md << " " << fmt(windTwo / windOne, 3) << "x of one view (target <= 1.6x) |\n";
  auto spread = [&](const char* tag, const Setting& set) {
    const Stats st = summarize(set.ratios);
    std::string list;
    for (double v : set.ratios) list += (list.empty() ? "" : ", ") + fmt(v, 2);
    r.md << "- " << tag << ": ratio of medians "
         << fmt(summarize(set.two.ms).median / summarize(set.one.ms).median, 3) << "x wall, "
         << fmt(summarize(set.two.cpu).median / summarize(set.one.cpu).median, 3)
         << "x process CPU; pair by pair (wall) median " << fmt(st.median, 3) << "x, min "
         << fmt(st.min, 3) << "x, max " << fmt(st.max, 3) << "x (" << list << ")\n";
    return st;
  };
  r.md << "\nTwo views against one, " << viewPairs
       << " interleaved pairs (one view, then two views of the same frame) per setting, "
          "the settings alternating:\n\n";
  const Stats stillR = spread("(a) still frame, maps kept", still2);
  const Stats windR = spread("(b) wind shot frame, maps rebuilt in every render", wind2);
  // where the second view's time goes: each stage's median device time on either side
  // (two views: both views' dispatches of the stage together), then the frame's device-time
  // sum, the wall clock less that sum (uploads, copies, read-backs, host work) and the
  // process CPU time (every core; steadier than the wall clock on a shared machine)
  {
    std::set<std::string> names;
    for (const Setting* set : {&still2, &wind2})
      for (const Side* side : {&set->one, &set->two})
        for (const auto& [k, v] : side->stages) names.insert(k);
    r.md << "\nThe stereo pair stage by stage (medians over the pairs; deep opacity maps "
            "rebuilt in "
         << still2.one.shadowRuns + still2.two.shadowRuns << " of the " << 2 * viewPairs
         << " renders of (a) and " << wind2.one.shadowRuns << " + " << wind2.two.shadowRuns
         << " of (b)):\n\n"
         << "| | (a) one view ms | (a) two views ms | (a) two / one | (b) one view ms | (b) two "
            "views ms | (b) two / one |\n|---|---|---|---|---|---|---|\n";
    auto cell = [&](double a, double c) {
      r.md << " " << fmt(a, 1) << " | " << fmt(c, 1) << " | "
           << (a > 0.0 ? fmt(c / a, 3) + "x" : std::string("")) << " |";
    };
    auto row = [&](const std::string& name, double a1, double a2, double b1, double b2) {
      r.md << "| " << name << " |";
      cell(a1, a2);
      cell(b1, b2);
      r.md << "\n";
      r.report["sequences"]["views_split"][name] = {{"one", a1}, {"two", a2}};
      r.report["sequences"]["wind_views_split"][name] = {{"one", b1}, {"two", b2}};
    };
    auto stage = [](const Side& side, const std::string& k) {
      auto it = side.stages.find(k);
      return it == side.stages.end() ? 0.0 : summarize(it->second).median;
    };
    for (const std::string& k : names)
      row(k, stage(still2.one, k), stage(still2.two, k), stage(wind2.one, k), stage(wind2.two, k));
    auto med = [](const std::vector<double>& v) { return summarize(v).median; };
    auto hostOf = [](const Side& side) {
      std::vector<double> h;
      for (std::size_t i = 0; i < side.ms.size(); ++i) h.push_back(side.ms[i] - side.dev[i]);
      return h;
    };
    row("device-time sum", med(still2.one.dev), med(still2.two.dev), med(wind2.one.dev),
        med(wind2.two.dev));
    row("wall less device time", med(hostOf(still2.one)), med(hostOf(still2.two)),
        med(hostOf(wind2.one)), med(hostOf(wind2.two)));
    row("wall", oneView, twoViews, windOne, windTwo);
    row("process CPU", med(still2.one.cpu), med(still2.two.cpu), med(wind2.one.cpu),
        med(wind2.two.cpu));
    r.report["sequences"]["one_view_cpu_ms"] = med(still2.one.cpu);
    r.report["sequences"]["two_views_cpu_ms"] = med(still2.two.cpu);
    r.report["sequences"]["wind_one_view_cpu_ms"] = med(wind2.one.cpu);
    r.report["sequences"]["wind_two_views_cpu_ms"] = med(wind2.two.cpu);
    r.report["sequences"]["views_shadow_rebuilds"] = still2.one.shadowRuns + still2.two.shadowRuns;
    r.report["sequences"]["wind_views_shadow_rebuilds"] =
        wind2.one.shadowRuns + wind2.two.shadowRuns;
  }
  r.report["sequences"]["view_pairs"] = viewPairs;
  r.report["sequences"]["one_view_ms"] = oneView;
  r.report["sequences"]["two_views_ms"] = twoViews;
  r.report["sequences"]["two_views_vs_one"] = twoViews / oneView;
  r.report["sequences"]["two_views_vs_one_pairs"] = {
      {"median", stillR.median}, {"min", stillR.min}, {"max", stillR.max}};
  r.report["sequences"]["wind_one_view_ms"] = windOne;
  r.report["sequences"]["wind_two_views_ms"] = windTwo;
  r.report["sequences"]["wind_two_views_vs_one"] = windTwo / windOne;
  r.report["sequences"]["wind_two_views_vs_one_pairs"] = {
      {"median", windR.median}, {"min", windR.min}, {"max", windR.max}};
  std::fprintf(stderr,
               "sequences views: (a) still, maps kept: one %.0f ms, two %.0f ms (%.3fx, "
               "pairs %.3f-%.3fx); (b) wind, maps rebuilt: one %.0f ms, two %.0f ms (%.3fx, "
               "pairs %.3f-%.3fx)\n",
               oneView, twoViews, twoViews / oneView, stillR.min, stillR.max, windOne, windTwo,
               windTwo / windOne, windR.min, windR.max);
  // motion vectors: frame t warped to t+1 by t+1's motion (docs/aovs.md), and what the
  // motion layer costs on a frame of the wind shot
  auto iouPairs = [&](const Scene& seq, const std::vector<int>& starts, double& warped,
                      double& unwarped, double* aovMs, double* plainMs) {
    warped = unwarped = 0.0;
    RenderOptions o;
    o.aovs = true;
    for (int f : starts) {
      const Scene s0 = sceneAtFrame(seq, f), p0 = sceneAtFrame(seq, f - 1);
      const Scene s1 = sceneAtFrame(seq, f + 1);
      o.previous = &p0;
      const Frame a = r.b.renderer.render(s0, o);
      o.previous = &s0;
      auto t0 = std::chrono::steady_clock::now();
      const Frame c = r.b.renderer.render(s1, o);
      if (aovMs) *aovMs += ms(t0) / static_cast<double>(starts.size());
      if (plainMs) {
        t0 = std::chrono::steady_clock::now();
        r.b.renderer.render(s1, RenderOptions{});
        *plainMs += ms(t0) / static_cast<double>(starts.size());
      }
      warped +=
          motionWarpIoU(c.aovs, a.aovs, s1.width, s1.height) / static_cast<double>(starts.size());
      unwarped += maskIoU(c.aovs, a.aovs, s1.width, s1.height) / static_cast<double>(starts.size());
    }
  };
  std::vector<int> starts;
  for (int f = 2; f + 1 <= std::max(frames, 3); f += std::max(1, frames / 4)) starts.push_back(f);
  double windIoU, windStill, aovMs = 0.0, plainMs = 0.0;
  iouPairs(shot, starts, windIoU, windStill, &aovMs, &plainMs);
  // a slow turntable: the default scene (no wind), the camera orbiting 0.5 degrees a frame
  const Scene turn = loadScene(std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json");
  double turnIoU = 0.0, turnStill = 0.0;
  {
    RenderOptions o;
    o.aovs = true;
    const int pairs = static_cast<int>(starts.size());
    for (int i = 0; i < pairs; ++i) {
      Scene s0 = turn, s1 = turn;
      const glm::vec3 c = turn.camera.target;
      auto orbit = [&](Scene& s, float deg) {
        const glm::vec3 d = turn.camera.position - c;
        const float a = glm::radians(deg);
        s.camera.position = c + glm::vec3(d.x * std::cos(a) + d.z * std::sin(a), d.y,
                                          -d.x * std::sin(a) + d.z * std::cos(a));
      };
      orbit(s0, 5.0f * static_cast<float>(i));
      orbit(s1, 5.0f * static_cast<float>(i) + 0.5f);
      o.previous = nullptr;
      const Frame a = r.b.renderer.render(s0, o);
      o.previous = &s0;
      const Frame cf = r.b.renderer.render(s1, o);
      turnIoU += motionWarpIoU(cf.aovs, a.aovs, s1.width, s1.height) / pairs;
      turnStill += maskIoU(cf.aovs, a.aovs, s1.width, s1.height) / pairs;
    }
  }
  r.md << "\nMotion vectors, frame t warped to t+1 by t+1's motion (docs/aovs.md, mean over "
       << starts.size()
       << " pairs): \n\n| shot | IoU warped | IoU not warped | target |\n|---|---|---|---|\n"
       << "| slow turntable (default scene, 0.5 deg a frame) | " << fmt(turnIoU, 3) << " | "
       << fmt(turnStill, 3) << " | >= 0.9 |\n"
       << "| wind shot | " << fmt(windIoU, 3) << " | " << fmt(windStill, 3)
       << " | >= 0.8 |\n\nA wind frame with `--aov all` (motion pass included): " << fmt(aovMs, 0)
       << " ms, without: " << fmt(plainMs, 0) << " ms.\n";
  r.report["sequences"]["iou_turntable"] = turnIoU;
  r.report["sequences"]["iou_turntable_unwarped"] = turnStill;
  r.report["sequences"]["iou_wind"] = windIoU;
  r.report["sequences"]["iou_wind_unwarped"] = windStill;
  r.report["sequences"]["aov_frame_ms"] = aovMs;
  r.report["sequences"]["plain_frame_ms"] = plainMs;
  std::fprintf(stderr, "sequences IoU: turntable %.3f (%.3f), wind %.3f (%.3f)\n", turnIoU,
               turnStill, windIoU, windStill);
}

}  // namespace clhair::bench
