// floor.cpp — the benchmark's floor section (clhair_bench --only floor):
// The strand pass against an in-run floor: the same raster as plain multithreaded C++
// (host/groom/cpu_raster.h, checked word for word against the device's G-buffer), the pass's cores
// used (CPU time / wall time), and the default scene's frame as wall clock next to the device-time
// sum.
#include "harness.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "groom/cpu_raster.h"
#include "groom/explicit_data.h"

namespace clhair::bench {

void runFloor(Run& r) {
  auto exportedGroom1 = [&r] { return r.exportedGroom1(); };
  // the strand pass against the same work as plain C++ on as many threads as the device
  // has compute units (LOD off, MSAA 1, filter off)
  std::shared_ptr<const StrandGroom> strands = exportedGroom1();
  const ExplicitData data = prepareExplicit(*strands);
  const unsigned threads = std::max(1u, r.dev.info().computeUnits);
  r.md << "\n## Strand pass vs the C++ floor (" << r.groomNames[0] << ", " << r.opt.width << "x"
       << r.opt.height << ", LOD off, MSAA 1; floor: " << threads << " threads)\n\n"
       << "| distance | C++ floor ms | explicit strands ms (x floor) | generated strands ms (x "
          "floor) | "
          "cores used: explicit / generated | floor words differing "
          "| with identity layer, x without: explicit / generated "
          "|\n|---|---|---|---|---|---|---|\n";
  // the three distances, then the default scene's camera (closer than "close": the
  // strand pass of the default frame)
  const Scene defaultView =
      loadScene(std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json");
  const char* rowNames[4] = {r.distNames[0], r.distNames[1], r.distNames[2], "default camera"};
  for (int d = 0; d < 4; ++d) {
    Scene sx = r.scenes[0];
    sx.grooms[0] = GroomInstance(sx.grooms[0].name, strands, sx.grooms[0].transform);
    Scene sg = r.scenes[0];
    sg.width = r.opt.width;
    sg.height = r.opt.height;
    if (d < 3)
      sg = framed(r.scenes[0], r.dists[d], r.opt.width, r.opt.height);
    else
      sg.camera = defaultView.camera;
    sx.width = r.opt.width;
    sx.height = r.opt.height;
    sx.camera = sg.camera;  // the same view for both
    RenderOptions o;
    o.lod = Toggle::Off;
    o.filter = Toggle::Off;
    o.rasterOnly = true;
    Measured mx = r.b.measure(sx, o, false);
    Measured mg = r.b.measure(sg, o, false);
    // the identity layer's cost: the same passes with and without it, interleaved
    RenderOptions oi = o;
    oi.strandIds = true;
    double idRatio[2] = {0.0, 0.0};
    for (int k = 0; k < 2; ++k) {
      const Scene& sk = k == 0 ? sx : sg;
      std::vector<double> off, on;
      for (int i = 0; i < r.opt.warmup + r.opt.runs; ++i) {
        const double a = r.b.renderer.render(sk, o).stageMs("strands");
        const double c = r.b.renderer.render(sk, oi).stageMs("strands");
        if (i >= r.opt.warmup) {
          off.push_back(a);
          on.push_back(c);
        }
      }
      idRatio[k] = summarize(on).median / std::max(summarize(off).median, 1e-9);
    }
    // the floor: inputs captured from the device's own pass, then timed on the CPU
    RenderOptions oc = o;
    oc.captureGBuffer = true;
    const Frame f = r.b.renderer.render(sx, oc);
    const CpuRasterInputs in = cpuRasterInputs(f, data);
    std::vector<std::uint64_t> cpu;
    std::vector<double> ms;
    for (int i = 0; i < r.opt.warmup + r.opt.runs; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      cpuRasterExplicit(in, threads, cpu);
      if (i >= r.opt.warmup)
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
    }
    std::size_t differ = 0;
    for (std::size_t i = 0; i < cpu.size() && i < f.gbuffer.size(); ++i)
      differ += cpu[i] != f.gbuffer[i];
    if (cpu.size() != f.gbuffer.size()) differ = std::max(cpu.size(), f.gbuffer.size());
    const double fl = summarize(ms).median;
    const double ex = stageMedian(mx, "strands"), ge = stageMedian(mg, "strands");
    r.md << "| " << rowNames[d] << " | " << fmt(fl) << " | " << fmt(ex) << " (" << fmt(ex / fl)
         << "x) | " << fmt(ge) << " (" << fmt(ge / fl) << "x) | " << fmt(mx.cores.median) << " / "
         << fmt(mg.cores.median) << " | " << differ << " | " << fmt(idRatio[0]) << " / "
         << fmt(idRatio[1]) << " |\n";
    r.report["floor"][rowNames[d]] = {{"floor_ms", fl},
                                      {"explicit", measuredJson(mx)},
                                      {"generated", measuredJson(mg)},
                                      {"explicit_x_floor", ex / fl},
                                      {"generated_x_floor", ge / fl},
                                      {"floor_words_differing", differ},
                                      {"identity_x_explicit", idRatio[0]},
                                      {"identity_x_generated", idRatio[1]}};
    std::fprintf(stderr,
                 "floor %s: C++ %.1f ms, explicit %.1f ms (%.2fx, %.2f cores), generated %.1f "
                 "ms (%.2fx, %.2f cores), %zu words differ\n",
                 rowNames[d], fl, ex, ex / fl, mx.cores.median, ge, ge / fl, mg.cores.median,
                 differ);
  }
  // the default scene's whole frame: wall clock next to the device-time sum
  Scene def = loadScene(std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json");
  def.width = r.opt.width;
  def.height = r.opt.height;
  // every frame rebuilds the deep opacity maps (a moving light or groom), then a still
  // scene that keeps them
  RenderOptions cold;
  cold.reuseShadows = false;
  Measured m = r.b.measure(def, cold, false);
  Measured still = r.b.measure(def, RenderOptions{}, false);
  // cores per stage from one more frame with every dispatch waited for and timed on the host
  RenderOptions oc = cold;
  oc.stageCores = true;
  const Frame fc = r.b.renderer.render(def, oc);
  r.md << "\n### Default scene frame (" << r.opt.width << "x" << r.opt.height
       << ")\n\n| | wall | device-time sum |";
  for (const auto& [k, st] : m.stages) r.md << " " << k << " |";
  r.md << "\n|---|---|---|";
  for (std::size_t i = 0; i < m.stages.size(); ++i) r.md << "---|";
  r.md << "\n| ms | " << fmt(m.wall.median) << " | " << fmt(m.total.median) << " |";
  for (const auto& [k, st] : m.stages) r.md << " " << fmt(st.median) << " |";
  r.md << "\n| cores used | " << fmt(m.cores.median) << " | |";
  for (const auto& [k, st] : m.stages) {
    double cores = 0.0;
    for (const StageTime& t : fc.timings)
      if (t.stage == k && t.wallMs > 0.0) cores = t.cpuMs / t.wallMs;
    r.md << " " << fmt(cores) << " |";
    r.report["default_frame_cores"][k] = cores;
  }
  r.md << "\n\nA still scene (the maps kept from the previous frame, "
          "`RenderOptions::reuseShadows`): "
       << fmt(still.wall.median) << " ms wall, " << fmt(still.total.median) << " ms device time.\n";
  r.report["default_frame_still"] = measuredJson(still);
  r.report["default_frame"] = measuredJson(m);
  std::fprintf(stderr, "default frame: wall %.1f ms, device %.1f ms; still scene: wall %.1f ms\n",
               m.wall.median, m.total.median, still.wall.median);
}

}  // namespace clhair::bench
