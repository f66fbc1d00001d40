// render.h — `clhair render`, in three files: render_options.cpp (its options and the
// parsing of their values), render_plan.cpp (every check before the first frame: the flags,
// the device, the scene, the views, the RenderOptions) and render.cpp (the frames: submitted,
// drawn while earlier ones are written, reported). cmdRender is what main.cpp dispatches to.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "clhair/aov.h"
#include "clhair/device.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/write_queue.h"

namespace clhair::cli {

// `clhair render`'s options as given on the command line.
struct RenderFlags {
  std::string scenePath, out;  // the scene file and -o
  int width = 0, height = 0, msaa = 1, spp = 256;
  bool reference = false;
  std::string referenceMethod;  // embree (also when --reference has no value), raster or path
  int pathEvents = 64;          // --reference path: scattering events per path
  std::string filter = "auto";
  bool widthGiven = false, heightGiven = false;
  std::string camera, lod, dispatch = "auto", ao = "on", visibility = "on", lodBsdf = "single",
                           scattering = "multiple";
  bool quiet = false;
  std::string frames;        // "N", "A-B" or "A-B:STEP"
  bool framesGiven = false;  // --frames given (even empty, which is refused); else frame 1
  bool skipExisting = false;
  std::string aov;            // --aov list; empty: the beauty alone through writeImage
  std::string views;          // --views: "all" or names; empty: all of the scene's "cameras"
  bool stats = false;         // --stats: strands and segments per groom instance
  bool trueWidth = false;     // --true-width (RenderOptions::trueWidth)
  std::string segmentBudget;  // --segment-budget; empty: the scene's
  std::string budgetRule = "screen";  // --budget-rule screen|uniform
  std::string raster;                 // --raster lines|coverage; empty: the scene's
  std::string temporal;               // --temporal; empty: the scene's "temporal"
  std::string screenBoxes = "on";     // --screen-boxes on|off (RenderOptions::screenBoxes)
  int framesInFlight = 2;             // --frames-in-flight (Renderer::setFramesInFlight)
  int encodeThreads = 0;              // --encode-threads (WriteQueue; 0: automatic)
  bool passes = false;                // --passes: print the first frame's graph
  ImageWriteOptions write;            // --png-compression, --exr-compression
  std::string quality;                // --quality draft|good|final; empty: the scene's
  std::string shadowLod;              // --shadow-lod camera|light|off; empty: camera
  std::string shading;                // --shading sample|point; empty: the level's
  bool sppGiven = false;              // --spp given (final's passes; else the level's default)
  int finalSubset = 1;                // --final-subset (RenderOptions::finalSubset)
  bool finalSubsetGiven = false;
};

// Adds `render` and its options to the command; noteRenderFlagsGiven records, after parsing,
// which options were given (those whose absence means "as the scene says").
CLI::App* addRenderCommand(CLI::App& app, RenderFlags& f);
void noteRenderFlagsGiven(const CLI::App& render, RenderFlags& f);

// Renders the frames and views the flags ask for (render.cpp); 0 on success, else throws.
int cmdRender(const DeviceOptions& opts, const std::string& scenePath, const std::string& out,
              const RenderFlags& f);

// ---- option values (render_options.cpp) ---------------------------------------------------

// --temporal: frames of history 0 (off) .. kMaxTemporalHistory.
int parseTemporal(const std::string& v);
// --segment-budget: a whole number 0 (none) .. kMaxSegmentBudget.
std::int64_t parseSegmentBudget(const std::string& v);
// --frames: the frame numbers of "7", "1-240", "1-240:5", "240-1" (in reverse).
std::vector<long long> parseFrames(const std::string& spec);
// --png-compression and --exr-compression, refused before any work with the flag named.
void checkWriteFlags(const ImageWriteOptions& w);
// --views: the views a render writes (the scene's "cameras", or its camera alone).
std::vector<View> selectViews(const Scene& scene, const std::string& spec);
// The output of view `name` for the -o pattern (%v, or the name before the extension).
std::string viewPath(const std::string& pattern, const std::string& name, bool several);

// ---- before the first frame (render_plan.cpp) ----------------------------------------------

// What the checks of a render settled: the open device, the loaded scene, the frames and
// views to write, the layers of --aov and the options every frame is rendered with.
struct RenderPlan {
  explicit RenderPlan(Device d) : dev(std::move(d)) {}
  Device dev;
  Scene scene;
  std::vector<long long> frames;
  std::vector<Aov> aovs;
  std::vector<View> views;
  bool several = false;       // more than one view
  bool temporal = false;      // reprojection on (--temporal or the scene's)
  bool finalQuality = false;  // --quality final (or the scene's) without --reference
  RenderOptions ro;
  std::optional<CameraPreset> preset;  // --camera
  ReferenceOptions ref;
};

// Every check of a render's flags, in the order the user meets them; throws the first failure.
RenderPlan planRender(const DeviceOptions& opts, const std::string& scenePath,
                      const std::string& out, const RenderFlags& f);

// ---- the frames (render.cpp) ---------------------------------------------------------------

// A reference's progress on stderr (passes done, time left).
std::function<void(int, int)> referenceProgress();

}  // namespace clhair::cli
