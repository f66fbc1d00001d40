// render_plan.cpp — everything `clhair render` checks before its first frame, in the order a
// user meets it: the flags that need no device (frames, -o, --aov, writers), then the device,
// the scene and its views, then the RenderOptions the flags and the scene make together. Any
// refusal is one Error, thrown before a file is written.
#include <algorithm>
#include <cstdio>

#include "clhair/error.h"
#include "clhair/progressive.h"
#include "clhair/temporal.h"
#include "io/json_util.h"
#include "io/regular_file.h"
#include "io/safe_write.h"
#include "options.h"
#include "outputs.h"
#include "render.h"

namespace clhair::cli {

RenderPlan planRender(const DeviceOptions& opts, const std::string& scenePath,
                      const std::string& out, const RenderFlags& f) {
  const int width = f.width, height = f.height;  // 0 = not given
  const std::string& camera = f.camera;
  const std::string& lod = f.lod;
  const bool quiet = f.quiet;
  const std::vector<long long> frames =
      f.framesGiven ? parseFrames(f.frames) : std::vector<long long>{1};
  if (frames.size() > 1 && framePath(out, 0) == out)
    throw Error("-o \"" + out + "\" has no '#' for the frame number, but --frames \"" + f.frames +
                "\" names " + std::to_string(frames.size()) +
                " frames: write e.g. out.####.exr (#### becomes 0007 for frame 7)");
  std::vector<Aov> aovs;
  if (!f.aov.empty()) {
    aovs = parseAovList(f.aov);
    if (lowerExtension(out) != ".exr")
      throw Error("--aov \"" + f.aov + "\" writes one multi-channel OpenEXR file, but -o \"" + out +
                  "\" is not .exr");
    if (f.reference) throw Error("--aov is not available with --reference");
    const auto strand = std::find(aovs.begin(), aovs.end(), Aov::Strand);
    if (strand != aovs.end() && f.msaa != 1) {
      // "all" means every layer this frame can have; naming the layer asks for MSAA 1
      const bool all = ("," + f.aov + ",").find(",all,") != std::string::npos;
      if (!all)
        throw Error("--aov strand needs --msaa 1 (one strand per pixel), not --msaa " +
                    std::to_string(f.msaa));
      aovs.erase(strand);
    }
    const bool crypto = std::find(aovs.begin(), aovs.end(), Aov::Cryptomatte) != aovs.end();
    if (crypto && f.msaa != 1)
      throw Error(
          "--aov cryptomatte needs --msaa 1 (it reads one strand identity per pixel), not "
          "--msaa " +
          std::to_string(f.msaa));
  }
  if (f.framesInFlight < 1 || f.framesInFlight > kMaxFramesInFlight)
    throw Error("--frames-in-flight must be 1.." + std::to_string(kMaxFramesInFlight) + ", not " +
                std::to_string(f.framesInFlight));
  if (f.encodeThreads < 0 || f.encodeThreads > 64)
    throw Error("--encode-threads must be 0 (automatic) .. 64, not " +
                std::to_string(f.encodeThreads));
  if (!f.views.empty() && f.views != "all" && f.views.find_first_of("/\\") != std::string::npos)
    throw Error("--views \"" + f.views + "\": expected all or view names");
  checkWriteFlags(f.write);
  checkImageFormat(out);  // -o x.xyz: refused before any work (folders: once the views are known)
  checkNotAnInput("-o", framePath(out, frames[0]), {{"the scene", scenePath}});
  { RegularFile scene(scenePath, "scene"); }  // a missing scene is named before the device opens
  // the device first: strand files are checked against its largest allocation as they load
  Device dev = Device::open(opts);
  Scene scene = loadScene(scenePath, dev.info().maxAlloc);
  for (const std::string& w : scene.warnings)
    std::fprintf(stderr, "clhair: warning: %s\n", w.c_str());
  if (!quiet)
    for (const std::string& n : scene.notes) std::fprintf(stderr, "clhair: note: %s\n", n.c_str());
  const std::vector<View> views = selectViews(scene, f.views);
  const bool several = views.size() > 1;
  if (several && !aovs.empty())
    throw Error("--aov writes one view; this render has " + std::to_string(views.size()) +
                " (choose one with --views NAME)");
  if (several && f.reference)
    throw Error("--reference renders one view; choose one with --views NAME");
  for (const View& v : views) checkOutputPath(framePath(viewPath(out, v.name, several), frames[0]));
  {  // no frame of any view writes over a file the scene reads (strands, images, meshes)
    std::vector<NamedFile> files;
    for (const std::string& file : scene.files) files.push_back({"a file the scene reads", file});
    const InputFiles inputs(files);
    for (const View& v : views)
      for (long long frame : frames)
        inputs.check("-o", framePath(viewPath(out, v.name, several), frame));
  }
  if (f.widthGiven || f.heightGiven) {
    int w = f.widthGiven ? width : scene.width, h = f.heightGiven ? height : scene.height;
    if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide)
      throw Error("resolution " + std::to_string(w) + "x" + std::to_string(h) + " is outside 1.." +
                  std::to_string(kMaxImageSide) + " per side");
    scene.width = w;
    scene.height = h;
  }
  RenderOptions ro;
  if (lod == "on")
    ro.lod = Toggle::On;
  else if (lod == "off")
    ro.lod = Toggle::Off;
  else if (!lod.empty() && lod != "auto")
    throw Error("--lod must be on, off or auto, not \"" + lod + "\"");
  if (f.msaa != 1 && f.msaa != 2 && f.msaa != 4 && f.msaa != 8)
    throw Error("--msaa must be 1, 2, 4 or 8, not " + std::to_string(f.msaa));
  ro.msaa = f.msaa;
  ro.dispatch = parseDispatchMode(f.dispatch);
  if (f.ao != "on" && f.ao != "off") throw Error("--ao must be on or off, not \"" + f.ao + "\"");
  ro.ambientOcclusion = f.ao == "on";
  if (f.visibility != "on" && f.visibility != "off")
    throw Error("--visibility must be on or off, not \"" + f.visibility + "\"");
  ro.bakedVisibility = f.visibility == "on";
  if (f.lodBsdf != "aggregated" && f.lodBsdf != "single")
    throw Error("--lod-bsdf must be aggregated or single, not \"" + f.lodBsdf + "\"");
  ro.lodAggregate = f.lodBsdf == "aggregated";
  if (f.scattering != "multiple" && f.scattering != "single")
    throw Error("--scattering must be multiple or single, not \"" + f.scattering + "\"");
  ro.multipleScattering = f.scattering == "multiple";
  ro.aovs = std::any_of(aovs.begin(), aovs.end(), [](Aov a) { return a != Aov::Rgba; });
  ro.strandIds = std::find(aovs.begin(), aovs.end(), Aov::Strand) != aovs.end();
  ro.cryptomatte = std::find(aovs.begin(), aovs.end(), Aov::Cryptomatte) != aovs.end();
  if (f.filter == "on") {
    ro.filter = Toggle::On;
  } else if (f.filter == "off") {
    ro.filter = Toggle::Off;
  } else if (f.filter == "lipp" || f.filter == "huang") {
    ro.filter = Toggle::On;
    ro.filterMethod =
        f.filter == "huang" ? FilterParams::Method::Huang : FilterParams::Method::Lipp;
  } else if (f.filter != "auto") {
    throw Error("--filter must be on, off, auto, lipp or huang, not \"" + f.filter + "\"");
  }
  if (!f.segmentBudget.empty()) ro.segmentBudget = parseSegmentBudget(f.segmentBudget);
  if (f.budgetRule != "screen" && f.budgetRule != "uniform")
    throw Error("--budget-rule must be screen or uniform, not \"" + f.budgetRule + "\"");
  ro.budgetRule = f.budgetRule == "screen" ? BudgetRule::Screen : BudgetRule::Uniform;
  if (f.screenBoxes != "on" && f.screenBoxes != "off")
    throw Error("--screen-boxes must be on or off, not \"" + f.screenBoxes + "\"");
  ro.screenBoxes = f.screenBoxes == "on";
  ro.trueWidth = ro.trueWidth || f.trueWidth;
  if (f.raster == "lines" || f.raster == "coverage")
    ro.raster = f.raster == "coverage" ? RasterMode::Coverage : RasterMode::Lines;
  else if (!f.raster.empty())
    throw Error("--raster must be lines or coverage, not \"" + f.raster + "\"");
  if (!f.temporal.empty()) ro.temporal = parseTemporal(f.temporal);
  const bool temporal = (ro.temporal < 0 ? scene.temporal.history : ro.temporal) > 0;
  if (temporal && (several || f.reference))
    throw Error(std::string("temporal reprojection (--temporal or the scene's \"temporal\") ") +
                "renders one view with the real-time pipeline, not " +
                (several ? "several views (choose one with --views NAME)" : "--reference") +
                "; --temporal 0 turns it off");
  if (f.reference && (f.spp < 1 || f.spp > 65536))
    throw Error("--spp must be 1..65536, not " + std::to_string(f.spp));
  ro.quality = parseQualityFlag(f.quality);
  if (f.shading == "point") {
    ro.pointShading = Toggle::On;
  } else if (f.shading == "sample") {
    ro.pointShading = Toggle::Off;
  } else if (!f.shading.empty()) {
    throw Error("--shading must be sample or point, not \"" + f.shading + "\"");
  }
  if (f.shadowLod == "light") {
    ro.shadowLodCamera = Toggle::Off;
  } else if (f.shadowLod == "off") {
    ro.shadowLod = Toggle::Off;
  } else if (!f.shadowLod.empty() && f.shadowLod != "camera") {
    throw Error("--shadow-lod must be camera, light or off, not \"" + f.shadowLod + "\"");
  }
  const bool final = !f.reference && qualityLevel(scene, ro) == Quality::Final;
  if (f.sppGiven && !f.reference && !final)
    throw Error("--spp counts the samples of --reference or the passes of --quality final");
  if (final && f.sppGiven) {
    if (f.spp < 1 || f.spp > kMaxFinalPasses)
      throw Error("--spp must be 1.." + std::to_string(kMaxFinalPasses) +
                  " passes with --quality final, not " + std::to_string(f.spp));
    ro.spp = f.spp;
  }
  if (f.finalSubsetGiven && !final)
    throw Error("--final-subset chooses the strands of --quality final's passes");
  if (f.finalSubsetGiven) {
    if (f.finalSubset < 1 || f.finalSubset > kMaxFinalSubset)
      throw Error("--final-subset must be 1.." + std::to_string(kMaxFinalSubset) + ", not " +
                  std::to_string(f.finalSubset));
    ro.finalSubset = f.finalSubset;
  }
  if (final && (several || temporal))
    throw Error(std::string("--quality final renders one view without temporal reprojection (") +
                (several ? "choose one with --views NAME" : "--temporal 0 turns it off") + ")");
  if (f.pathEvents < 1 || f.pathEvents > 1024)
    throw Error("--path-events must be 1..1024, not " + std::to_string(f.pathEvents));
  const CameraPreset* preset = nullptr;
  CameraPreset presetValue{};
  if (!camera.empty()) {
    presetValue = parseCameraPreset(camera);
    preset = &presetValue;
  }
  ReferenceOptions ref;
  ref.spp = f.spp;
  ref.pathEvents = f.pathEvents;
  if (f.reference && !f.referenceMethod.empty())
    ref.method = parseReferenceMethod(f.referenceMethod);
  if (f.reference && !quiet) ref.progress = referenceProgress();
  RenderPlan plan(std::move(dev));
  plan.scene = std::move(scene);
  plan.frames = frames;
  plan.aovs = std::move(aovs);
  plan.views = views;
  plan.several = several;
  plan.temporal = temporal;
  plan.finalQuality = final;
  plan.ro = ro;
  if (preset) plan.preset = *preset;
  plan.ref = std::move(ref);
  return plan;
}

}  // namespace clhair::cli
