// render_options.cpp — the options of `clhair render` (their names, help texts and defaults,
// the shared groups from options.h among them) and the parsing of the values that need more
// than a type: frame ranges, history and budget counts, image-writer settings, view lists
// and the output path of each view.
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>

#include "clhair/error.h"
#include "clhair/progressive.h"
#include "clhair/temporal.h"
#include "io/json_util.h"
#include "options.h"
#include "render.h"

namespace clhair::cli {

CLI::App* addRenderCommand(CLI::App& app, RenderFlags& f) {
  CLI::App* render = app.add_subcommand("render", "render a scene to an image");
  render->add_option("scene", f.scenePath, "scene JSON file")->required();
  addOutputOption(render, f.out, "output image (.png, .exr, ...)");
  addCameraOptions(render, f.width, f.height, f.camera);
  render->add_option("--lod", f.lod, "LOD: on, off, or auto (as each groom says)");
  render->add_option("--msaa", f.msaa, "software MSAA samples per pixel: 1, 2, 4, 8");
  render->add_option("--dispatch", f.dispatch,
                     "strand dispatch sizing: auto, readback, overlaunch, persistent");
  render->add_option("--ao", f.ao, "baked ambient occlusion: on (default) or off");
  render->add_option("--visibility", f.visibility,
                     "grooms' baked visibility (scene key \"visibility\"): on (default) or off");
  render->add_option("--lod-bsdf", f.lodBsdf,
                     "BSDF of strands LOD widened for a cluster: single (default, the "
                     "single-fibre BSDF) or aggregated (Huang 2024)");
  render->add_option("--scattering", f.scattering,
                     "light between fibres: multiple (default: dual scattering for lights with "
                     "a deep opacity map and the ambient/environment light) or single");
  render->add_option("--filter", f.filter,
                     "reconstruction filter with MSAA 1: on, off, auto (as the scene says; by "
                     "default Huang's filter in one view, Lipp's in several), lipp or huang (on, "
                     "with that method; docs/scene-format.md)");
  render
      ->add_option("--reference", f.referenceMethod,
                   "render the ground truth, the average of --spp shifted true-width passes "
                   "whose hair is traced as round curves (embree, the default) or drawn by the "
                   "strand pass (raster); or path: paths traced through the full groom, light "
                   "scattered between fibres (docs/hair-shading.md)")
      ->expected(0, 1)
      ->check(CLI::IsMember({"embree", "raster", "path"}));
  render->add_option("--path-events", f.pathEvents,
                     "--reference path: scattering events per path, 1..1024 (default 64; 1: "
                     "direct light at the first fibre seen, shadowed)");
  addQualityOptions(render, f.spp, f.shadowLod, f.quality, f.shading);
  render->add_option("--frames", f.frames,
                     "frames of an animated scene: N, FIRST-LAST or FIRST-LAST:STEP (default 1); "
                     "#### in -o becomes the zero-padded frame number");
  render->add_option(
      "--aov", f.aov,
      "layers for compositing in one multi-channel EXR: a comma-separated list of "
      "rgba, z, alpha, tangent, motion, strand, cryptomatte (ID mattes per groom and "
      "strand), or all (every layer but cryptomatte; docs/aovs.md)");
  render->add_option("--views", f.views,
                     "views of a scene with \"cameras\": all (default) or a comma-separated list "
                     "of names (\"camera\": the scene's camera); %v in -o becomes the view's name");
  render->add_flag("--skip-existing", f.skipExisting,
                   "leave frames whose output file exists (resume a range)");
  render->add_flag("-q,--quiet", f.quiet, "print nothing on success");
  render->add_option("--frames-in-flight", f.framesInFlight,
                     "frames the device draws while earlier ones are read back and written "
                     "(1.." +
                         std::to_string(kMaxFramesInFlight) + ", default 2)");
  render->add_option("--encode-threads", f.encodeThreads,
                     "threads converting and writing images (0: one per core but one, at most 8)");
  render->add_flag("--passes", f.passes,
                   "print the first frame's graph: its passes, buffers and host waits");
  render->add_option("--final-subset", f.finalSubset,
                     "--quality final: each pass draws one hair-mesh strand in N, a different "
                     "subset per pass, widened to keep the hair's coverage (1..16, default 1: "
                     "every strand)");
  render->add_flag("--true-width", f.trueWidth,
                   "draw every strand at its true projected width: no minimum hit diameter and "
                   "no widening of faint strand files");
  render->add_flag("--stats", f.stats,
                   "print the strands and segments each groom instance draws, and the totals");
  render->add_option("--temporal", f.temporal,
                     "temporal reprojection: blend each frame's hair with the K frames before it, "
                     "carried along the motion vectors (0: off; default: the scene's \"temporal\", "
                     "off; DESIGN.md)");
  render->add_option("--segment-budget", f.segmentBudget,
                     "most segments of all grooms per frame (0: none; default: the scene's)");
  render->add_option("--budget-rule", f.budgetRule,
                     "how the segment budget is shared: screen (default: each groom by its "
                     "screen area) or uniform (one factor for every groom)");
  render->add_option("--screen-boxes", f.screenBoxes,
                     "run each groom's G-buffer clear, hair linking, Huang's filter and its "
                     "compositing over the groom's screen box: on (default) or off (the whole "
                     "frame; the same image, for timing)");
  render->add_option("--png-compression", f.write.pngCompression,
                     "zlib level of PNG files: 0 (none) .. 9 (smallest); default 1, fast "
                     "(bench/README.md, \"Image writing\")");
  render->add_option("--exr-compression", f.write.exrCompression,
                     "OpenEXR compression: none, rle, zips, zip (default), piz, pxr24, b44, b44a, "
                     "dwaa, dwab (the last four lossy)");
  render->add_option("--raster", f.raster,
                     "strand raster: lines (default: centre samples, Lipp) or coverage "
                     "(trapezoids with analytic coverage, three layers and a coverage layer; "
                     "scene key \"raster\")");
  return render;
}

void noteRenderFlagsGiven(const CLI::App& render, RenderFlags& f) {
  f.framesGiven = render.count("--frames") > 0;
  f.widthGiven = render.count("--width") > 0;
  f.reference = render.count("--reference") > 0;
  f.sppGiven = render.count("--spp") > 0;
  f.finalSubsetGiven = render.count("--final-subset") > 0;
  f.heightGiven = render.count("--height") > 0;
}

// The --temporal value: frames of history, a whole number 0 (off) .. kMaxTemporalHistory.
int parseTemporal(const std::string& v) {
  const std::string hint = "--temporal \"" + v + "\": expected frames of history 0.." +
                           std::to_string(kMaxTemporalHistory) + " (0: off)";
  if (v.empty() || v.size() > 2 ||
      !std::all_of(v.begin(), v.end(), [](unsigned char c) { return std::isdigit(c); }))
    throw Error(hint);
  const int n = std::stoi(v);
  if (n > kMaxTemporalHistory) throw Error(hint);
  return n;
}

// The --segment-budget value: a whole number 0 (none) .. kMaxSegmentBudget.
std::int64_t parseSegmentBudget(const std::string& v) {
  const std::string hint = "--segment-budget \"" + v +
                           "\": expected a whole number of segments 0.." +
                           std::to_string(kMaxSegmentBudget) + " (0: no budget)";
  if (v.empty() || v.size() > 10 ||
      !std::all_of(v.begin(), v.end(), [](unsigned char c) { return std::isdigit(c); }))
    throw Error(hint);
  const unsigned long long n = std::stoull(v);
  if (n > kMaxSegmentBudget) throw Error(hint);
  return static_cast<std::int64_t>(n);
}

// The views a render writes: the scene's "cameras" (all, or those --views names; "camera" is
// the scene's own camera), or the scene's camera alone.
std::vector<View> selectViews(const Scene& scene, const std::string& spec) {
  View main;
  main.name = "camera";
  main.relative = true;  // the scene's camera itself, keys included
  if (scene.views.empty() && (spec.empty() || spec == "all" || spec == "camera")) return {main};
  if (spec.empty() || spec == "all") return scene.views;
  std::vector<View> out;
  std::size_t at = 0;
  while (at <= spec.size()) {
    const std::size_t comma = std::min(spec.find(',', at), spec.size());
    const std::string name = spec.substr(at, comma - at);
    at = comma + 1;
    const View* found = name == "camera" ? &main : nullptr;
    for (const View& v : scene.views)
      if (v.name == name) found = &v;
    if (!found) {
      std::string known = "camera";
      for (const View& v : scene.views) known += ", " + v.name;
      throw Error("--views \"" + spec + "\": no view named \"" + name + "\" (the scene has " +
                  known + ")");
    }
    for (const View& v : out)
      if (v.name == name) throw Error("--views \"" + spec + "\" names \"" + name + "\" twice");
    out.push_back(*found);
  }
  if (out.size() > static_cast<std::size_t>(kMaxViews))
    throw Error("--views \"" + spec + "\": at most " + std::to_string(kMaxViews) + " views");
  return out;
}

// The output of view `name`: every "%v" of the pattern replaced by the name; without one (and
// several views) the name goes before the extension: out.0007.exr -> out.0007.left.exr.
std::string viewPath(const std::string& pattern, const std::string& name, bool several) {
  std::string p = pattern;
  bool token = false;
  for (std::size_t at = p.find("%v"); at != std::string::npos; at = p.find("%v", at)) {
    p.replace(at, 2, name);
    at += name.size();
    token = true;
  }
  if (token || !several) return p;
  const std::filesystem::path path(p);
  return (path.parent_path() / (path.stem().string() + "." + name + path.extension().string()))
      .string();
}

// The frame numbers of a --frames value: "7", "1-240", "1-240:5", "240-1" (in reverse).
std::vector<long long> parseFrames(const std::string& spec) {
  const std::string hint =
      "--frames \"" + spec + "\": expected N, FIRST-LAST or FIRST-LAST:STEP (e.g. 1-240:2)";
  if (spec.empty())  // `--frames "$SLURM_ARRAY_TASK_ID"` with the variable unset
    throw Error(hint + "; the value is empty (an unset variable?)");
  constexpr long long kMaxFrame = 99999999;
  auto number = [&](const std::string& t) {
    if (t.empty() || t.size() > 8 ||
        !std::all_of(t.begin(), t.end(), [](unsigned char c) { return std::isdigit(c); }))
      throw Error(hint + "; frame numbers are whole numbers 0.." + std::to_string(kMaxFrame));
    return std::stoll(t);
  };
  const std::size_t colon = spec.find(':');
  const std::string range = spec.substr(0, colon);
  const long long step = colon == std::string::npos ? 1 : number(spec.substr(colon + 1));
  if (step < 1) throw Error(hint + "; the step must be at least 1");
  const std::size_t dash = range.find('-');
  const long long first = number(range.substr(0, dash));
  const long long last = dash == std::string::npos ? first : number(range.substr(dash + 1));
  if (dash == std::string::npos && colon != std::string::npos)
    throw Error(hint + "; a step needs a range");
  std::vector<long long> out;
  const long long count = (std::llabs(last - first)) / step + 1;
  if (count > 1000000)
    throw Error(hint + "; " + std::to_string(count) + " frames, at most 1000000 per command");
  for (long long k = 0; k < count; ++k)
    out.push_back(first <= last ? first + k * step : first - k * step);
  return out;
}

// --png-compression and --exr-compression, refused before any work with the flag named.
void checkWriteFlags(const ImageWriteOptions& w) {
  if (w.pngCompression < 0 || w.pngCompression > 9)
    throw Error("--png-compression " + std::to_string(w.pngCompression) +
                " is outside 0..9 (zlib levels: 0 none, 1 fast, the default; 9 smallest)");
  try {
    checkImageWriteOptions(w);
  } catch (const Error& e) {
    throw Error(std::string("--exr-compression: ") + e.what());
  }
}

}  // namespace clhair::cli
