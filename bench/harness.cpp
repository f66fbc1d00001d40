// harness.cpp — see harness.h: options, timing and medians, the report's header and files.
#include "harness.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <CLI/CLI.hpp>

#include "cl/dispatch.h"
#include "io/cyhair.h"
#include "metrics/image_metrics.h"

namespace clhair::bench {

Stats summarize(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  return s;
}

Measured Bench::measure(const Scene& scene, RenderOptions o, bool counts) {
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

std::string fmt(double v, int digits) {
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

void useFilter(Scene& s, int huang, std::optional<bool> promote) {
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

Scene framed(Scene s, CameraPreset p, int w, int h) {
  s.width = w;
  s.height = h;
  s.camera = framePreset(s, p, 35.0f, 10.0f, 35.0f);
  return s;
}

double maskedFlip(const Image& ref, const Image& test, const std::vector<char>& mask) {
  const ImageComparison cmp = compareImages(ref, test);
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) {
      sum += cmp.flip.error[i];
      ++n;
    }
  return n ? sum / static_cast<double>(n) : 0.0;
}

std::optional<int> parseOptions(int argc, char** argv, Options& o) {
  CLI::App app{"clhair_bench: speed of the clhair pipeline on one device"};
  DeviceOptions& dopts = o.dopts;
  std::string &out = o.out, &only = o.only, &sceneDir = o.sceneDir;
  int &runs = o.runs, &warmup = o.warmup, &width = o.width, &height = o.height, &refSpp = o.refSpp,
      &qualityWidth = o.qualityWidth, &qualityHeight = o.qualityHeight, &seqFrames = o.seqFrames,
      &temporalRefSpp = o.temporalRefSpp, &viewPairsOpt = o.viewPairsOpt;
  bool& quick = o.quick;
  std::string &qualityGrooms = o.qualityGrooms, &refName = o.refName, &refCache = o.refCache,
              &qualityConfigs = o.qualityConfigs, &qualityDistances = o.qualityDistances,
              &qualityLights = o.qualityLights;
  app.add_option("--device", dopts.selector, "device: P:D or a name substring");
  app.add_option("--out", out, "folder for bench.json, bench.csv, bench.md");
  app.add_option(
      "--only", only,
      "one section: table1, dispatch, scaling, atomics, quality, temporal, explicit, children, "
      "mesh, crowd, floor, sequences, lodfar, throughput, look, pixels");
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
  app.add_option("--pixel-sizes", o.pixelSizes,
                 "pixels section: image sizes, comma-separated WxH (480x270,...,3840x2160)");
  app.add_option(
      "--pixel-parts", o.pixelParts,
      "pixels section: cost (default scene by size), flip (against the reference, "
      "--quality-grooms and --quality-distances; scenemaps: a column with the maps at the "
      "scene's resolution), final (against Embree at equal spp)");
  app.add_option("--pixel-k", o.pixelK,
                 "pixels section: FLIP columns with every groom at these strands per pixel");
  app.add_option("--look-scattering", o.lookScattering,
                 "look section: multiple (default) or both (also rows with the light between "
                 "fibres left out)")
      ->check(CLI::IsMember({"multiple", "both"}));
  app.add_option("--look-final-passes", o.lookFinalPasses,
                 "look section: passes of the final level (16)")
      ->check(CLI::Range(1, 4096));
  app.add_option("--look-ref-seed", o.lookRefSeed,
                 "look section: the path references' seed (1; another gives an independent "
                 "reference, to measure the references' own noise)");
  app.add_option("--look-rows", o.lookRows,
                 "look section: only these rows, comma-separated tags (groom1_eu0.3, "
                 "groom2_eu8.0, blonde_file, dark_blonde_file, ...); default all");
  app.add_option("--look-light", o.lookLight,
                 "look section: all (default), lights (the ambient light off) or ambient (the "
                 "lights off): one kind of light at a time")
      ->check(CLI::IsMember({"all", "lights", "ambient"}));
  app.add_flag("--look-scales", o.lookScales,
               "look section: also the FLIP left with every feature coarser than 1-32 px made "
               "exact, and the hair's contrast per octave of scale (look_scales.h)");
  app.add_option("--look-path-events", o.lookPathEvents,
                 "look section: scattering events per path of the reference (64; 1: the lights' "
                 "single scattering, 2: the ambient light's, against --look-scattering both's "
                 "single-scattering rows)")
      ->check(CLI::Range(1, 1024));
  app.add_option("--temporal-ref-spp", temporalRefSpp,
                 "temporal section: samples per pixel of each frame's reference (default 4)")
      ->check(CLI::Range(1, 4096));
  app.add_option("--seq-frames", seqFrames, "sequences section: frames of the wind shot (120)")
      ->check(CLI::Range(3, 100000));
  app.add_option("--view-pairs", viewPairsOpt,
                 "sequences section: interleaved one-view / two-view pairs per setting (9)")
      ->check(CLI::Range(1, 1000));
  ThroughputOptions& tp = o.tp;
  tp.scene = std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/wind.json";
  tp.cli = CLHAIR_BENCH_CLI;
  int &tpWidth = o.tpWidth, &tpHeight = o.tpHeight;
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
  if (quick) {
    runs = 1;
    warmup = 1;
    width = 640;
    height = 360;
  }
  return std::nullopt;
}

Run::Run(const Options& options)
    : opt(options),
      dev(Device::open(DeviceOptions::fromEnvironment(opt.dopts))),
      b{dev, Renderer(dev), opt.warmup, opt.runs} {
  const int runs = opt.runs, warmup = opt.warmup;
  compileMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started_)
                  .count();
  const DeviceInfo& info = dev.info();
  report["device"] = info.name;
  report["platform"] = info.platformName;
  report["driver"] = info.driverVersion;
  report["opencl"] = info.version;
  report["subgroup_backend"] = subgroupBackendName(info.backend);
  report["revision"] = gitRevision();
  report["runs"] = runs;
  report["warmup"] = warmup;
  report["startup_and_compile_ms"] = compileMs;
  md << "# clhair benchmark\n\n"
     << "device: " << info.name << " (" << info.platformName << ", driver " << info.driverVersion
     << "), sub-group backend " << subgroupBackendName(info.backend) << ", revision "
     << report["revision"].get<std::string>() << "; median of " << runs << " runs after " << warmup
     << " warm-up; device times from profiling events. Start-up incl. kernel compilation: "
     << fmt(compileMs, 0) << " ms.\n\n";
  csv << "section,groom,lod,msaa,distance,strands_target,width,height,dispatch,total_ms,strands_"
         "ms,lod_ms,shade_ms,"
         "composite_ms,strands,segments,pixel_writes,atomics_issued,atomics_skipped\n";
  const std::string& sceneDir = opt.sceneDir;
  scenes[0] = loadScene(sceneDir + "/groom1.json");
  scenes[1] = loadScene(sceneDir + "/groom2.json");
}

void Run::write() const {
  const std::string& out = opt.out;
  std::filesystem::create_directories(out);
  std::ofstream(out + "/bench.json") << report.dump(2) << "\n";
  std::ofstream(out + "/bench.csv") << csv.str();
  std::ofstream(out + "/bench.md") << md.str();
  std::printf("%s", md.str().c_str());
  std::fprintf(stderr, "wrote %s/bench.{json,csv,md}\n", out.c_str());
}

std::shared_ptr<const StrandGroom> Run::exportedGroom1() {
  std::shared_ptr<const StrandGroom>& exported = exported_;
  const std::string& out = opt.out;
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
}

void Run::csvRow(const std::string& section, const std::string& groom, int lod, int msaa,
                 const std::string& dist, std::int64_t strandsTarget, int w, int h,
                 const std::string& dispatch, const Measured& m) {
  csv << section << ",\"" << groom << "\"," << lod << "," << msaa << "," << dist << ","
      << strandsTarget << "," << w << "," << h << "," << dispatch << "," << m.total.median << ","
      << stageMedian(m, "strands") << "," << stageMedian(m, "lod") << "," << stageMedian(m, "shade")
      << "," << stageMedian(m, "composite") << "," << m.counts.strandsDrawn << ","
      << m.counts.segmentsDrawn << "," << m.counts.pixelWrites << "," << m.counts.atomicsIssued
      << "," << m.counts.atomicsSkipped << "\n";
}

}  // namespace clhair::bench
