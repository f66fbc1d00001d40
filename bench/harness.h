// harness.h — what every section of clhair_bench shares: the command line's options, the
// device and renderer of the run, timing a configuration (medians of the stage device
// times, wall clock and cores used after warm-up), the two benchmark grooms and their
// camera presets, and the report being written (bench.md, bench.csv, bench.json). A
// section is a function `void runName(Run&)` in a file of its own, registered in main.cpp.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "clhair/device.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/strand_groom.h"
#include "masked_flip.h"
#include "throughput.h"

namespace clhair::bench {

using nlohmann::json;

struct Stats {
  double median = 0, min = 0, max = 0;
};

Stats summarize(std::vector<double> v);

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

  // warmup untimed frames, then runs timed ones; with counts, one more frame with the
  // raster's statistics on (never timed)
  Measured measure(const Scene& scene, RenderOptions o, bool counts = true);
};

std::string gitRevision();
std::string fmt(double v, int digits = 2);
json measuredJson(const Measured& m);

// Sets the reconstruction filter of the scene and of each groom in it: Lipp's (huang 0) or
// Huang's parts (1 linking, 2 + alpha fix, 3 + anisotropic filter), and the strand connection
// when given.
void useFilter(Scene& s, int huang, std::optional<bool> promote = std::nullopt);

double stageMedian(const Measured& m, const std::string& stage);

// The scene at w x h, its camera at one of the presets (the benchmark's fixed angles).
Scene framed(Scene s, CameraPreset p, int w, int h);

// The command line (clhair_bench --help).
struct Options {
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
  // pixels: the sizes, and which tables (cost, flip, final; comma-separated)
  std::string pixelSizes = "480x270,960x540,1920x1080,3840x2160";
  std::string pixelParts = "cost,flip,final";
  std::string pixelK;  // pixels: FLIP columns at these strands per pixel (comma-separated)
  std::string lookScattering = "multiple";  // look: multiple, or both (single-scattering rows too)
  int lookFinalPasses = 16;                 // look: passes of the final level
  std::string lookLight = "all";            // look: all, lights (no ambient) or ambient (no lights)
  std::string lookRows;           // look: the rows (tags, comma-separated) to measure; empty: all
  std::uint32_t lookRefSeed = 1;  // look: the path references' seed (their own noise, apart)
  int lookPathEvents = 64;        // look: scattering events of the path reference
  bool lookScales = false;        // look: the FLIP left per scale and the contrast per octave
  ThroughputOptions tp;
  int tpWidth = 0, tpHeight = 0;
};

// Parses the command line into o (--quick applied); an exit status when the program is to
// end here (--help, or a bad option, whose message CLI11 printed), else nothing.
std::optional<int> parseOptions(int argc, char** argv, Options& o);

// One benchmark run: the device opened (start-up and kernel compilation timed), the
// report's header written, the two grooms loaded. Sections append to md, csv and report.
class Run {
 public:
  explicit Run(const Options& options);

  // bench.json, bench.csv and bench.md into --out; the markdown printed
  void write() const;

  // groom1's generated strands exported to cyHair and read back (once), with the mesh's
  // appearance and LOD settings: the explicit-strand twin of groom1
  std::shared_ptr<const StrandGroom> exportedGroom1();

  void csvRow(const std::string& section, const std::string& groom, int lod, int msaa,
              const std::string& dist, std::int64_t strandsTarget, int w, int h,
              const std::string& dispatch, const Measured& m);

 private:
  const std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  std::shared_ptr<const StrandGroom> exported_;

 public:
  const Options opt;
  Device dev;
  Bench b;
  double compileMs = 0.0;  // start-up incl. kernel compilation
  json report;
  std::ostringstream md, csv;
  Scene scenes[2];
  const char* groomNames[2] = {"groom1 (long_wavy)", "groom2 (curly_medium)"};
  const CameraPreset dists[3] = {CameraPreset::Close, CameraPreset::Mid, CameraPreset::Far};
  const char* distNames[3] = {"close", "mid", "far"};
  // table1's MSAA-1 rows, for the atomic-floor multiples
  std::vector<std::pair<std::string, Measured>> msaa1Rows;
};

}  // namespace clhair::bench
