// main.cpp — clhair_bench: speed of the pipeline on one device, reported side by side.
//
// Sections (all by default, or chosen with --only):
//   table1    Lipp et al. Table 1 for this device: {MSAA 1, 2, 4, 8} x {LOD off, on} x
//             {close, mid, far} x {groom 1, groom 2}; per-stage medians after warm-up,
//             strands and segments drawn, G-buffer writes, atomics issued and skipped.
//   dispatch  read-back vs over-launch vs persistent sizing of the strand pass.
//   scaling   strands 16k -> 256k at a fixed view; resolution 720p -> 4K at a fixed groom.
//   atomics   64-bit atom_min throughput with and without the load skip, and each
//             table1 MSAA-1 raster time as a multiple of that floor.
//   quality   Lipp Fig. 7: SWR1, SWR1+F, SWR1+F+L (LOD strands with the single-fibre BSDF,
//             and with Huang's aggregated one), MSAA 2/4/8, the coverage raster
//             (Kulikov 2025) at close/mid/far, FLIP and
//             PSNR against the reference (--ref embree: the strands traced as round curves,
//             the default; raster: jittered true-width strand passes), with frame times;
//             at mid also SWR1 against the other reference and the two references' times.
//   temporal  a 30-frame orbit: mean frame-to-frame change for SWR1, SWR1+F (Lipp's
//             filter), SWR1 with Huang's filter and its parts, MSAA 4, and with temporal
//             reprojection (clhair/temporal.h) on, after SWR1, Lipp's filter or Huang's:
//             flicker, FLIP against a per-frame
//             reference (--temporal-ref-spp), and on a fast shot the hair left in the pixels
//             the groom vacated.
//   explicit  the hair mesh vs the same strands as a cyHair file: device bytes, frame times.
//   mesh      the head as the analytic sphere vs a ~50k-triangle OBJ-style mesh of the same
//             sphere (generated here): frame time and the opaque + mesh stages' times.
//   sequences a shot of the default groom in wind (assets/scenes/wind.json, 720p, --seq-frames
//             frames, 120 by default) rendered frame after frame in one process: the time per
//             frame after the first against the same scene as a still frame (interleaved;
//             wall and process CPU time), start-up paid once; two views of one assembly against one
//             view, on a still frame (maps kept) and on a frame of the shot (maps rebuilt),
//             --view-pairs interleaved pairs each, with every pair's ratio and a per-stage split;
//             the cost of the motion layer; the warped-mask IoU of the motion vectors
//             (clhair::motionWarpIoU) on the wind shot and on a slow turntable.
//   crowd     assets/scenes/crowd.json (100 groom instances, bench/crowd.cpp): at 960x540
//             and 1920x1080, frame time and FLIP against the full render (LOD off) of LOD
//             alone and of budgets 1-8 M under the uniform and the screen rule; thinning
//             variants; segments per groom; a 60-frame dolly's popping against LOD alone
//             and its segments against the budget; the single default groom at close.
//   lodfar    the default scene far at the quality size, maps rebuilt every frame: strand and
//             shadow stages with LOD off, with LOD (lights' passes capped by the camera's),
//             the light's view alone and full-detail maps; dispatch sizing; the shadowed
//             pixels' FLIP between them (bench/lod_far.h).
//   throughput a shot written frame after frame as PNG and as EXR (bench/throughput.h):
//             frames per second, per frame wall, device time, host CPU and host waits; frames in
//             flight against one at a time; single stills per process and in-process.
//   floor     the strand pass against an in-run floor: the same raster as plain
//             multithreaded C++ (host/groom/cpu_raster.h, checked word for word against
//             the device's G-buffer), the pass's cores used (CPU time / wall time), and the
//             default scene's frame as wall clock next to the device-time sum.
// Stage timings come from OpenCL profiling events (device time per stage); frames are also
// timed by wall clock (what a user waits for: uploads, read-backs and host work included);
// compile time is reported apart. Output: bench.json, bench.csv and bench.md in --out,
// tagged with device, driver and git revision; the markdown is also printed.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <CLI/CLI.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include "cl/device_impl.h"
#include "cl/dispatch.h"
#include "clhair/aov.h"
#include "clhair/progressive.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/strand_groom.h"
#include "clhair/temporal.h"
#include "crowd.h"
#include "groom/cpu_raster.h"
#include "groom/explicit_data.h"
#include "io/cyhair.h"
#include "io/tressfx.h"
#include "lod_far.h"
#include "metrics/image_metrics.h"
#include "throughput.h"

namespace {

using namespace clhair;
using nlohmann::json;

struct Stats {
  double median = 0, min = 0, max = 0;
};

Stats summarize(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  return s;
}

struct Measured {
  std::map<std::string, Stats> stages;
  Stats total;        // sum of the stages' device times
  Stats wall;         // render() call, wall clock
  Stats cores;        // process CPU time / wall time during render()
  FrameStats counts;  // from a separate statistics frame
};

struct Bench {
  Device device;
  Renderer renderer;
  int warmup = 1, runs = 3;

  Measured measure(const Scene& scene, RenderOptions o, bool counts = true) {
    for (int i = 0; i < warmup; ++i) renderer.render(scene, o);
    std::map<std::string, std::vector<double>> stages;
    std::vector<double> totals, walls, cores;
    for (int i = 0; i < runs; ++i) {
      const double c0 = processCpuMs();
      const auto t0 = std::chrono::steady_clock::now();
      Frame f = renderer.render(scene, o);
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      walls.push_back(wall * 1e3);
      cores.push_back(wall > 0.0 ? (processCpuMs() - c0) * 1e-3 / wall : 0.0);
      for (const StageTime& t : f.timings) stages[t.stage].push_back(t.ms);
      totals.push_back(f.totalMs());
    }
    Measured m;
    for (auto& [k, v] : stages) m.stages[k] = summarize(v);
    m.total = summarize(totals);
    m.wall = summarize(walls);
    m.cores = summarize(cores);
    if (counts) {
      o.rasterStats = true;
      m.counts = renderer.render(scene, o).stats;
    }
    return m;
  }
};

std::string gitRevision() {
  std::string cmd =
      std::string("git -C '") + CLHAIR_SOURCE_DIR + "' rev-parse --short HEAD 2>/dev/null";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return "unknown";
  char buf[64] = {};
  std::string rev = std::fgets(buf, sizeof(buf), p) ? std::string(buf) : "unknown";
  ::pclose(p);
  rev.erase(std::remove(rev.begin(), rev.end(), '\n'), rev.end());
  return rev.empty() ? "unknown" : rev;
}

std::string fmt(double v, int digits = 2) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.*f", digits, v);
  return b;
}

json measuredJson(const Measured& m) {
  json j;
  j["total_ms"] = {{"median", m.total.median}, {"min", m.total.min}, {"max", m.total.max}};
  j["wall_ms"] = {{"median", m.wall.median}, {"min", m.wall.min}, {"max", m.wall.max}};
  j["cores_used"] = m.cores.median;
  for (const auto& [k, s] : m.stages)
    j["stages_ms"][k] = {{"median", s.median}, {"min", s.min}, {"max", s.max}};
  j["strands"] = m.counts.strandsDrawn;
  j["segments"] = m.counts.segmentsDrawn;
  j["pixel_writes"] = m.counts.pixelWrites;
  j["atomics_issued"] = m.counts.atomicsIssued;
  j["atomics_skipped"] = m.counts.atomicsSkipped;
  return j;
}

// Sets the reconstruction filter of the scene and of each groom in it: Lipp's (huang 0) or
// Huang's parts (1 linking, 2 + alpha fix, 3 + anisotropic filter), and the strand connection
// when given.
void useFilter(Scene& s, int huang, std::optional<bool> promote = std::nullopt) {
  std::vector<FilterParams*> fps{&s.filter};
  for (GroomInstance& gi : s.grooms) fps.push_back(&gi.filter);
  for (FilterParams* fp : fps) {
    if (promote) fp->promote = *promote;
    fp->method = huang ? FilterParams::Method::Huang : FilterParams::Method::Lipp;
    fp->alphaFix = huang >= 2;
    fp->aniso = huang >= 3;
  }
}

double stageMedian(const Measured& m, const std::string& stage) {
  auto it = m.stages.find(stage);
  return it == m.stages.end() ? 0.0 : it->second.median;
}

// ns per 64-bit atom_min issued on this device (coherent addresses); returns {plain, skip}
std::pair<double, double> atomicProbe(Device::Impl& d, std::size_t words, int repeats, json& out) {
  cl::Kernel k(d.program("bench.cl"), "bench_atomic_min");
  cl::Buffer target(d.context, CL_MEM_READ_WRITE, words * sizeof(cl_ulong));
  const cl_uint perItem = 16;
  const std::size_t items = words / 4;  // 4 attempts per word per pass on average
  double result[2];
  for (int skip = 0; skip < 2; ++skip) {
    std::vector<double> ms;
    for (int r = 0; r < repeats + 1; ++r) {
      d.queue.enqueueFillBuffer(target, ~cl_ulong(0), 0, words * sizeof(cl_ulong));
      k.setArg(0, target);
      k.setArg(1, static_cast<cl_uint>(words));
      k.setArg(2, perItem);
      k.setArg(3, static_cast<cl_uint>(skip));
      cl::Event e;
      d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(items), cl::NullRange, nullptr,
                                   &e);
      e.wait();
      double t = (e.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                  e.getProfilingInfo<CL_PROFILING_COMMAND_START>()) *
                 1e-6;
      if (r > 0) ms.push_back(t);  // the first run warms up
    }
    Stats s = summarize(ms);
    double attempts = static_cast<double>(items) * perItem;
    result[skip] = s.median * 1e6 / attempts;
    out[skip ? "load_skip" : "plain"] = {{"median_ms", s.median},
                                         {"attempts", attempts},
                                         {"ns_per_attempt", result[skip]},
                                         {"attempts_per_s", attempts / (s.median * 1e-3)}};
  }
  return {result[0], result[1]};
}

}  // namespace

int main(int argc, char** argv) {
  using namespace clhair;
  CLI::App app{"clhair_bench: speed of the clhair pipeline on one device"};
  DeviceOptions dopts;
  std::string out = "bench-results", only,
              sceneDir = std::string(CLHAIR_SOURCE_DIR) + "/bench/scenes";
  int runs = 3, warmup = 1, width = 1920, height = 1080, refSpp = 64, qualityWidth = 960,
      qualityHeight = 540, seqFrames = 120, temporalRefSpp = 4, viewPairsOpt = 9;
  bool quick = false;
  std::string qualityGrooms = "1";
  std::string refName = "embree";
  std::string refCache;        // quality: folder of references kept between runs
  std::string qualityConfigs;  // quality: the configurations to run (comma-separated names)
  std::string qualityDistances = "close,mid,far";
  std::string qualityLights = "plain";  // quality: plain, maps or both
  app.add_option("--device", dopts.selector, "device: P:D or a name substring");
  app.add_option("--out", out, "folder for bench.json, bench.csv, bench.md");
  app.add_option(
      "--only", only,
      "one section: table1, dispatch, scaling, atomics, quality, temporal, explicit, children, "
      "mesh, crowd, floor, sequences, lodfar, throughput");
  app.add_option("--runs", runs,
                 "timed runs per configuration (median reported); the quality section takes 0 "
                 "for the times of the one frame it compares");
  app.add_option("--warmup", warmup, "untimed runs first");
  app.add_option("--width", width, "table1 width");
  app.add_option("--height", height, "table1 height");
  app.add_option("--scenes", sceneDir, "folder with groom1.json and groom2.json");
  app.add_option("--ref-spp", refSpp, "samples per pixel of the quality reference (default 64)");
  app.add_option("--ref", refName,
                 "quality reference: embree (strands traced as round curves, default), raster "
                 "(jittered true-width strand passes) or path (paths traced through the full "
                 "groom: scattering between fibres, every light shadowed by the geometry)")
      ->check(CLI::IsMember({"embree", "raster", "path"}));
  app.add_option("--quality-width", qualityWidth, "quality and temporal sections: width");
  app.add_option("--quality-grooms", qualityGrooms,
                 "quality section: 1 (groom1, default), 2 (groom2) or both");
  app.add_option("--quality-height", qualityHeight, "quality and temporal sections: height");
  app.add_option("--ref-cache", refCache,
                 "quality and crowd sections: keep each reference as EXR in this folder and read "
                 "it back when it is there (for runs of one revision: the file names carry "
                 "groom, distance, size, method and spp, not the code; the crowd's full "
                 "renders and LOD-only dolly frames keep their wall time beside them)");
  app.add_option("--quality-distances", qualityDistances,
                 "quality section: the distances to run (comma-separated: close, mid, far)");
  app.add_option("--quality-lights", qualityLights,
                 "quality section: the grooms' lights plain (no hair shadows, default), maps (each "
                 "with a deep opacity map, shadows between fibres) or both");
  app.add_option("--quality-configs", qualityConfigs,
                 "quality and temporal sections: only these configurations (comma-separated "
                 "names as in the tables, e.g. \"SWR1,SWR MSAA 4\"); default all");
  app.add_option("--temporal-ref-spp", temporalRefSpp,
                 "temporal section: samples per pixel of each frame's reference (default 4)")
      ->check(CLI::Range(1, 4096));
  app.add_option("--seq-frames", seqFrames, "sequences section: frames of the wind shot (120)")
      ->check(CLI::Range(3, 100000));
  app.add_option("--view-pairs", viewPairsOpt,
                 "sequences section: interleaved one-view / two-view pairs per setting (9)")
      ->check(CLI::Range(1, 1000));
  bench::ThroughputOptions tp;
  tp.scene = std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/wind.json";
  tp.cli = CLHAIR_BENCH_CLI;
  int tpWidth = 0, tpHeight = 0;
  app.add_option("--tp-scene", tp.scene, "throughput section: the shot (assets/scenes/wind.json)");
  app.add_option("--tp-frames", tp.frames, "throughput section: frames of the shot per row (240)")
      ->check(CLI::Range(3, 100000));
  app.add_option("--tp-width", tpWidth, "throughput section: width (default --width)");
  app.add_option("--tp-height", tpHeight, "throughput section: height (default --height)");
  app.add_option("--tp-stills", tp.stills, "throughput section: single stills per way (5)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--tp-formats", tp.formats,
                 "throughput section: formats, comma-separated (png,exr)");
  app.add_flag("--quick", quick, "smaller sweep for a fast look (640x360, 1 run, MSAA 1 and 4)");
  CLI11_PARSE(app, argc, argv);
  try {
    if (quick) {
      runs = 1;
      warmup = 1;
      width = 640;
      height = 360;
    }
    auto t0 = std::chrono::steady_clock::now();
    Device dev = Device::open(DeviceOptions::fromEnvironment(dopts));
    Bench b{dev, Renderer(dev), warmup, runs};
    double compileMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const DeviceInfo& info = dev.info();
    json report;
    report["device"] = info.name;
    report["platform"] = info.platformName;
    report["driver"] = info.driverVersion;
    report["opencl"] = info.version;
    report["subgroup_backend"] = subgroupBackendName(info.backend);
    report["revision"] = gitRevision();
    report["runs"] = runs;
    report["warmup"] = warmup;
    report["startup_and_compile_ms"] = compileMs;
    std::ostringstream md, csv;
    md << "# clhair benchmark\n\n"
       << "device: " << info.name << " (" << info.platformName << ", driver " << info.driverVersion
       << "), sub-group backend " << subgroupBackendName(info.backend) << ", revision "
       << report["revision"].get<std::string>() << "; median of " << runs << " runs after "
       << warmup
       << " warm-up; device times from profiling events. Start-up incl. kernel compilation: "
       << fmt(compileMs, 0) << " ms.\n\n";
    csv << "section,groom,lod,msaa,distance,strands_target,width,height,dispatch,total_ms,strands_"
           "ms,lod_ms,shade_ms,"
           "composite_ms,strands,segments,pixel_writes,atomics_issued,atomics_skipped\n";

    Scene scenes[2] = {loadScene(sceneDir + "/groom1.json"), loadScene(sceneDir + "/groom2.json")};
    const char* groomNames[2] = {"groom1 (long_wavy)", "groom2 (curly_medium)"};
    const CameraPreset dists[3] = {CameraPreset::Close, CameraPreset::Mid, CameraPreset::Far};
    const char* distNames[3] = {"close", "mid", "far"};
    auto framed = [&](Scene s, CameraPreset p, int w, int h) {
      s.width = w;
      s.height = h;
      s.camera = framePreset(s, p, 35.0f, 10.0f, 35.0f);
      return s;
    };
    auto csvRow = [&](const std::string& section, const std::string& groom, int lod, int msaa,
                      const std::string& dist, std::int64_t strandsTarget, int w, int h,
                      const std::string& dispatch, const Measured& m) {
      csv << section << ",\"" << groom << "\"," << lod << "," << msaa << "," << dist << ","
          << strandsTarget << "," << w << "," << h << "," << dispatch << "," << m.total.median
          << "," << stageMedian(m, "strands") << "," << stageMedian(m, "lod") << ","
          << stageMedian(m, "shade") << "," << stageMedian(m, "composite") << ","
          << m.counts.strandsDrawn << "," << m.counts.segmentsDrawn << "," << m.counts.pixelWrites
          << "," << m.counts.atomicsIssued << "," << m.counts.atomicsSkipped << "\n";
    };

    // groom1's generated strands exported to cyHair and read back (once), with the mesh's
    // appearance and LOD settings: the explicit-strand twin of groom1
    std::shared_ptr<const StrandGroom> exported;
    auto exportedGroom1 = [&]() {
      if (exported) return exported;
      std::filesystem::create_directories(out);
      const std::string hairPath = out + "/groom1.hair";
      const HairMesh& mesh = *scenes[0].grooms[0].mesh;
      StrandSet set = b.renderer.generateStrands(mesh);
      {
        CyHair h;
        for (std::uint32_t c : set.pointCounts) h.segments.push_back(c - 1);
        h.points = set.points;
        h.defaultThickness = mesh.appearance.strandWidth;
        writeCyHair(h, hairPath);
      }
      auto strands =
          std::make_shared<const StrandGroom>(loadStrandGroom(hairPath, dev.info().maxAlloc));
      StrandGroom sg = *strands;
      sg.appearance = mesh.appearance;
      sg.lod = mesh.lod;
      exported = std::make_shared<const StrandGroom>(std::move(sg));
      return exported;
    };

    std::vector<std::pair<std::string, Measured>> msaa1Rows;  // for the atomic-floor multiples
    if (only.empty() || only == "table1" || only == "atomics") {
      // rows: software MSAA 1 (filter off), SWR1+F (the default filter: Huang's), MSAA 2, 4, 8
      struct Row {
        int msaa;
        bool filter;
        const char* label;
      };
      std::vector<Row> rows =
          quick ? std::vector<Row>{{1, false, "1"}, {1, true, "1+F"}, {4, false, "4"}}
                : std::vector<Row>{{1, false, "1"},
                                   {1, true, "1+F"},
                                   {2, false, "2"},
                                   {4, false, "4"},
                                   {8, false, "8"}};
      md << "## Table 1: frame time in ms, total (strand pass), " << width << "x" << height
         << "\n\n";
      md << "| LOD | MSAA | " << groomNames[0] << " close | mid | far | " << groomNames[1]
         << " close | mid | far |\n";
      md << "|---|---|---|---|---|---|---|---|\n";
      json t1 = json::array();
      std::ostringstream counts;
      counts << "\n### Work per frame (LOD off / on, MSAA 1, no filter)\n\n| groom | distance | "
                "LOD | strands | segments | "
                "G-buffer writes | atomics issued | skipped by the load "
                "|\n|---|---|---|---|---|---|---|---|\n";
      for (int lod = 0; lod < 2; ++lod) {
        for (const Row& rowSpec : rows) {
          const int msaa = rowSpec.msaa;
          md << "| " << (lod ? "on" : "off") << " | " << rowSpec.label << " |";
          for (int g = 0; g < 2; ++g) {
            for (int d = 0; d < 3; ++d) {
              if (only == "atomics" && (msaa != 1 || rowSpec.filter)) continue;
              Scene s = framed(scenes[g], dists[d], width, height);
              RenderOptions o;
              o.lod = lod;
              o.msaa = msaa;
              o.filter = rowSpec.filter ? 1 : 0;
              Measured m = b.measure(s, o);
              md << " " << fmt(m.wall.median) << " (" << fmt(m.total.median) << "; "
                 << fmt(stageMedian(m, "strands")) << ") |";
              json row = measuredJson(m);
              row["groom"] = groomNames[g];
              row["lod"] = lod == 1;
              row["msaa"] = msaa;
              row["filter"] = rowSpec.filter;
              row["distance"] = distNames[d];
              t1.push_back(row);
              csvRow(rowSpec.filter ? "table1+F" : "table1", groomNames[g], lod, msaa, distNames[d],
                     scenes[g].grooms[0].mesh->strandCount, width, height, "auto", m);
              if (msaa == 1 && !rowSpec.filter) {
                msaa1Rows.push_back(
                    {std::string(groomNames[g]) + " " + distNames[d] + (lod ? " LOD" : ""), m});
                counts << "| " << groomNames[g] << " | " << distNames[d] << " | "
                       << (lod ? "on" : "off") << " | " << m.counts.strandsDrawn << " | "
                       << m.counts.segmentsDrawn << " | " << m.counts.pixelWrites << " | "
                       << m.counts.atomicsIssued << " | " << m.counts.atomicsSkipped << " |\n";
              }
              std::fprintf(stderr, "table1 %s LOD %d MSAA %s %s: %.1f ms\n", groomNames[g], lod,
                           rowSpec.label, distNames[d], m.total.median);
            }
          }
          md << "\n";
        }
      }
      md << counts.str();
      // LOD speed-up at far, per groom (MSAA 1)
      for (bool filtered : {false, true}) {
        md << "\nLOD speed-up at far (" << (filtered ? "SWR1+F" : "SWR1") << ", total frame): ";
        for (int g = 0; g < 2; ++g) {
          double off = 0, on = 0;
          for (const auto& row : t1)
            if (row["groom"] == groomNames[g] && row["distance"] == "far" && row["msaa"] == 1 &&
                row["filter"].get<bool>() == filtered)
              (row["lod"].get<bool>() ? on : off) = row["total_ms"]["median"].get<double>();
          if (on > 0) md << groomNames[g] << " " << fmt(off / on) << "x" << (g == 0 ? ", " : "\n");
          report["lod_far_speedup"][filtered ? "SWR1+F" : "SWR1"][groomNames[g]] =
              on > 0 ? off / on : 0.0;
        }
      }
      report["table1"] = t1;
    }

    if (only.empty() || only == "atomics") {
      json probe;
      auto [plain, skip] = atomicProbe(*dev.impl(), static_cast<std::size_t>(width) * height,
                                       std::max(runs, 3), probe);
      report["atomic_probe"] = probe;
      md << "\n## Atomic floor\n\n64-bit `atom_min` on " << width << "x" << height
         << " words, coherent addresses, 4 attempts per word: " << fmt(plain, 3)
         << " ns per attempt (plain), " << fmt(skip, 3)
         << " ns with the load skip.\n\n| configuration | strand pass ms | atomics issued | floor "
            "ms "
            "(issued x plain) | raster / floor |\n|---|---|---|---|---|\n";
      for (const auto& [name, m] : msaa1Rows) {
        double floorMs = m.counts.atomicsIssued * plain * 1e-6;
        double ratio = floorMs > 0 ? stageMedian(m, "strands") / floorMs : 0.0;
        md << "| " << name << " | " << fmt(stageMedian(m, "strands")) << " | "
           << m.counts.atomicsIssued << " | " << fmt(floorMs, 3) << " | " << fmt(ratio, 1)
           << "x |\n";
        report["raster_over_atomic_floor"][name] = ratio;
      }
    }

    if (only.empty() || only == "dispatch") {
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
          csvRow("dispatch", groomNames[0], 1, 1, distNames[d],
                 scenes[0].grooms[0].mesh->strandCount, width, height, dispatchModeName(mode), m);
          std::fprintf(stderr, "dispatch %s %s: wall %.1f ms, device %.1f ms\n",
                       dispatchModeName(mode), distNames[d], m.wall.median, m.total.median);
        }
        md << "\n";
      }
    }

    if (only.empty() || only == "scaling") {
      md << "\n## Scaling (groom1 at mid, LOD off, MSAA 1)\n\n| strands | width x height | frame "
            "ms | strand pass ms | "
            "segments | ms per M segments | ms per megapixel |\n|---|---|---|---|---|---|---|\n";
      std::vector<std::int64_t> counts =
          quick ? std::vector<std::int64_t>{16000, 64000}
                : std::vector<std::int64_t>{16000, 32000, 64000, 128000, 256000};
      std::vector<std::pair<int, int>> sizes =
          quick ? std::vector<std::pair<int, int>>{{1280, 720}, {1920, 1080}}
                : std::vector<std::pair<int, int>>{
                      {1280, 720}, {1920, 1080}, {2560, 1440}, {3840, 2160}};
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
        std::fprintf(stderr, "scaling %lld strands %dx%d: %.1f ms\n", static_cast<long long>(n), w,
                     h, r.total.median);
      };
      for (std::int64_t n : counts) row(n, 1920, 1080);
      for (auto [w, h] : sizes) row(127000, w, h);
    }

    if (only.empty() || only == "quality") {
      // Lipp Fig. 7: each configuration against the reference (average of refSpp jittered
      // true-width passes), FLIP and PSNR, with its frame time.
      const int qw = quick ? 320 : qualityWidth, qh = quick ? 180 : qualityHeight;
      const ReferenceMethod refMethod = parseReferenceMethod(refName);
      const ReferenceMethod otherMethod =
          refMethod == ReferenceMethod::Embree ? ReferenceMethod::Raster : ReferenceMethod::Embree;
      if (qualityGrooms != "1" && qualityGrooms != "2" && qualityGrooms != "both")
        throw Error("--quality-grooms must be 1, 2 or both, not \"" + qualityGrooms + "\"");
      if (qualityLights != "plain" && qualityLights != "maps" && qualityLights != "both")
        throw Error("--quality-lights must be plain, maps or both, not \"" + qualityLights + "\"");
      std::filesystem::create_directories(out + "/quality");
      struct Config {
        const char* name;
        int msaa, filter, lod;
        bool promote;  // the filter's strand connection (Lipp §3.3.2)
        int huang;     // 0: Lipp's filter; else Huang's: 1 linking, 2 + alpha fix, 3 + filter
        int lodAggregate = 0;  // LOD strands: single fibre or aggregated BCSDF (Huang 2024)
        int raster = 0;        // 0 lines, 1 coverage (Kulikov 2025, clhair/coverage.h)
        // segment budget: -1 the scene's (2 M segments by default), 0 none; with LOD a
        // groom over the budget keeps fewer, wider strands (docs/scene-format.md)
        std::int64_t budget = -1;
        int points = 0;   // 1: shaded once per visible strand point (RenderOptions::pointShading)
        int quality = 0;  // RenderOptions::quality: 0 draft (the fields above), 1 good, 2 final
        int finalPasses = 0;  // final: passes (the first N of one progressive run per cell)
        int finalPath = -1;   // final: RenderOptions::finalPath
      };
      const Config configs[] = {{"SWR1", 1, 0, 0, true, 0},
                                {"SWR1+F", 1, 1, 0, true, 0},
                                {"SWR1+F+L", 1, 1, 1, true, 0},
                                {"SWR1+F+L aggregated", 1, 1, 1, true, 0, 1},
                                {"SWR1+L", 1, 0, 1, true, 0},
                                {"SWR1+L aggregated", 1, 0, 1, true, 0, 1},
                                {"SWR1+F, no promotion", 1, 1, 0, false, 0},
                                {"SWR1+H linking", 1, 1, 0, true, 1},
                                {"SWR1+H linking+alpha fix", 1, 1, 0, true, 2},
                                {"SWR1+H (linking+alpha fix+anisotropic)", 1, 1, 0, true, 3},
                                {"SWR1+H+L", 1, 1, 1, true, 3},
                                {"SWR1+H+L no budget", 1, 1, 1, true, 3, 0, 0, 0},
                                {"SWR MSAA 2", 2, 0, 0, true, 0},
                                {"SWR MSAA 4", 4, 0, 0, true, 0},
                                {"SWR MSAA 8", 8, 0, 0, true, 0},
                                {"SWR MSAA 4 per point", 4, 0, 0, true, 0, 0, 0, -1, 1},
                                {"SWR MSAA 8 per point", 8, 0, 0, true, 0, 0, 0, -1, 1},
                                {"SWR1 per point", 1, 0, 0, true, 0, 0, 0, -1, 1},
                                {"good", 1, 0, 0, true, 0, 0, 0, -1, 0, 1},
                                {"final 4", 1, 0, 0, true, 0, 0, 0, -1, 0, 2, 4},
                                {"final 16", 1, 0, 0, true, 0, 0, 0, -1, 0, 2, 16},
                                {"final 64", 1, 0, 0, true, 0, 0, 0, -1, 0, 2, 64},
                                {"final SWR1 4", 1, 0, 0, true, 0, 0, 0, -1, 0, 2, 4, 0},
                                {"final SWR1 16", 1, 0, 0, true, 0, 0, 0, -1, 0, 2, 16, 0},
                                {"final SWR1 64", 1, 0, 0, true, 0, 0, 0, -1, 0, 2, 64, 0},
                                {"SWR coverage", 1, 0, 0, true, 0, 0, 1}};
      auto splitList = [](const std::string& list) {
        std::set<std::string> items;
        for (std::size_t at = 0; !list.empty() && at <= list.size();) {
          const std::size_t comma = std::min(list.find(',', at), list.size());
          items.insert(list.substr(at, comma - at));
          at = comma + 1;
        }
        return items;
      };
      const std::set<std::string> chosen = splitList(qualityConfigs);
      const std::set<std::string> distances = splitList(qualityDistances);
      for (const std::string& name : distances)
        if (name != "close" && name != "mid" && name != "far")
          throw Error("--quality-distances: no distance \"" + name + "\" (close, mid, far)");
      for (const std::string& name : chosen)
        if (std::none_of(std::begin(configs), std::end(configs),
                         [&](const Config& c) { return name == c.name; }))
          throw Error("--quality-configs: no configuration \"" + name + "\"");
      if (!refCache.empty()) std::filesystem::create_directories(refCache);
      // the reference of one groom and distance, from the cache when it holds it
      auto reference = [&](const Scene& s, int g, int d, ReferenceMethod method, std::string ltag) {
        // the path reference shadows every light by the geometry whatever the lights say:
        // one reference serves both lightings, and its mask is always from the depth
        const bool traced = method == ReferenceMethod::Path;
        if (traced) ltag.clear();
        const std::string path = refCache + "/groom" + std::to_string(g + 1) + "_" + ltag +
                                 distNames[d] + "_" + std::to_string(s.width) + "x" +
                                 std::to_string(s.height) + "_" + referenceMethodName(method) +
                                 "_" + std::to_string(refSpp) + "spp.exr";
        // the depth (the hair mask of the lighting with maps) as raw floats beside it
        const std::string depthPath = path + ".depth";
        Frame f;
        if (!refCache.empty() && std::filesystem::exists(path)) {
          f.color = readImage(path);
          if (ltag.empty() && !traced) return f;  // plain: the mask is from the colour alone
          f.depth.resize(static_cast<std::size_t>(f.color.width) * f.color.height);
          std::ifstream in(depthPath, std::ios::binary);
          in.read(reinterpret_cast<char*>(f.depth.data()),
                  static_cast<std::streamsize>(f.depth.size() * sizeof(float)));
          if (in && in.gcount() == static_cast<std::streamsize>(f.depth.size() * sizeof(float)))
            return f;
        }
        f = b.renderer.renderReference(s, refSpp, method);
        if (!refCache.empty()) {
          writeImage(f.color, path);
          std::ofstream o(depthPath, std::ios::binary);
          o.write(reinterpret_cast<const char*>(f.depth.data()),
                  static_cast<std::streamsize>(f.depth.size() * sizeof(float)));
        }
        return f;
      };
      auto hairFlip = [](const Frame& ref, const Frame& f, const std::vector<char>& mask) {
        ImageComparison cmp = compareImages(ref.color, f.color);
        double sum = 0.0;
        std::size_t n = 0;
        for (std::size_t i = 0; i < mask.size(); ++i)
          if (mask[i]) {
            ++n;
            sum += cmp.flip.error[i];
          }
        return sum / std::max<std::size_t>(n, 1);
      };
      // mean linear luminance over the hair's pixels (brighter or darker than the reference)
      auto hairLuminance = [](const Frame& f, const std::vector<char>& mask) {
        double sum = 0.0;
        std::size_t n = 0;
        for (std::size_t i = 0; i < mask.size(); ++i)
          if (mask[i]) {
            ++n;
            sum += 0.2126 * f.color.rgba[4 * i] + 0.7152 * f.color.rgba[4 * i + 1] +
                   0.0722 * f.color.rgba[4 * i + 2];
          }
        return sum / std::max<std::size_t>(n, 1);
      };
      auto wallMs = [](auto&& fn) {
        const auto t0 = std::chrono::steady_clock::now();
        fn();
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
            .count();
      };
      json q;
      for (int run = 0; run < 4; ++run) {  // plain lights, then lights with maps
        const int lighting = run / 2, g = run % 2;
        if ((g == 0 && qualityGrooms == "2") || (g == 1 && qualityGrooms == "1")) continue;
        // lighting 1: every light of the groom's scene with a deep opacity map, so that the
        // reference (maps of the full groom) and the frames (maps drawn with their LOD) are
        // shadowed between fibres by the same model
        const bool maps = lighting == 1;
        if ((maps && qualityLights == "plain") || (!maps && qualityLights == "maps")) continue;
        const std::string ltag = maps ? "maps_" : "";               // plain keeps its file names
        const std::string gtag = ltag + (g == 0 ? "" : "groom2_");  // groom1 keeps its names
        md << "\n## Quality against the reference (" << groomNames[g] << ", " << qw << "x" << qh
           << ", " << referenceMethodName(refMethod) << " reference " << refSpp << " spp"
           << (maps ? ", every light with a deep opacity map" : "")
           << ")\n\nOver the hair's pixels ("
           << (maps || refMethod == ReferenceMethod::Path
                   ? "where a sample of the reference saw hair in front of the scene: the hair "
                     "also shadows the head"
                   : "where the reference differs from the scene without hair")
           << "): mean FLIP (lower is better) / PSNR dB / frame ms. Whole-image values are in "
              "bench.json. SWR1+H: Huang's filter (DESIGN.md).\n\n| configuration |";
        for (int d = 0; d < 3; ++d)
          if (distances.count(distNames[d])) md << " " << distNames[d] << " |";
        md << "\n|---|";
        for (int d = 0; d < 3; ++d)
          if (distances.count(distNames[d])) md << "---|";
        md << "\n";
        std::map<std::string, std::vector<std::string>> cells;
        json& ql = maps ? q["lights_maps"] : q;
        json& qg = g == 0 ? ql : ql["groom2"];
        std::ostringstream refMd;  // the two references at mid
        for (int d = 0; d < 3; ++d) {
          if (!distances.count(distNames[d])) continue;
          Scene s = framed(scenes[g], dists[d], qw, qh);
          if (maps)
            for (Light& light : s.lights) light.shadows = true;
          Frame ref;
          const double refMs = wallMs([&] { ref = reference(s, g, d, refMethod, ltag); });
          qg["reference"][distNames[d]] = {
              {"method", referenceMethodName(refMethod)}, {"spp", refSpp}, {"wall_ms", refMs}};
          std::fprintf(stderr, "quality %s%s %s: %s reference, %d spp, %.1f s\n", ltag.c_str(),
                       groomNames[g], distNames[d], referenceMethodName(refMethod), refSpp,
                       refMs / 1000.0);
          Scene bare = s;
          bare.grooms.clear();
          const Frame background = b.renderer.render(bare);
          std::vector<char> hairMask(ref.color.rgba.size() / 4, 0);
          // the hair's shadows change the head too (maps, and always in the path reference):
          // the mask is where a sample of the reference saw hair
          const bool depthMask = maps || refMethod == ReferenceMethod::Path;
          for (std::size_t i = 0; i < hairMask.size(); ++i)
            if (depthMask)
              hairMask[i] = ref.depth[i] < background.depth[i] * (1.0f - 1e-6f);
            else
              for (int c = 0; c < 3; ++c)
                hairMask[i] |=
                    std::fabs(ref.color.rgba[4 * i + c] - background.color.rgba[4 * i + c]) > 1e-4f;
          qg["reference"][distNames[d]]["hair_luminance"] = hairLuminance(ref, hairMask);
          const std::string refPath = out + "/quality/" + gtag + distNames[d] + "_reference.png";
          writeImage(ref.color, refPath);
          // the scene without hair: the hair's pixels are where the reference differs from it
          writeImage(background.color, out + "/quality/" + gtag + distNames[d] + "_background.png");
          // quality final: one progressive run per pass path and cell, whose first N passes
          // give the row of N passes (the rows of fewer passes are its prefixes)
          std::map<int, std::unique_ptr<ProgressiveStill>> finals;
          for (const Config& c : configs) {
            if (!chosen.empty() && !chosen.count(c.name)) continue;
            RenderOptions o;
            o.msaa = c.msaa;
            o.filter = c.filter;
            o.lod = c.lod;
            o.lodAggregate = c.lodAggregate;
            o.raster = c.raster;
            o.segmentBudget = c.budget;
            o.pointShading = c.points;
            o.quality = c.quality;
            o.finalPath = c.finalPath;
            Scene sc = s;
            useFilter(sc, c.huang, c.promote);
            Frame f;
            if (c.finalPasses > 0) {
              std::unique_ptr<ProgressiveStill>& acc = finals[c.finalPath];
              if (!acc) acc = std::make_unique<ProgressiveStill>(b.renderer, s, o);
              acc->add(acc->passes(), std::max(c.finalPasses - acc->passes(), 0));
              f = acc->frame();
            } else {
              f = b.renderer.render(sc, o);
            }
            // --runs 0 (quick tuning runs): the times of this one frame; final: the sum of
            // its passes' times
            Measured m;
            if (runs > 0 && c.finalPasses == 0) {
              m = b.measure(sc, o, false);
            } else {
              for (const StageTime& t : f.timings) m.stages[t.stage] = summarize({t.ms});
              m.total = summarize({f.totalMs()});
            }
            ImageComparison cmp = compareImages(ref.color, f.color);
            // the same measures restricted to the hair's pixels
            const double psnrHair = computePsnr(ref.color, f.color, &hairMask).psnrDb;
            double flipHair = 0.0;
            std::size_t nHair = 0;
            for (std::size_t i = 0; i < hairMask.size(); ++i)
              if (hairMask[i]) {
                ++nHair;
                flipHair += cmp.flip.error[i];
              }
            flipHair /= std::max<std::size_t>(nHair, 1);
            std::string name = c.name;
            std::string file = name;
            for (char& ch : file)
              if (ch == ' ' || ch == '+' || ch == ',' || ch == '(' || ch == ')') ch = '_';
            writeImage(f.color, out + "/quality/" + gtag + distNames[d] + "_" + file + ".png");
            // the filter's share of the frame: Huang's link and filter stages, or Lipp's
            const double filterMs = stageMedian(m, "link") + stageMedian(m, "filter");
            cells[name].push_back(fmt(flipHair, 4) + " / " + fmt(psnrHair, 1) + " / " +
                                  fmt(m.total.median));
            qg[name][distNames[d]] = {{"flip_hair", flipHair},
                                      {"psnr_hair_db", psnrHair},
                                      {"flip", cmp.flip.mean},
                                      {"psnr_db", cmp.psnr.psnrDb},
                                      {"frame_ms", m.total.median},
                                      {"hair_pixels", nHair},
                                      {"hair_luminance", hairLuminance(f, hairMask)},
                                      {"filter_ms", filterMs},
                                      {"linked_pixels", f.stats.linkedPixels},
                                      {"link_turned_away", f.stats.linkTurnedAway}};
            std::fprintf(stderr,
                         "quality %s%s %s %s: hair FLIP %.4f PSNR %.1f (image FLIP %.4f), frame "
                         "%.1f ms, filter %.1f ms\n",
                         ltag.c_str(), groomNames[g], c.name, distNames[d], flipHair, psnrHair,
                         cmp.flip.mean, m.total.median, filterMs);
            if (!maps && g == 0 && d == 1 && c.msaa == 1 && c.filter == 0 && c.lod == 0 &&
                c.raster == 0 && c.quality == 0 && c.points == 0) {
              // SWR1 at mid against the other reference too, over the same hair pixels
              Frame other;
              const double otherMs = wallMs([&] { other = reference(s, g, d, otherMethod, ltag); });
              writeImage(other.color, out + "/quality/mid_reference_" +
                                          referenceMethodName(otherMethod) + ".png");
              const double flipOther = hairFlip(other, f, hairMask);
              const double flipRefs = hairFlip(ref, other, hairMask);
              const char* a = referenceMethodName(refMethod);
              const char* o = referenceMethodName(otherMethod);
              refMd << "\nSWR1 at mid, mean FLIP over the hair against each reference (" << refSpp
                    << " spp): " << a << " " << fmt(flipHair, 4) << ", " << o << " "
                    << fmt(flipOther, 4) << "; the " << o << " reference against the " << a
                    << " one: " << fmt(flipRefs, 4) << ". Reference wall time: " << a << " "
                    << fmt(refMs / 1000.0, 1) << " s, " << o << " " << fmt(otherMs / 1000.0, 1)
                    << " s.\n";
              q["references_mid"] = {{"swr1_flip_hair_" + std::string(a), flipHair},
                                     {"swr1_flip_hair_" + std::string(o), flipOther},
                                     {"flip_hair_between_references", flipRefs},
                                     {std::string(a) + "_wall_ms", refMs},
                                     {std::string(o) + "_wall_ms", otherMs}};
              std::fprintf(stderr, "quality SWR1 mid: hair FLIP %.4f vs %s, %.4f vs %s\n", flipHair,
                           a, flipOther, o);
            }
          }
        }
        for (const Config& c : configs) {
          if (!chosen.empty() && !chosen.count(c.name)) continue;
          md << "| " << c.name << " |";
          for (const std::string& cell : cells[c.name]) md << " " << cell << " |";
          md << "\n";
        }
        md << refMd.str();
      }
      report["quality"] = q;
      report["quality_size"] = std::to_string(qw) + "x" + std::to_string(qh);
      md << "\nImages: `" << out << "/quality/`.\n";
    }

    if (only.empty() || only == "temporal") {
      // flicker: a 30-frame orbit, the mean absolute frame-to-frame change of sRGB values;
      // with temporal reprojection (clhair/temporal.h) also the error against a per-frame
      // reference (ghosting adds error, flicker alone does not) and, on a shot whose groom
      // moves fast, the hair left behind in the pixels it vacated
      const int tw = quick ? 320 : qualityWidth, th = quick ? 180 : qualityHeight;
      const int frames = quick ? 8 : 30;
      std::set<std::string> temporalChosen;  // --quality-configs, the names this section has
      for (std::size_t at = 0; !qualityConfigs.empty() && at <= qualityConfigs.size();) {
        const std::size_t comma = std::min(qualityConfigs.find(',', at), qualityConfigs.size());
        temporalChosen.insert(qualityConfigs.substr(at, comma - at));
        at = comma + 1;
      }
      struct Config {
        const char* name;
        int msaa, filter;
        int history;      // temporal reprojection: frames of history, 0 off
        bool protect;     // the depth rule and the neighbourhood clamp
        int huang = 0;    // 0: Lipp's filter; else Huang's: 1 linking, 2 + alpha fix, 3 + filter
        int quality = 0;  // RenderOptions::quality (1: good)
      };
      const Config configs[] = {{"SWR1", 1, 0, 0, true},
                                {"good", 1, 0, 0, true, 0, 1},
                                {"SWR1+F", 1, 1, 0, true},
                                {"SWR1+H linking", 1, 1, 0, true, 1},
                                {"SWR1+H linking+alpha fix", 1, 1, 0, true, 2},
                                {"SWR1+H (linking+alpha fix+anisotropic)", 1, 1, 0, true, 3},
                                {"SWR MSAA 4", 4, 0, 0, true},
                                {"SWR1 + reprojection (3 frames)", 1, 0, 3, true},
                                {"SWR1+F + reprojection (1 frame)", 1, 1, 1, true},
                                {"SWR1+F + reprojection (3 frames)", 1, 1, 3, true},
                                {"SWR1+F + reprojection (3 frames), unprotected", 1, 1, 3, false},
                                {"SWR1+H + reprojection (1 frame)", 1, 1, 1, true, 3},
                                {"SWR1+H + reprojection (3 frames)", 1, 1, 3, true, 3}};
      auto srgbOf = [](const Frame& fr) {
        std::vector<float> srgb(fr.color.rgba.size() / 4 * 3);
        for (std::size_t i = 0; i < srgb.size(); ++i)
          srgb[i] = static_cast<float>(linearToSrgbClamped(fr.color.rgba[(i / 3) * 4 + i % 3]));
        return srgb;
      };
      // per frame: the reference and the hair mask (where it differs from the scene without hair)
      struct Truth {
        Frame ref;
        std::vector<char> mask;
      };
      auto truthOf = [&](const Scene& s) {
        Truth t;
        t.ref = b.renderer.renderReference(s, temporalRefSpp, ReferenceMethod::Embree);
        Scene bare = s;
        bare.grooms.clear();
        const Frame background = b.renderer.render(bare);
        t.mask.assign(t.ref.depth.size(), 0);
        for (std::size_t i = 0; i < t.mask.size(); ++i)
          for (int c = 0; c < 3; ++c)
            t.mask[i] |=
                std::fabs(t.ref.color.rgba[4 * i + c] - background.color.rgba[4 * i + c]) > 1e-4f;
        return t;
      };
      auto hairFlipOf = [](const Truth& t, const Frame& f) {
        const ImageComparison cmp = compareImages(t.ref.color, f.color);
        double sum = 0.0;
        std::size_t n = 0;
        for (std::size_t i = 0; i < t.mask.size(); ++i)
          if (t.mask[i]) {
            ++n;
            sum += cmp.flip.error[i];
          }
        return sum / static_cast<double>(std::max<std::size_t>(n, 1));
      };
      auto optionsOf = [](const Config& c) {
        RenderOptions o;
        o.msaa = c.msaa;
        o.filter = c.filter;
        o.lod = 0;
        o.temporal = c.history;
        o.quality = c.quality;
        return o;
      };
      auto protectedScene = [](Scene s, const Config& c) {
        s.temporal.clamp = c.protect;
        s.temporal.rejectDepth = c.protect;
        useFilter(s, c.huang);
        return s;
      };
      auto orbitAt = [&](long long f) {
        Scene s = scenes[0];
        s.width = tw;
        s.height = th;
        s.camera =
            framePreset(s, CameraPreset::Mid, 35.0f + 0.5f * static_cast<float>(f), 10.0f, 35.0f);
        return s;
      };
      std::vector<Truth> truth;
      std::size_t hairPerFrame = 0;
      for (int f = 0; f < frames; ++f) {
        truth.push_back(truthOf(orbitAt(f)));
        hairPerFrame += static_cast<std::size_t>(
            std::count(truth.back().mask.begin(), truth.back().mask.end(), 1));
      }
      hairPerFrame /= static_cast<std::size_t>(frames);
      md << "\n## Temporal stability (" << groomNames[0] << ", mid, " << frames
         << "-frame orbit of 0.5 deg per frame, " << tw << "x" << th
         << ")\n\nFlicker: mean absolute sRGB change between consecutive frames (lower is "
            "steadier). FLIP: mean over the frames of the mean FLIP over the hair's pixels "
            "against that frame's Embree reference ("
         << temporalRefSpp
         << " spp). Reprojection: the hair of the frames before carried along the motion "
            "vectors and blended (DESIGN.md, \"Temporal reprojection\"); unprotected: without "
            "its depth rule and neighbourhood clamp. Frames rendered: outputs and history "
            "frames together, in one pass over the range. Flicker (hair): the same change over "
            "the pixels that are hair in either frame's reference. Dropped / clamped: pixels "
            "per frame whose history the depth rule dropped / the clamp changed (the hair "
            "covers about "
         << hairPerFrame
         << " pixels a frame).\n\n| configuration | flicker | flicker (hair) | FLIP (hair) | "
            "dropped / clamped | ms per frame | frames rendered |\n|---|---|---|---|---|---|---|\n";
      int temporalRows = 0;
      for (const Config& c : configs) {
        if (!temporalChosen.empty() && !temporalChosen.count(c.name)) continue;
        ++temporalRows;
        FrameSequence seq(
            b.renderer, [&](long long f) { return protectedScene(orbitAt(f), c); }, optionsOf(c),
            0);
        double total = 0.0, flip = 0.0, totalHair = 0.0;
        std::vector<float> prev;
        double renderMs = 0.0;
        TemporalStats steps;
        for (int f = 0; f < frames; ++f) {
          const auto r0 = std::chrono::steady_clock::now();
          const Frame fr = seq.render(f);
          renderMs +=
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0)
                  .count();
          flip += hairFlipOf(truth[static_cast<std::size_t>(f)], fr);
          steps.rejected += seq.lastStats().rejected;
          steps.clamped += seq.lastStats().clamped;
          std::vector<float> srgb = srgbOf(fr);
          if (!prev.empty()) {
            double diff = 0.0, diffHair = 0.0;
            std::size_t nHair = 0;
            const std::vector<char>& m0 = truth[static_cast<std::size_t>(f - 1)].mask;
            const std::vector<char>& m1 = truth[static_cast<std::size_t>(f)].mask;
            for (std::size_t i = 0; i < srgb.size(); ++i) {
              const float d = std::fabs(srgb[i] - prev[i]);
              diff += d;
              if (m0[i / 3] || m1[i / 3]) {
                diffHair += d;
                ++nHair;
              }
            }
            total += diff / static_cast<double>(srgb.size());
            totalHair += diffHair / static_cast<double>(std::max<std::size_t>(nHair, 1));
          }
          prev.swap(srgb);
        }
        const double flicker = total / (frames - 1), flickerHair = totalHair / (frames - 1);
        flip /= frames;
        const double dropped = static_cast<double>(steps.rejected) / frames;
        const double clamped = static_cast<double>(steps.clamped) / frames;
        md << "| " << c.name << " | " << fmt(flicker, 5) << " | " << fmt(flickerHair, 4) << " | "
           << fmt(flip, 4) << " | " << fmt(dropped, 0) << " / " << fmt(clamped, 0) << " | "
           << fmt(renderMs / frames, 0) << " | " << seq.framesRendered() << " |\n";
        // the first three rows keep their flat numbers in bench.json (earlier reports)
        if (c.history == 0) report["temporal"][c.name] = flicker;
        report["temporal_study"][c.name] = {{"flicker", flicker},
                                            {"flicker_hair", flickerHair},
                                            {"flip_hair", flip},
                                            {"dropped_per_frame", dropped},
                                            {"clamped_per_frame", clamped},
                                            {"ms_per_frame", renderMs / frames},
                                            {"frames_rendered", seq.framesRendered()}};
        std::fprintf(stderr,
                     "temporal %s: flicker %.5f (hair %.4f), hair FLIP %.4f, dropped %.0f clamped "
                     "%.0f, %.0f ms a frame\n",
                     c.name, flicker, flickerHair, flip, dropped, clamped, renderMs / frames);
      }
      if (temporalRows == 0) {
        md << "| (none: --quality-configs names none of this section's rows) | |\n";
        std::fprintf(stderr, "temporal: --quality-configs names none of this section's rows\n");
      }
      // a fast shot: the groom translated sideways about 8 px a frame, camera still
      const int fastFrames = quick ? 5 : 10;
      const Scene fast0 = orbitAt(0);
      const float dist = glm::length(fast0.camera.position - fast0.camera.target);
      const float fy =
          0.5f * static_cast<float>(th) / std::tan(glm::radians(fast0.camera.fovYDegrees) * 0.5f);
      const float step = 8.0f * dist / fy;  // world units a frame: 8 px at the target's depth
      auto fastAt = [&](long long f) {
        Scene s = fast0;
        for (GroomInstance& gi : s.grooms)
          gi.transform =
              glm::translate(glm::mat4(1.0f), glm::vec3(step * static_cast<float>(f), 0.0f, 0.0f)) *
              gi.transform;
        return s;
      };
      std::vector<Truth> fastTruth;
      for (int f = 0; f < fastFrames; ++f) fastTruth.push_back(truthOf(fastAt(f)));
      // each frame's own hair alpha (no reprojection), for the vacated pixels
      std::vector<std::vector<float>> ownAlpha;
      {
        RenderOptions o;
        o.lod = 0;
        o.filter = 1;
        o.aovs = true;
        FrameSequence own(b.renderer, fastAt, o, 0);
        for (int f = 0; f < fastFrames; ++f) ownAlpha.push_back(own.render(f).aovs.hairAlpha);
      }
      md << "\nFast shot (the same groom translated " << fmt(step, 4)
         << " world units, about 8 px, a frame; camera still; " << fastFrames
         << " frames): in the pixels each frame vacated (hair alpha >= 0.5 in the frame before, "
            "no hair within a pixel now), the blended hair alpha (0 is right: they are "
            "background), and the share of them above 0.01; FLIP, dropped and clamped as "
            "above.\n\n| configuration | vacated pixels | trail alpha mean | trail alpha max | "
            "share > 0.01 | FLIP (hair) | dropped / clamped |\n|---|---|---|---|---|---|---|\n";
      for (const Config& c : configs) {
        // SWR1+F with and without reprojection
        if (c.msaa != 1 || c.filter != 1 || c.huang != 0) continue;
        RenderOptions o = optionsOf(c);
        o.aovs = true;
        FrameSequence seq(
            b.renderer, [&](long long f) { return protectedScene(fastAt(f), c); }, o, 0);
        std::size_t vacated = 0, trail = 0;
        double mean = 0.0, flip = 0.0;
        float worst = 0.0f;
        TemporalStats steps;
        for (int f = 0; f < fastFrames; ++f) {
          const Frame fr = seq.render(f);
          flip += hairFlipOf(fastTruth[static_cast<std::size_t>(f)], fr);
          steps.rejected += seq.lastStats().rejected;
          steps.clamped += seq.lastStats().clamped;
          if (f == 0) continue;
          const std::vector<float>& before = ownAlpha[static_cast<std::size_t>(f - 1)];
          const std::vector<float>& now = ownAlpha[static_cast<std::size_t>(f)];
          for (int y = 0; y < th; ++y)
            for (int x = 0; x < tw; ++x) {
              const std::size_t p = static_cast<std::size_t>(y) * tw + x;
              if (!(before[p] >= 0.5f)) continue;
              bool hairNear = false;
              for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                  const int qx = std::clamp(x + dx, 0, tw - 1), qy = std::clamp(y + dy, 0, th - 1);
                  hairNear = hairNear || now[static_cast<std::size_t>(qy) * tw + qx] > 0.0f;
                }
              if (hairNear) continue;
              const float a = fr.aovs.hairAlpha[p];
              ++vacated;
              mean += a;
              worst = std::max(worst, a);
              if (a > 0.01f) ++trail;
            }
        }
        mean /= static_cast<double>(std::max<std::size_t>(vacated, 1));
        flip /= fastFrames;
        const double share = static_cast<double>(trail) / std::max<std::size_t>(vacated, 1);
        md << "| " << c.name << " | " << vacated << " | " << fmt(mean, 5) << " | " << fmt(worst, 4)
           << " | " << fmt(share, 4) << " | " << fmt(flip, 4) << " | "
           << fmt(static_cast<double>(steps.rejected) / fastFrames, 0) << " / "
           << fmt(static_cast<double>(steps.clamped) / fastFrames, 0) << " |\n";
        report["temporal_study"]["fast_shot"][c.name] = {
            {"vacated_pixels", vacated},
            {"trail_alpha_mean", mean},
            {"trail_alpha_max", worst},
            {"trail_share", share},
            {"flip_hair", flip},
            {"dropped_per_frame", static_cast<double>(steps.rejected) / fastFrames},
            {"clamped_per_frame", static_cast<double>(steps.clamped) / fastFrames}};
        std::fprintf(stderr,
                     "temporal fast shot %s: %zu vacated, trail mean %.5f max %.4f share %.4f, "
                     "hair FLIP %.4f\n",
                     c.name, vacated, mean, worst, share, flip);
      }
    }

    if (only.empty() || only == "explicit") {
      // Bhokare §4: the groom as a hair mesh vs the same strands exported to cyHair and read
      // back as an explicit strand groom: device bytes and frame time of each
      std::shared_ptr<const StrandGroom> strands = exportedGroom1();
      md << "\n## Hair mesh vs explicit strands (" << groomNames[0] << ", " << width << "x"
         << height
         << ")\n\n| representation | device bytes | close, LOD off ms | far, LOD on ms "
            "|\n|---|---|---|---|\n";
      for (int explicitStrands = 0; explicitStrands < 2; ++explicitStrands) {
        Scene s = scenes[0];
        if (explicitStrands)
          s.grooms[0] = GroomInstance(s.grooms[0].name, strands, s.grooms[0].transform);
        std::uint64_t bytes = b.renderer.groomDeviceBytes(s.grooms[0]);
        RenderOptions o;
        o.lod = 0;
        Measured close = b.measure(framed(s, CameraPreset::Close, width, height), o, false);
        o.lod = 1;
        Measured far = b.measure(framed(s, CameraPreset::Far, width, height), o, false);
        const char* name = explicitStrands ? "cyHair strands" : "hair mesh";
        md << "| " << name << " | " << bytes << " | " << fmt(close.total.median) << " | "
           << fmt(far.total.median) << " |\n";
        report["explicit"][name] = {{"device_bytes", bytes},
                                    {"close_ms", close.total.median},
                                    {"far_lod_ms", far.total.median}};
        std::fprintf(stderr, "explicit %s: %llu bytes, close %.1f ms, far %.1f ms\n", name,
                     static_cast<unsigned long long>(bytes), close.total.median, far.total.median);
      }
    }

    if (only.empty() || only == "children") {
      // Children from guides (docs/scene-format.md, "Children"): 3000 guides of groom1, as a
      // guides-only TressFX export would hold them (32 points each), with 16 follow hairs
      // each, against the same 51 000 strands exported and read as a strand file. The strand
      // pass (device time, median) at each distance, LOD off and on.
      HairMesh guidesMesh = *scenes[0].grooms[0].mesh;
      guidesMesh.strandCount = 3000;
      StrandSet gs = b.renderer.generateStrands(guidesMesh);
      CyHair gh;
      for (std::uint32_t c : gs.pointCounts) gh.segments.push_back(c - 1);
      gh.points = gs.points;
      const CyHair resampled = resampleStrands(gh, 32);
      StrandGroom guides;
      guides.name = "groom1 guides";
      std::size_t at = 0;
      for (std::uint32_t seg : resampled.segments) {
        guides.pointCounts.push_back(seg + 1);
        for (std::uint32_t k = 0; k <= seg; ++k, ++at)
          guides.points.emplace_back(resampled.points[3 * at], resampled.points[3 * at + 1],
                                     resampled.points[3 * at + 2]);
      }
      guides.appearance = guidesMesh.appearance;
      guides.lod = guidesMesh.lod;
      guides.children.count = 16;
      guides.children.radius = kTressFxFollowRadiusMetres;
      guides.children.tipSpread = kTressFxTipSeparation;
      StrandSet all = b.renderer.generateStrands(guides);
      StrandGroom file;
      file.name = "groom1 children as a file";
      file.pointCounts = all.pointCounts;
      for (std::size_t i = 0; i < all.points.size(); i += 3)
        file.points.emplace_back(all.points[i], all.points[i + 1], all.points[i + 2]);
      file.appearance = guides.appearance;
      file.lod = guides.lod;
      auto kids = std::make_shared<const StrandGroom>(std::move(guides));
      auto stored = std::make_shared<const StrandGroom>(std::move(file));
      md << "\n## Children from guides (3000 guides x 17 = " << stored->pointCounts.size()
         << " strands, " << width << "x" << height
         << ")\n\n| distance | LOD | children ms | file ms | ratio |\n|---|---|---|---|---|\n";
      const CameraPreset dists[3] = {CameraPreset::Close, CameraPreset::Mid, CameraPreset::Far};
      const char* distNames[3] = {"close", "mid", "far"};
      for (int lod = 0; lod < 2; ++lod)
        for (int d = 0; d < 3; ++d) {
          RenderOptions o;
          o.lod = lod;
          Scene s = scenes[0];
          s.grooms[0] = GroomInstance("children", stored, s.grooms[0].transform);
          s = framed(s, dists[d], width, height);  // one camera for both
          Scene k = s;
          k.grooms[0].strands = kids;
          const double tk = stageMedian(b.measure(k, o, false), "strands");
          const double tf = stageMedian(b.measure(s, o, false), "strands");
          md << "| " << distNames[d] << " | " << (lod ? "on" : "off") << " | " << fmt(tk) << " | "
             << fmt(tf) << " | " << fmt(tk / tf) << " |\n";
          report["children"][std::string(distNames[d]) + (lod ? "_lod" : "")] = {
              {"children_ms", tk}, {"file_ms", tf}, {"ratio", tk / tf}};
          std::fprintf(stderr, "children %s LOD %s: strands %.1f ms, file %.1f ms, %.3fx\n",
                       distNames[d], lod ? "on" : "off", tk, tf, tk / tf);
        }
    }

    if (only.empty() || only == "crowd") {
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
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
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

    if (only.empty() || only == "mesh") {
      // groom1's head sphere (radius 0.093) against a latitude/longitude mesh of the same
      // sphere with 158 rings of 160 segments (50 240 triangles, a decimated head scan's
      // size) at close range, where the head covers the most pixels
      TriangleMesh head;
      head.name = "sphere50k";
      constexpr int kRings = 158, kSegments = 160;
      const glm::vec3 c = scenes[0].spheres.at(0).center;
      const float radius = scenes[0].spheres.at(0).radius;
      head.positions.push_back(c + glm::vec3(0, radius, 0));
      for (int i = 1; i < kRings; ++i)
        for (int j = 0; j < kSegments; ++j) {
          const float th = 3.14159265f * i / kRings, ph = 6.28318531f * j / kSegments;
          head.positions.push_back(c + radius * glm::vec3(std::sin(th) * std::cos(ph), std::cos(th),
                                                          std::sin(th) * std::sin(ph)));
        }
      head.positions.push_back(c - glm::vec3(0, radius, 0));
      const auto ring = [&](int i, int j) {
        return static_cast<std::uint32_t>(1 + (i - 1) * kSegments + j % kSegments);
      };
      const auto bottom = static_cast<std::uint32_t>(head.positions.size() - 1);
      for (int j = 0; j < kSegments; ++j) {
        head.indices.insert(head.indices.end(), {0u, ring(1, j + 1), ring(1, j)});
        head.indices.insert(head.indices.end(),
                            {bottom, ring(kRings - 1, j), ring(kRings - 1, j + 1)});
      }
      for (int i = 1; i < kRings - 1; ++i)
        for (int j = 0; j < kSegments; ++j)
          head.indices.insert(head.indices.end(), {ring(i, j), ring(i, j + 1), ring(i + 1, j + 1),
                                                   ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
      const std::size_t triangles = head.indices.size() / 3;
      auto headMesh = std::make_shared<const TriangleMesh>(std::move(head));
      md << "\n## Head as a triangle mesh (" << groomNames[0] << ", " << width << "x" << height
         << ", close, " << triangles
         << " triangles)\n\n| head | frame ms | opaque ms | mesh ms | opaque + mesh share of the "
            "frame |\n"
         << "|---|---|---|---|---|\n";
      double sphereOpaque = 0.0, sphereShare = 0.0;
      for (int asMesh = 0; asMesh < 2; ++asMesh) {
        Scene s = framed(scenes[0], CameraPreset::Close, width, height);
        if (asMesh) {
          MeshInstance mi;
          mi.name = headMesh->name;
          mi.mesh = headMesh;
          mi.color = s.spheres[0].color;
          s.spheres.clear();
          s.meshes.push_back(mi);
        }
        Measured m = b.measure(s, RenderOptions{}, false);
        const double opaqueMs = stageMedian(m, "opaque") + stageMedian(m, "mesh");
        const double share = opaqueMs / std::max(m.total.median, 1e-9);
        const char* name = asMesh ? "mesh" : "sphere";
        md << "| " << name << " | " << fmt(m.total.median) << " | " << fmt(stageMedian(m, "opaque"))
           << " | " << fmt(stageMedian(m, "mesh")) << " | " << fmt(100.0 * share, 1) << " % |\n";
        report["mesh"][name] = measuredJson(m);
        report["mesh"][name]["opaque_and_mesh_ms"] = opaqueMs;
        std::fprintf(stderr, "mesh section, %s head: frame %.1f ms, opaque %.2f ms, mesh %.2f ms\n",
                     name, m.total.median, stageMedian(m, "opaque"), stageMedian(m, "mesh"));
        if (!asMesh) {
          sphereOpaque = opaqueMs;
          sphereShare = share;
        } else {
          report["mesh"]["cost_vs_sphere"] = opaqueMs / std::max(sphereOpaque, 1e-9);
          md << "\nThe mesh head's opaque work is " << fmt(opaqueMs / std::max(sphereOpaque, 1e-9))
             << "x the sphere's (" << fmt(100.0 * share, 1) << " % against "
             << fmt(100.0 * sphereShare, 1) << " % of the frame; target: at most 2x).\n";
        }
      }
    }

    if (only.empty() || only == "floor") {
      // the strand pass against the same work as plain C++ on as many threads as the device
      // has compute units (LOD off, MSAA 1, filter off)
      std::shared_ptr<const StrandGroom> strands = exportedGroom1();
      const ExplicitData data = prepareExplicit(*strands);
      const unsigned threads = std::max(1u, dev.info().computeUnits);
      md << "\n## Strand pass vs the C++ floor (" << groomNames[0] << ", " << width << "x" << height
         << ", LOD off, MSAA 1; floor: " << threads << " threads)\n\n"
         << "| distance | C++ floor ms | explicit strands ms (x floor) | generated strands ms (x "
            "floor) | "
            "cores used: explicit / generated | floor words differing "
            "| with identity layer, x without: explicit / generated "
            "|\n|---|---|---|---|---|---|---|\n";
      // the three distances, then the default scene's camera (closer than "close": the
      // strand pass of the default frame)
      const Scene defaultView =
          loadScene(std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json");
      const char* rowNames[4] = {distNames[0], distNames[1], distNames[2], "default camera"};
      for (int d = 0; d < 4; ++d) {
        Scene sx = scenes[0];
        sx.grooms[0] = GroomInstance(sx.grooms[0].name, strands, sx.grooms[0].transform);
        Scene sg = scenes[0];
        sg.width = width;
        sg.height = height;
        if (d < 3)
          sg = framed(scenes[0], dists[d], width, height);
        else
          sg.camera = defaultView.camera;
        sx.width = width;
        sx.height = height;
        sx.camera = sg.camera;  // the same view for both
        RenderOptions o;
        o.lod = 0;
        o.filter = 0;
        o.rasterOnly = true;
        Measured mx = b.measure(sx, o, false);
        Measured mg = b.measure(sg, o, false);
        // the identity layer's cost: the same passes with and without it, interleaved
        RenderOptions oi = o;
        oi.strandIds = true;
        double idRatio[2] = {0.0, 0.0};
        for (int k = 0; k < 2; ++k) {
          const Scene& sk = k == 0 ? sx : sg;
          std::vector<double> off, on;
          for (int i = 0; i < warmup + runs; ++i) {
            const double a = b.renderer.render(sk, o).stageMs("strands");
            const double c = b.renderer.render(sk, oi).stageMs("strands");
            if (i >= warmup) {
              off.push_back(a);
              on.push_back(c);
            }
          }
          idRatio[k] = summarize(on).median / std::max(summarize(off).median, 1e-9);
        }
        // the floor: inputs captured from the device's own pass, then timed on the CPU
        RenderOptions oc = o;
        oc.captureGBuffer = true;
        const Frame f = b.renderer.render(sx, oc);
        const CpuRasterInputs in = cpuRasterInputs(f, data);
        std::vector<std::uint64_t> cpu;
        std::vector<double> ms;
        for (int i = 0; i < warmup + runs; ++i) {
          const auto t0 = std::chrono::steady_clock::now();
          cpuRasterExplicit(in, threads, cpu);
          if (i >= warmup)
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
        md << "| " << rowNames[d] << " | " << fmt(fl) << " | " << fmt(ex) << " (" << fmt(ex / fl)
           << "x) | " << fmt(ge) << " (" << fmt(ge / fl) << "x) | " << fmt(mx.cores.median) << " / "
           << fmt(mg.cores.median) << " | " << differ << " | " << fmt(idRatio[0]) << " / "
           << fmt(idRatio[1]) << " |\n";
        report["floor"][rowNames[d]] = {{"floor_ms", fl},
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
      def.width = width;
      def.height = height;
      // every frame rebuilds the deep opacity maps (a moving light or groom), then a still
      // scene that keeps them
      RenderOptions cold;
      cold.reuseShadows = false;
      Measured m = b.measure(def, cold, false);
      Measured still = b.measure(def, RenderOptions{}, false);
      // cores per stage from one more frame with every dispatch waited for and timed on the host
      RenderOptions oc = cold;
      oc.stageCores = true;
      const Frame fc = b.renderer.render(def, oc);
      md << "\n### Default scene frame (" << width << "x" << height
         << ")\n\n| | wall | device-time sum |";
      for (const auto& [k, st] : m.stages) md << " " << k << " |";
      md << "\n|---|---|---|";
      for (std::size_t i = 0; i < m.stages.size(); ++i) md << "---|";
      md << "\n| ms | " << fmt(m.wall.median) << " | " << fmt(m.total.median) << " |";
      for (const auto& [k, st] : m.stages) md << " " << fmt(st.median) << " |";
      md << "\n| cores used | " << fmt(m.cores.median) << " | |";
      for (const auto& [k, st] : m.stages) {
        double cores = 0.0;
        for (const StageTime& t : fc.timings)
          if (t.stage == k && t.wallMs > 0.0) cores = t.cpuMs / t.wallMs;
        md << " " << fmt(cores) << " |";
        report["default_frame_cores"][k] = cores;
      }
      md << "\n\nA still scene (the maps kept from the previous frame, "
            "`RenderOptions::reuseShadows`): "
         << fmt(still.wall.median) << " ms wall, " << fmt(still.total.median)
         << " ms device time.\n";
      report["default_frame_still"] = measuredJson(still);
      report["default_frame"] = measuredJson(m);
      std::fprintf(stderr,
                   "default frame: wall %.1f ms, device %.1f ms; still scene: wall %.1f ms\n",
                   m.wall.median, m.total.median, still.wall.median);
    }

    if (only.empty() || only == "sequences") {
      Scene shot = loadScene(std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/wind.json");
      const int frames = quick ? std::min(seqFrames, 8) : seqFrames;
      auto ms = [](std::chrono::steady_clock::time_point t0) {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
            .count();
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
        b.renderer.render(s, RenderOptions{});
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
          b.renderer.render(still, RenderOptions{});
          stillCold.push_back(ms(t0));
          coldCpu.push_back(processCpuMs() - c0);
          pairCpu.push_back(tc / coldCpu.back());
          c0 = processCpuMs();
          t0 = std::chrono::steady_clock::now();
          b.renderer.render(still, RenderOptions{});
          stillKept.push_back(ms(t0));
          keptCpu.push_back(processCpuMs() - c0);
        }
      }
      const Stats shotS = summarize(shotMs), keptS = summarize(stillKept),
                  coldS = summarize(stillCold);
      const Stats shotC = summarize(shotCpu), keptC = summarize(keptCpu),
                  coldC = summarize(coldCpu), pairC = summarize(pairCpu);
      double mean = 0.0;
      for (double v : shotMs) mean += v / static_cast<double>(shotMs.size());
      auto cpuCells = [&](const Stats& c, const Stats& ref) {
        return " | " + fmt(c.median, 0) + " | " + fmt(c.min, 0) + " | " + fmt(c.max, 0) + " | " +
               fmt(c.median / ref.median, 3) + "x |\n";
      };
      md << "\n## Sequences (assets/scenes/wind.json: the default groom in wind, " << still.width
         << "x" << still.height << ", " << frames
         << " frames in one process)\n\nStart-up (device, kernel compilation) " << fmt(compileMs, 0)
         << " ms, once per process; first frame " << fmt(firstMs, 0)
         << " ms.\n\n| | renders | median ms | min | max | vs still (maps kept) | CPU ms median "
            "| min | max | CPU vs still (maps kept) |\n|---|---|---|---|---|---|---|---|---|---|\n"
         << "| shot frames 2.." << frames << " (mean " << fmt(mean, 0) << ") | " << shotMs.size()
         << " | " << fmt(shotS.median, 0) << " | " << fmt(shotS.min, 0) << " | "
         << fmt(shotS.max, 0) << " | " << fmt(shotS.median / keptS.median, 3) << "x"
         << cpuCells(shotC, keptC) << "| still frame, maps kept | " << stillKept.size() << " | "
         << fmt(keptS.median, 0) << " | " << fmt(keptS.min, 0) << " | " << fmt(keptS.max, 0)
         << " | 1x" << cpuCells(keptC, keptC) << "| still frame, maps rebuilt | "
         << stillCold.size() << " | " << fmt(coldS.median, 0) << " | " << fmt(coldS.min, 0) << " | "
         << fmt(coldS.max, 0) << " | " << fmt(coldS.median / keptS.median, 3) << "x"
         << cpuCells(coldC, keptC) << "\nShot frame against the still frame that rebuilds its "
         << "maps: " << fmt(shotS.median / coldS.median, 3) << "x wall, "
         << fmt(shotC.median / coldC.median, 3) << "x process CPU (ratio of medians); pair by "
         << "pair (each rebuilt still against the shot frame before it, CPU) median "
         << fmt(pairC.median, 3) << "x, min " << fmt(pairC.min, 3) << "x, max " << fmt(pairC.max, 3)
         << "x over " << pairCpu.size() << " pairs (target within 5 %).\n";
      report["sequences"]["frames"] = frames;
      report["sequences"]["first_frame_ms"] = firstMs;
      report["sequences"]["shot_frame_ms"] = {
          {"median", shotS.median}, {"mean", mean}, {"min", shotS.min}, {"max", shotS.max}};
      report["sequences"]["still_maps_kept_ms"] = keptS.median;
      report["sequences"]["still_maps_rebuilt_ms"] = coldS.median;
      report["sequences"]["shot_vs_still"] = shotS.median / keptS.median;
      report["sequences"]["shot_vs_still_rebuilt"] = shotS.median / coldS.median;
      report["sequences"]["shot_frame_cpu_ms"] = shotC.median;
      report["sequences"]["still_maps_kept_cpu_ms"] = keptC.median;
      report["sequences"]["still_maps_rebuilt_cpu_ms"] = coldC.median;
      report["sequences"]["shot_vs_still_rebuilt_cpu"] = shotC.median / coldC.median;
      report["sequences"]["shot_vs_still_rebuilt_cpu_pairs"] = {
          {"median", pairC.median}, {"min", pairC.min}, {"max", pairC.max}};
      std::fprintf(stderr,
                   "sequences: first %.0f ms, shot median %.0f ms, still kept %.0f ms, still "
                   "rebuilt %.0f ms (%.3fx / %.3fx); CPU shot %.0f ms, still rebuilt %.0f ms "
                   "(%.3fx, pairs %.3f-%.3fx)\n",
                   firstMs, shotS.median, keptS.median, coldS.median, shotS.median / keptS.median,
                   shotS.median / coldS.median, shotC.median, coldC.median,
                   shotC.median / coldC.median, pairC.min, pairC.max);

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
      const int viewPairs = quick ? std::min(viewPairsOpt, 3) : viewPairsOpt;
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
      Renderer windRenderer(b.device);
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
        for (Renderer* r : {&b.renderer, &windRenderer}) {  // warm-up: both paths built
          const std::vector<Camera> eyes = stereo(held);
          Scene one = held;
          one.camera = eyes[0];
          r->render(one);
          r->renderViews(held, eyes);
        }
        for (int i = 0; i < viewPairs; ++i) {
          pair(b.renderer, still2, held, kept);
          // frames midFrame, midFrame + 1, ... (wrapping inside the shot)
          const int f = 2 + (midFrame - 2 + i) % std::max(frames - 1, 1);
          pair(windRenderer, wind2, sceneAtFrame(shot, static_cast<double>(f)), rebuilt);
        }
      }
      const double oneView = summarize(still2.one.ms).median,
                   twoViews = summarize(still2.two.ms).median;
      const double windOne = summarize(wind2.one.ms).median,
                   windTwo = summarize(wind2.two.ms).median;
      auto viewRow = [&](const std::string& name, const Side& side) {
        const Stats st = summarize(side.ms);
        md << "| " << name << " | " << fmt(st.median, 0) << " | " << fmt(st.min, 0) << " | "
           << fmt(st.max, 0) << " |";
      };
      md << "\n| stereo pair | median ms | min | max | two views / one |\n|---|---|---|---|---|\n";
      viewRow("(a) one view of a stereo pair, still frame, maps kept", still2.one);
      md << " |\n";
      viewRow("(a) both views, one assembly, still frame, maps kept", still2.two);
      md << " " << fmt(twoViews / oneView, 3) << "x of one view (target <= 1.6x) |\n";
      viewRow("(b) one view, wind shot frame, maps rebuilt", wind2.one);
      md << " |\n";
      viewRow("(b) both views, one assembly, wind shot frame, maps rebuilt once", wind2.two);
      md << " " << fmt(windTwo / windOne, 3) << "x of one view (target <= 1.6x) |\n";
      auto spread = [&](const char* tag, const Setting& set) {
        const Stats r = summarize(set.ratios);
        std::string list;
        for (double v : set.ratios) list += (list.empty() ? "" : ", ") + fmt(v, 2);
        md << "- " << tag << ": ratio of medians "
           << fmt(summarize(set.two.ms).median / summarize(set.one.ms).median, 3) << "x wall, "
           << fmt(summarize(set.two.cpu).median / summarize(set.one.cpu).median, 3)
           << "x process CPU; pair by pair (wall) median " << fmt(r.median, 3) << "x, min "
           << fmt(r.min, 3) << "x, max " << fmt(r.max, 3) << "x (" << list << ")\n";
        return r;
      };
      md << "\nTwo views against one, " << viewPairs
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
        md << "\nThe stereo pair stage by stage (medians over the pairs; deep opacity maps "
              "rebuilt in "
           << still2.one.shadowRuns + still2.two.shadowRuns << " of the " << 2 * viewPairs
           << " renders of (a) and " << wind2.one.shadowRuns << " + " << wind2.two.shadowRuns
           << " of (b)):\n\n"
           << "| | (a) one view ms | (a) two views ms | (a) two / one | (b) one view ms | (b) two "
              "views ms | (b) two / one |\n|---|---|---|---|---|---|---|\n";
        auto cell = [&](double a, double c) {
          md << " " << fmt(a, 1) << " | " << fmt(c, 1) << " | "
             << (a > 0.0 ? fmt(c / a, 3) + "x" : std::string("")) << " |";
        };
        auto row = [&](const std::string& name, double a1, double a2, double b1, double b2) {
          md << "| " << name << " |";
          cell(a1, a2);
          cell(b1, b2);
          md << "\n";
          report["sequences"]["views_split"][name] = {{"one", a1}, {"two", a2}};
          report["sequences"]["wind_views_split"][name] = {{"one", b1}, {"two", b2}};
        };
        auto stage = [](const Side& side, const std::string& k) {
          auto it = side.stages.find(k);
          return it == side.stages.end() ? 0.0 : summarize(it->second).median;
        };
        for (const std::string& k : names)
          row(k, stage(still2.one, k), stage(still2.two, k), stage(wind2.one, k),
              stage(wind2.two, k));
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
        report["sequences"]["one_view_cpu_ms"] = med(still2.one.cpu);
        report["sequences"]["two_views_cpu_ms"] = med(still2.two.cpu);
        report["sequences"]["wind_one_view_cpu_ms"] = med(wind2.one.cpu);
        report["sequences"]["wind_two_views_cpu_ms"] = med(wind2.two.cpu);
        report["sequences"]["views_shadow_rebuilds"] =
            still2.one.shadowRuns + still2.two.shadowRuns;
        report["sequences"]["wind_views_shadow_rebuilds"] =
            wind2.one.shadowRuns + wind2.two.shadowRuns;
      }
      report["sequences"]["view_pairs"] = viewPairs;
      report["sequences"]["one_view_ms"] = oneView;
      report["sequences"]["two_views_ms"] = twoViews;
      report["sequences"]["two_views_vs_one"] = twoViews / oneView;
      report["sequences"]["two_views_vs_one_pairs"] = {
          {"median", stillR.median}, {"min", stillR.min}, {"max", stillR.max}};
      report["sequences"]["wind_one_view_ms"] = windOne;
      report["sequences"]["wind_two_views_ms"] = windTwo;
      report["sequences"]["wind_two_views_vs_one"] = windTwo / windOne;
      report["sequences"]["wind_two_views_vs_one_pairs"] = {
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
          const Frame a = b.renderer.render(s0, o);
          o.previous = &s0;
          auto t0 = std::chrono::steady_clock::now();
          const Frame c = b.renderer.render(s1, o);
          if (aovMs) *aovMs += ms(t0) / static_cast<double>(starts.size());
          if (plainMs) {
            t0 = std::chrono::steady_clock::now();
            b.renderer.render(s1, RenderOptions{});
            *plainMs += ms(t0) / static_cast<double>(starts.size());
          }
          warped += motionWarpIoU(c.aovs, a.aovs, s1.width, s1.height) /
                    static_cast<double>(starts.size());
          unwarped +=
              maskIoU(c.aovs, a.aovs, s1.width, s1.height) / static_cast<double>(starts.size());
        }
      };
      std::vector<int> starts;
      for (int f = 2; f + 1 <= std::max(frames, 3); f += std::max(1, frames / 4))
        starts.push_back(f);
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
          const Frame a = b.renderer.render(s0, o);
          o.previous = &s0;
          const Frame cf = b.renderer.render(s1, o);
          turnIoU += motionWarpIoU(cf.aovs, a.aovs, s1.width, s1.height) / pairs;
          turnStill += maskIoU(cf.aovs, a.aovs, s1.width, s1.height) / pairs;
        }
      }
      md << "\nMotion vectors, frame t warped to t+1 by t+1's motion (docs/aovs.md, mean over "
         << starts.size()
         << " pairs): \n\n| shot | IoU warped | IoU not warped | target |\n|---|---|---|---|\n"
         << "| slow turntable (default scene, 0.5 deg a frame) | " << fmt(turnIoU, 3) << " | "
         << fmt(turnStill, 3) << " | >= 0.9 |\n"
         << "| wind shot | " << fmt(windIoU, 3) << " | " << fmt(windStill, 3)
         << " | >= 0.8 |\n\nA wind frame with `--aov all` (motion pass included): " << fmt(aovMs, 0)
         << " ms, without: " << fmt(plainMs, 0) << " ms.\n";
      report["sequences"]["iou_turntable"] = turnIoU;
      report["sequences"]["iou_turntable_unwarped"] = turnStill;
      report["sequences"]["iou_wind"] = windIoU;
      report["sequences"]["iou_wind_unwarped"] = windStill;
      report["sequences"]["aov_frame_ms"] = aovMs;
      report["sequences"]["plain_frame_ms"] = plainMs;
      std::fprintf(stderr, "sequences IoU: turntable %.3f (%.3f), wind %.3f (%.3f)\n", turnIoU,
                   turnStill, windIoU, windStill);
    }

    if (only.empty() || only == "lodfar") {
      bench::LodFarOptions lf;
      lf.scene = std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json";
      lf.width = quick ? 320 : qualityWidth;
      lf.height = quick ? 180 : qualityHeight;
      lf.runs = std::max(runs, 1);
      lf.warmup = warmup;
      bench::lodFarSection(b.renderer, lf, md, report);
    }

    if (only.empty() || only == "throughput") {
      tp.width = tpWidth > 0 ? tpWidth : width;
      tp.height = tpHeight > 0 ? tpHeight : height;
      if (quick) tp.frames = std::min(tp.frames, 12);
      tp.outDir = out + "/throughput-frames";
      bench::throughputSection(dev, tp, md, report);
    }

    std::filesystem::create_directories(out);
    std::ofstream(out + "/bench.json") << report.dump(2) << "\n";
    std::ofstream(out + "/bench.csv") << csv.str();
    std::ofstream(out + "/bench.md") << md.str();
    std::printf("%s", md.str().c_str());
    std::fprintf(stderr, "wrote %s/bench.{json,csv,md}\n", out.c_str());
  } catch (const cl::Error& e) {
    std::fprintf(stderr, "clhair_bench: error: OpenCL %s (%d)\n", e.what(), e.err());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "clhair_bench: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
