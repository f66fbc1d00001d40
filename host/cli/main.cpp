// main.cpp — the `clhair` command: a thin user of the library API.
//
//   clhair devices                          list OpenCL devices and what clhair would use
//   clhair render SCENE -o OUT.png|.exr     render a scene, print per-stage times
//                [--reference [embree|raster|path] --spp N]   or its ground truth (default
//                [--path-events N]                  embree; path: multiple scattering)
//     [--frames 1-240[:STEP] -o OUT.####.exr] a frame range, one file per frame
//     [--aov rgba,z,alpha,tangent,motion,strand|all]  layers for compositing in one EXR
//     (docs/aovs.md)
//     [--views all|NAME,...]              several views of one assembly, one file per view
//                                         (%v in -o becomes the view's name)
//     [--temporal K]                      blend the hair of the K frames before (reprojected)
//   clhair groom --preset NAME -o FILE      write a generated hair mesh
//   clhair export-strands GROOM -o F.hair   write the generated strands as cyHair (F.data: USC,
//                                           F.tfx: TressFX 4.0, resampled to 4..64 points)
//   clhair compare A B [--error-map M]      PSNR, RMSE and mean FLIP of B against reference A
//   clhair fit-mesh STRANDS -o G.json       a hair mesh fitted to a strand file (docs/fitting.md)
//                [--bundles N] [--layers L] [--report R.json] [--head MESH.obj]
//
// Global options choose the device (--device, CLHAIR_DEVICE), force a sub-group backend
// (--subgroup, CLHAIR_SUBGROUP) or read kernels from a source tree (--kernel-dir,
// CLHAIR_KERNEL_DIR). Any failure prints one line "clhair: error: ..." and exits 1;
// output files are only written when the work completed.
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cl/cl_error.h"
#include "cl/stderr_capture.h"
#include "clhair/aov.h"
#include "clhair/device.h"
#include "clhair/error.h"
#include "clhair/fit.h"
#include "clhair/hair_mesh.h"
#include "clhair/progressive.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/temporal.h"
#include "clhair/triangle_mesh.h"
#include "clhair/visibility_sh.h"
#include "clhair/write_queue.h"
#include "groom/presets.h"
#include "groom/visibility_bake.h"
#include "io/binary_file.h"
#include "io/cyhair.h"
#include "io/draw_warnings.h"
#include "io/json_util.h"
#include "io/ply_strands.h"
#include "io/safe_write.h"
#include "io/tressfx.h"
#include "io/usc_hair.h"
#include "metrics/image_metrics.h"

namespace {

using namespace clhair;

// A message on one line: line breaks become "; ".
std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  for (std::size_t p = text.find('\n'); p != std::string::npos; p = text.find('\n', p))
    text.replace(p, 1, "; ");
  return text;
}

// Prints the one error line. A message's lines after the first, and `details` (a device list,
// a build log), follow it with --verbose; otherwise they go to a log file in $TMPDIR (or /tmp)
// that the line names, or, when that cannot be written, the line says to use --verbose.
void reportError(const std::string& message, std::string details, bool verbose) {
  const std::size_t nl = message.find('\n');
  std::string line = message.substr(0, nl);
  if (nl != std::string::npos)
    details = message.substr(nl + 1) + (details.empty() ? "" : "\n") + details;
  while (!details.empty() && (details.back() == '\n' || details.back() == ' ')) details.pop_back();
  if (details.empty()) {
    std::fprintf(stderr, "clhair: error: %s\n", oneLine(line).c_str());
    return;
  }
  if (verbose) {
    std::fprintf(stderr, "clhair: error: %s\n%s\n", oneLine(line).c_str(), details.c_str());
    return;
  }
  const char* tmp = std::getenv("TMPDIR");
  const std::string log = std::string(tmp && *tmp ? tmp : "/tmp") + "/clhair-error-" +
                          std::to_string(::getpid()) + ".log";
  std::string where;
  try {
    writeFileAtomically(log, "clhair: error: " + line + "\n" + details + "\n");
    where = "details in " + log;
  } catch (const Error&) {
    where = "details with --verbose";
  }
  std::fprintf(stderr, "clhair: error: %s (%s)\n", oneLine(line).c_str(), where.c_str());
}

// The first word of the command line where a subcommand belongs, when it names none ("rendr"):
// "unknown subcommand ..." for the error line; "" otherwise.
std::string unknownSubcommand(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--device" || a == "--subgroup" || a == "--kernel-dir") {
      ++i;  // the option's value
      continue;
    }
    if (!a.empty() && a[0] == '-') continue;
    std::string known;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      if (sub->get_name() == a) return {};
      known += (known.empty() ? "" : ", ") + sub->get_name();
    }
    return "unknown subcommand \"" + a + "\"; expected one of: " + known;
  }
  return {};
}

std::string mib(std::uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

int cmdDevices(const DeviceOptions& opts) {
  std::vector<DeviceInfo> all = Device::list();
  if (all.empty())
    throw Error("no OpenCL devices found (install an OpenCL driver, e.g. pocl-opencl-icd)");
  for (const DeviceInfo& d : all) {
    std::cout << d.platformIndex << ":" << d.deviceIndex << "  " << d.name << "\n"
              << "    platform        " << d.platformName << "\n"
              << "    vendor          " << d.vendor << "\n"
              << "    OpenCL          " << d.version << " / " << d.clcVersion << "\n"
              << "    driver          " << d.driverVersion << "\n"
              << "    type            " << (d.isGpu ? "GPU" : "not GPU") << ", " << d.computeUnits
              << " compute units\n"
              << "    64-bit atomics  "
              << (d.int64Atomics ? "yes" : "no (clhair cannot use this device)") << "\n"
              << "    max allocation  " << mib(d.maxAlloc) << " of " << mib(d.globalMem) << "\n";
    std::string backend = "-";
    if (d.int64Atomics) {
      try {
        DeviceOptions o = opts;
        o.selector = std::to_string(d.platformIndex) + ":" + std::to_string(d.deviceIndex);
        Device dev = Device::open(o);
        backend = std::string(subgroupBackendName(dev.info().backend)) + " (" +
                  dev.info().backendNote + ")";
      } catch (const Error& e) {
        std::string msg = e.what();
        backend = "unavailable: " + msg.substr(0, msg.find('\n'));
      }
    }
    std::string cands;
    for (SubgroupBackend b : d.candidates)
      cands += std::string(cands.empty() ? "" : ", ") + subgroupBackendName(b);
    std::cout << "    sub-group       " << backend << "; candidates: " << cands << "\n";
  }
  return 0;
}

struct RenderFlags {
  int width = 0, height = 0, msaa = 1, spp = 256;
  bool reference = false;
  std::string referenceMethod;  // embree (also when --reference has no value), raster or path
  int pathEvents = 64;          // --reference path: scattering events per path
  std::string filter = "auto";
  bool widthGiven = false, heightGiven = false;
  std::string camera, lod, dispatch = "auto", ao = "on", visibility = "on", lodBsdf = "single";
  bool quiet = false;
  std::string frames;        // "N", "A-B" or "A-B:STEP"
  bool framesGiven = false;  // --frames given (even empty, which is refused); else frame 1
  bool skipExisting = false;
  std::string aov;            // --aov list; empty: the beauty alone through writeImage
  std::string views;          // --views: "all" or names; empty: all of the scene's "cameras"
  bool stats = false;         // --stats: strands and segments per groom instance
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
  bool sppGiven = false;              // --spp given (final's passes; else the level's default)
};

// --quality's value as RenderOptions::quality (0 draft, 1 good, 2 final); -1 when not given.
int parseQualityFlag(const std::string& v) {
  if (v.empty()) return -1;
  if (v == "draft") return 0;
  if (v == "good") return 1;
  if (v == "final") return 2;
  throw Error("--quality must be draft, good or final, not \"" + v + "\"");
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

// --stats: what each groom instance drew (from its LOD records) and the frame's totals.
void printStats(const FrameStats& st) {
  std::size_t drawn = 0;
  for (const GroomDrawStats& g : st.grooms) {
    if (!g.drawn) {
      std::printf("groom %zu \"%s\": not drawn (behind the camera)\n", g.instance, g.name.c_str());
      continue;
    }
    ++drawn;
    std::printf("groom %zu \"%s\": %u strands, %llu segments, %u visible strands%s", g.instance,
                g.name.c_str(), g.strands, static_cast<unsigned long long>(g.segments),
                g.visibleStrands, g.halved ? ", every other control point" : "");
    if (st.overBudget && st.budgetScreenRule)
      std::printf(" (asked %u, floor %u, share %u; screen box %.0f px, keep claim %.2f)",
                  g.requested, g.floor, g.share, g.screenArea, g.keepClaim);
    std::printf("\n");
  }
  std::printf("total: %zu of %zu grooms drawn, %llu strands, %llu segments", drawn,
              st.grooms.size(), static_cast<unsigned long long>(st.strandsDrawn),
              static_cast<unsigned long long>(st.segmentsPlanned));
  if (st.segmentBudget == 0)
    std::printf(" (no segment budget)\n");
  else if (st.overBudget && st.budgetScreenRule && !std::isfinite(st.budgetLevel))
    std::printf(
        " (budget %llu: the LOD passes asked for %llu; every other control point of the "
        "far grooms made it fit)\n",
        static_cast<unsigned long long>(st.segmentBudget),
        static_cast<unsigned long long>(st.segmentsBeforeBudget));
  else if (st.overBudget && st.budgetScreenRule)
    std::printf(
        " (budget %llu: the LOD passes asked for %llu, shared by screen area: %.3f segments "
        "per pixel of screen box)\n",
        static_cast<unsigned long long>(st.segmentBudget),
        static_cast<unsigned long long>(st.segmentsBeforeBudget), st.budgetLevel);
  else if (st.overBudget)
    std::printf(" (budget %llu: the LOD passes asked for %llu, strands scaled by %.4f)\n",
                static_cast<unsigned long long>(st.segmentBudget),
                static_cast<unsigned long long>(st.segmentsBeforeBudget), st.budgetScale);
  else
    std::printf(" (budget %llu, not reached)\n", static_cast<unsigned long long>(st.segmentBudget));
  std::printf("host waits: %llu\n", static_cast<unsigned long long>(st.hostWaits));
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

// A frame's image with the --png-compression / --exr-compression options. Without them, the
// two-argument writeImage: the form ../shared/gpu/bundle.sh replaces by its PPM writer on
// machines without OpenImageIO (scripts/gpu-check.sh).
void writeFrameImage(const Image& image, const std::string& path, const ImageWriteOptions& w) {
  const ImageWriteOptions defaults;
  if (w.pngCompression == defaults.pngCompression && w.exrCompression == defaults.exrCompression)
    writeImage(image, path);
  else
    writeImage(image, path, w);
}

std::string seconds(double s) {
  char buf[32];
  if (s < 60.0)
    std::snprintf(buf, sizeof(buf), "%.2f s", s);
  else
    std::snprintf(buf, sizeof(buf), "%dm%02ds", static_cast<int>(s / 60.0),
                  static_cast<int>(s) % 60);
  return buf;
}

// Reports a reference's progress on stderr: passes done of the total and the time left,
// estimated from the mean pass after the first (which also pays for kernel builds, shadow
// maps and the BVH); on a terminal one line rewritten in place, else a line at most every
// 10 s (and the first and last ones).
std::function<void(int, int)> referenceProgress() {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const bool tty = isatty(fileno(stderr)) != 0;
  Clock::time_point first = start, last = start;
  return [start, tty, first, last](int done, int total) mutable {
    const Clock::time_point now = Clock::now();
    if (done == 1) first = now;
    const double elapsed = std::chrono::duration<double>(now - start).count();
    const bool end = done == total;
    if (!tty && done > 1 && !end && std::chrono::duration<double>(now - last).count() < 10.0)
      return;
    last = now;
    const double perPass =
        done > 1 ? std::chrono::duration<double>(now - first).count() / (done - 1) : elapsed;
    const double left = perPass * (total - done);
    std::fprintf(stderr, "%sclhair: reference %d/%d samples, %.0f s elapsed, %.0f s left%s",
                 tty ? "\r" : "", done, total, elapsed, left, tty && !end ? "" : "\n");
    std::fflush(stderr);
  };
}

int cmdRender(const DeviceOptions& opts, const std::string& scenePath, const std::string& out,
              const RenderFlags& f) {
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
  // the device first: strand files are checked against its largest allocation as they load
  Device dev = Device::open(opts);
  Scene scene = loadScene(scenePath, dev.info().maxAlloc);
  for (const std::string& w : scene.warnings)
    std::fprintf(stderr, "clhair: warning: %s\n", w.c_str());
  for (const std::string& n : scene.notes) std::fprintf(stderr, "clhair: note: %s\n", n.c_str());
  const std::vector<View> views = selectViews(scene, f.views);
  const bool several = views.size() > 1;
  if (several && !aovs.empty())
    throw Error("--aov writes one view; this render has " + std::to_string(views.size()) +
                " (choose one with --views NAME)");
  if (several && f.reference)
    throw Error("--reference renders one view; choose one with --views NAME");
  for (const View& v : views) checkOutputPath(framePath(viewPath(out, v.name, several), frames[0]));
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
    ro.lod = 1;
  else if (lod == "off")
    ro.lod = 0;
  else if (!lod.empty() && lod != "auto")
    throw Error("--lod must be on, off or auto, not \"" + lod + "\"");
  if (f.msaa != 1 && f.msaa != 2 && f.msaa != 4 && f.msaa != 8)
    throw Error("--msaa must be 1, 2, 4 or 8, not " + std::to_string(f.msaa));
  ro.msaa = f.msaa;
  ro.dispatch = parseDispatchMode(f.dispatch);
  if (f.ao != "on" && f.ao != "off") throw Error("--ao must be on or off, not \"" + f.ao + "\"");
  ro.ambientOcclusion = f.ao == "on" ? 1 : 0;
  if (f.visibility != "on" && f.visibility != "off")
    throw Error("--visibility must be on or off, not \"" + f.visibility + "\"");
  ro.bakedVisibility = f.visibility == "on" ? 1 : 0;
  if (f.lodBsdf != "aggregated" && f.lodBsdf != "single")
    throw Error("--lod-bsdf must be aggregated or single, not \"" + f.lodBsdf + "\"");
  ro.lodAggregate = f.lodBsdf == "aggregated" ? 1 : 0;
  ro.aovs = std::any_of(aovs.begin(), aovs.end(), [](Aov a) { return a != Aov::Rgba; });
  ro.strandIds = std::find(aovs.begin(), aovs.end(), Aov::Strand) != aovs.end();
  if (f.filter == "on") {
    ro.filter = 1;
  } else if (f.filter == "off") {
    ro.filter = 0;
  } else if (f.filter == "lipp" || f.filter == "huang") {
    ro.filter = 1;
    ro.filterMethod = f.filter == "huang" ? 1 : 0;
  } else if (f.filter != "auto") {
    throw Error("--filter must be on, off, auto, lipp or huang, not \"" + f.filter + "\"");
  }
  if (!f.segmentBudget.empty()) ro.segmentBudget = parseSegmentBudget(f.segmentBudget);
  if (f.budgetRule != "screen" && f.budgetRule != "uniform")
    throw Error("--budget-rule must be screen or uniform, not \"" + f.budgetRule + "\"");
  ro.budgetRule = f.budgetRule == "screen" ? 1 : 0;
  if (f.screenBoxes != "on" && f.screenBoxes != "off")
    throw Error("--screen-boxes must be on or off, not \"" + f.screenBoxes + "\"");
  ro.screenBoxes = f.screenBoxes == "on";
  if (f.raster == "lines" || f.raster == "coverage")
    ro.raster = f.raster == "coverage" ? 1 : 0;
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
  if (f.shadowLod == "light") {
    ro.shadowLodCamera = 0;
  } else if (f.shadowLod == "off") {
    ro.shadowLod = 0;
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
  Renderer renderer(dev);
  // the still scene of frame n as this command renders it (also for the previous frames)
  auto stillAt = [&](long long n) {
    Scene st = sceneAtFrame(scene, static_cast<double>(n));
    if (preset) st.camera = reframeCamera(st, *preset);
    if (!views[0].relative || views[0].offset != glm::vec3(0.0f))
      st.camera = viewCamera(st, views[0]);
    return st;
  };
  // with reprojection, each frame blends the frames before it, rendered or held by the sequence
  // (clhair/temporal.h): still the same frame whatever this process rendered before
  FrameSequence sequenceFrames(renderer, stillAt, ro);
  // Every frame is evaluated from the scene and its number alone and rendered from a
  // cleared target, so it is the same whichever frames this process rendered before.
  const bool sequence = !f.frames.empty();
  renderer.setFramesInFlight(f.framesInFlight);
  ro.timings = !sequence;    // a sequence prints no stage times: no profiling events
  ro.readBackDepth = false;  // images hold colour; AOVs read the depth they need
  // frames are converted and written on worker threads while the device draws the next ones
  WriteQueue writer(static_cast<unsigned>(f.encodeThreads));
  struct InFlight {
    FrameTicket ticket = 0;
    long long number = 0;
    std::size_t index = 0;
    std::chrono::steady_clock::time_point t0;
    int width = 0, height = 0;
  };
  std::deque<InFlight> inFlight;
  const auto start = std::chrono::steady_clock::now();
  std::size_t rendered = 0, skipped = 0;
  // hands a finished frame to the writers and reports it
  auto deliver = [&](const InFlight& q, std::vector<Frame> shots) {
    const std::string path = framePath(viewPath(out, views[0].name, several), q.number);
    if (several) {
      for (std::size_t v = 0; v < views.size(); ++v) {
        auto image = std::make_shared<Image>(std::move(shots[v].color));
        const std::string vp = framePath(viewPath(out, views[v].name, true), q.number);
        writer.submit([image, vp, w = f.write] { writeFrameImage(*image, vp, w); });
      }
    } else if (aovs.empty()) {
      auto image = std::make_shared<Image>(std::move(shots[0].color));
      writer.submit([image, path, w = f.write] { writeFrameImage(*image, path, w); });
    } else {
      auto channels = std::make_shared<std::vector<ImageChannel>>(aovChannels(shots[0], aovs));
      writer.submit([channels, path, w = q.width, h = q.height, o = f.write] {
        writeChannels(*channels, w, h, path, o);
      });
    }
    const Frame& frame = shots[0];
    if (rendered == 0 && !several && !f.reference)  // a groom that vanished says why
      for (const std::string& w : drawWarnings(stillAt(q.number), frame.stats, scenePath))
        std::fprintf(stderr, "clhair: warning: %s\n", w.c_str());
    ++rendered;
    if (!frame.passes.empty()) std::printf("%s", frame.passes.c_str());
    if (f.stats && !several) {
      if (sequence) std::printf("frame %lld:\n", q.number);
      printStats(frame.stats);
    }
    if (quiet) return;
    const auto t1 = std::chrono::steady_clock::now();
    if (sequence) {
      const double took = std::chrono::duration<double>(t1 - q.t0).count();
      const double perFrame = std::chrono::duration<double>(t1 - start).count() / rendered;
      const std::size_t left = frames.size() - q.index - 1;
      if (several)
        std::fprintf(stderr,
                     "clhair: frame %lld (%zu/%zu), %zu views -> %s ...: %s, about %s left\n",
                     q.number, q.index + 1, frames.size(), views.size(), path.c_str(),
                     seconds(took).c_str(), seconds(perFrame * static_cast<double>(left)).c_str());
      else
        std::fprintf(stderr, "clhair: frame %lld (%zu/%zu) -> %s: %s, about %s left\n", q.number,
                     q.index + 1, frames.size(), path.c_str(), seconds(took).c_str(),
                     seconds(perFrame * static_cast<double>(left)).c_str());
      return;
    }
    if (several) {  // the stage times of all views together
      std::printf("%s ...: %zu views of %dx%d on %s\n", path.c_str(), views.size(), q.width,
                  q.height, dev.info().name.c_str());
    } else {
      std::printf("%s: %dx%d on %s (sub-group %s), %llu strands", path.c_str(), q.width, q.height,
                  dev.info().name.c_str(), subgroupBackendName(dev.info().backend),
                  static_cast<unsigned long long>(frame.stats.strandsDrawn));
      if (frame.stats.shadowStrandsDrawn > 0)
        std::printf(" (%llu into shadow maps)",
                    static_cast<unsigned long long>(frame.stats.shadowStrandsDrawn));
      if (frame.stats.pointsShaded > 0)
        std::printf(", %llu points shaded",
                    static_cast<unsigned long long>(frame.stats.pointsShaded));
      std::printf("\n");
    }
    for (const StageTime& t : frame.timings)
      std::printf("  %-10s %9.2f ms\n", t.stage.c_str(), t.ms);
    std::printf("  %-10s %9.2f ms\n", "total", frame.totalMs());
  };
  auto deliverOldest = [&] {
    const InFlight q = inFlight.front();
    inFlight.pop_front();
    deliver(q,
            several ? renderer.waitViews(q.ticket) : std::vector<Frame>{renderer.wait(q.ticket)});
  };
  Scene previous;
  for (std::size_t i = 0; i < frames.size() && !writer.failed(); ++i) {
    const long long number = frames[i];
    const std::string path = framePath(viewPath(out, views[0].name, several), number);
    std::error_code ec;
    bool allExist = f.skipExisting;
    for (const View& v : views)
      allExist = allExist &&
                 std::filesystem::exists(framePath(viewPath(out, v.name, several), number), ec);
    if (allExist) {
      // a killed run may have left its unfinished temporaries of these frames
      for (const View& v : views)
        removeStaleTemporaries(framePath(viewPath(out, v.name, several), number));
      ++skipped;
      if (!quiet && sequence)
        std::fprintf(stderr, "clhair: frame %lld (%zu/%zu): %s exists, skipped\n", number, i + 1,
                     frames.size(), path.c_str());
      continue;
    }
    InFlight q;
    q.number = number;
    q.index = i;
    q.t0 = std::chrono::steady_clock::now();
    Scene still = sceneAtFrame(scene, static_cast<double>(number));
    // the scene's viewing angle is kept: the preset changes only the distance and framing
    if (preset) still.camera = reframeCamera(still, *preset);
    q.width = still.width;
    q.height = still.height;
    ro.describePasses = f.passes && i == 0;
    if (several) {
      std::vector<Camera> cameras;
      for (const View& v : views) cameras.push_back(viewCamera(still, v));
      q.ticket = renderer.submitViews(still, cameras, ro);
    } else {
      if (!views[0].relative || views[0].offset != glm::vec3(0.0f))
        still.camera = viewCamera(still, views[0]);
      if (rendered == 0 && inFlight.empty())
        for (const std::string& w : viewWarnings(still, scenePath))
          std::fprintf(stderr, "clhair: warning: %s\n", w.c_str());
      // motion goes to the previous frame; frames 1 and before (a shot's first) have none, so
      // they are their own previous frame and their motion is zero
      if (ro.aovs) {
        previous = still;
        if (number > 1) {
          previous = sceneAtFrame(scene, static_cast<double>(number - 1));
          if (preset) previous.camera = reframeCamera(previous, *preset);
          if (!views[0].relative || views[0].offset != glm::vec3(0.0f))
            previous.camera = viewCamera(previous, views[0]);
        }
        ro.previous = &previous;
      }
      if (f.reference || temporal || final) {  // frames of their own: rendered one by one
        Frame frame = f.reference ? renderer.renderReference(still, ref)
                      : final     ? renderer.render(still, ro)
                                  : sequenceFrames.render(number);
        std::vector<Frame> shots;
        shots.push_back(std::move(frame));
        deliver(q, std::move(shots));
        renderer.releaseGrooms();
        ro.previous = nullptr;
        continue;
      }
      q.ticket = renderer.submit(still, ro);  // the scenes are not used after it returns
      ro.previous = nullptr;
    }
    // per-frame strand files are new grooms every frame: their device forms go with it
    renderer.releaseGrooms();
    inFlight.push_back(q);
    while (inFlight.size() > static_cast<std::size_t>(renderer.framesInFlight())) deliverOldest();
  }
  while (!inFlight.empty() && !writer.failed()) deliverOldest();
  writer.finish();  // the first failed write: one error line, the frames before it kept
  if (!quiet && sequence)
    std::fprintf(
        stderr, "clhair: %zu frames rendered, %zu skipped, %s\n", rendered, skipped,
        seconds(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count())
            .c_str());
  return 0;
}

// `clhair bake-visibility`'s options as given on the command line (defaults:
// VisibilityBakeOptions).
struct BakeVisibilityFlags {
  int groom = 0;
  int rays = static_cast<int>(VisibilityBakeOptions{}.raysPerPoint);
  int perCell = static_cast<int>(VisibilityBakeOptions{}.pointsPerCell);
  int maxEvents = static_cast<int>(VisibilityBakeOptions{}.maxEvents);
  bool verbose = false;
  std::string directions = "per-point";
  int cellStride = 1;
  std::string transmittanceOut;
};

// The study mode's table: "CLHTRN01", u32 absorptions, cells, directions, the absorptions as
// f32, then f32 [absorption][cell][direction] (little-endian; scripts/compare-visibility.py).
void writeTransmittance(const VisibilityBakeStats& st, std::uint32_t rays,
                        const std::string& path) {
  std::string out("CLHTRN01", 8);
  appendU32(out, kTransmittanceAbsorptions);
  appendU32(out, CLH_VIS_CELLS);
  appendU32(out, rays);
  for (float a : kTransmittanceAbsorption) appendF32(out, a);
  for (float t : st.transmittance) appendF32(out, t);
  writeTextAtomically(path, out);
}

int cmdBakeVisibility(const DeviceOptions& opts, const std::string& scenePath,
                      const std::string& out, const BakeVisibilityFlags& f) {
  const int rays = f.rays, perCell = f.perCell, groom = f.groom;
  if (rays < 1 || rays > 4096) throw Error("--rays must be 1..4096, not " + std::to_string(rays));
  if (perCell < 1 || perCell > 64)
    throw Error("--points-per-cell must be 1..64, not " + std::to_string(perCell));
  if (f.maxEvents < 1 || f.maxEvents > static_cast<int>(kMaxEventsLimit))
    throw Error("--max-events must be 1.." + std::to_string(kMaxEventsLimit) + ", not " +
                std::to_string(f.maxEvents));
  if (f.directions != "per-cell" && f.directions != "per-point")
    throw Error("--directions must be per-cell or per-point, not \"" + f.directions + "\"");
  if (f.cellStride < 1)
    throw Error("--cell-stride must be 1 or more, not " + std::to_string(f.cellStride));
  if (!f.transmittanceOut.empty() && f.directions != "per-point")
    throw Error("--transmittance-out traces per-point directions, not --directions per-cell");
  checkOutputPath(out);
  if (!f.transmittanceOut.empty()) checkOutputPath(f.transmittanceOut);
  VisibilityBakeStats st;
  BakePhaseTimer timer(&st);
  const Scene scene = loadScene(scenePath);
  timer.finish("scene");
  if (groom < 0 || static_cast<std::size_t>(groom) >= scene.grooms.size())
    throw Error(scenePath + ": --groom " + std::to_string(groom) +
                " does not exist, the scene has " + std::to_string(scene.grooms.size()) +
                " groom(s)");
  const GroomInstance& gi = scene.grooms[static_cast<std::size_t>(groom)];
  if (gi.strands && gi.strands->appearance.useFileColor && !gi.strands->colors.empty())
    throw Error(scenePath + ": groom \"" + gi.name +
                "\" is drawn with its file colours, whose G-buffer words carry no styling uv to "
                "look a bake up by");
  Device dev = Device::open(opts);
  Renderer renderer(dev);
  timer.finish("device");
  VisibilityBakeOptions o;
  o.raysPerPoint = static_cast<std::uint32_t>(rays);
  o.pointsPerCell = static_cast<std::uint32_t>(perCell);
  o.maxEvents = static_cast<std::uint32_t>(f.maxEvents);
  o.directions = f.directions == "per-point" ? VisibilityBakeOptions::Directions::PerPoint
                                             : VisibilityBakeOptions::Directions::PerCell;
  o.cellStride = static_cast<std::uint32_t>(f.cellStride);
  o.transmittance = !f.transmittanceOut.empty();
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  const VisibilityBake bake =
      bakeGroomVisibility(renderer, scene, static_cast<std::size_t>(groom), o, &st);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  BakePhaseTimer writeTimer(&st);
  writeVisibility(bake, out);
  if (o.transmittance) writeTransmittance(st, o.raysPerPoint, f.transmittanceOut);
  writeTimer.finish("write");
  if (f.verbose) {
    // one line per phase: wall, CPU over all threads, and the cores that CPU time kept busy;
    // for the split tracing, the workers' time waiting for a core (other processes' load)
    // and the rest (blocked or idle)
    for (const BakePhase& p : st.phases) {
      std::fprintf(stderr, "clhair: bake phase %-8s wall %8.2f s  cpu %8.2f s  (%.2f cores)",
                   p.name.c_str(), p.wallSeconds, p.cpuSeconds,
                   p.wallSeconds > 0.0 ? p.cpuSeconds / p.wallSeconds : 0.0);
      if (p.threads > 0 && p.waitSeconds >= 0.0)
        std::fprintf(stderr, "  %u threads: waiting for a core %.2f s, blocked or idle %.2f s",
                     p.threads, p.waitSeconds,
                     std::max(0.0, p.threads * p.wallSeconds - p.cpuSeconds - p.waitSeconds));
      std::fprintf(stderr, "\n");
    }
  }
  std::printf(
      "%s: groom \"%s\" (%u strands), %llu cells, %llu points, %llu rays, %.2f events "
      "per ray that hit, %.1f s (%.1f s of CPU time over all threads)\n",
      out.c_str(), gi.name.c_str(), bake.strands, static_cast<unsigned long long>(st.cells),
      static_cast<unsigned long long>(st.points), static_cast<unsigned long long>(st.rays),
      st.meanEvents, secs, cpu);
  if (gi.strands && gi.strands->rootUv.empty())
    std::fprintf(stderr,
                 "clhair: warning: %s has no root uv: its strands' cells are keyed by a hash, so "
                 "each cell averages unrelated strands and the bake varies only along them\n",
                 gi.name.c_str());
  return 0;
}

int cmdGroom(const std::string& preset, const std::string& out, long long strands) {
  checkOutputPath(out);
  HairMesh m = makeGroomPreset(preset);
  if (strands >= 0) m.strandCount = strands;
  saveHairMesh(m, out);
  std::printf("%s: %s, %d bundles, %d layers, %lld strands\n", out.c_str(), m.name.c_str(),
              static_cast<int>(m.faces.size()), m.layerCount,
              static_cast<long long>(m.strandCount));
  return 0;
}

int cmdBakeAo(const DeviceOptions& opts, const std::string& groomPath, const std::string& out) {
  checkOutputPath(out);
  HairMesh mesh = loadHairMesh(groomPath);
  Device dev = Device::open(opts);
  Renderer renderer(dev);
  mesh.ao = renderer.bakeAmbientOcclusion(mesh);
  saveHairMesh(mesh, out);
  float lo = 1.0f, hi = 0.0f;
  for (float a : mesh.ao) {
    lo = std::min(lo, a);
    hi = std::max(hi, a);
  }
  std::printf("%s: AO of %zu layer vertices, %.3f..%.3f\n", out.c_str(), mesh.ao.size(), lo, hi);
  return 0;
}

// The strands export-strands writes: a hair mesh's generated strands (root/tip colours), a
// strand file's (its colours), or a scene groom's as drawn at full detail, children included
// (in the groom's object space).
CyHair exportSource(Renderer& renderer, std::uint64_t maxAlloc, const std::string& path,
                    int groom) {
  const std::string ext = lowerExtension(path);
  const bool strandFile =
      ext == ".hair" || ext == ".data" || ext == ".tfx" || ext == ".ply" || ext == ".bin";
  bool scene = false;
  if (!strandFile && ext == ".json") {
    std::ifstream in(path);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    scene = j.is_object() && j.contains("grooms");
  }
  if (!scene && groom != 0)
    throw Error("--groom " + std::to_string(groom) + ": " + path + " is not a scene file");
  std::shared_ptr<const StrandGroom> strands;
  std::shared_ptr<const HairMesh> mesh;
  std::string name;
  if (strandFile) {
    strands = std::make_shared<const StrandGroom>(loadStrandGroom(path, maxAlloc));
  } else if (scene) {
    const Scene sc = loadScene(path, maxAlloc);
    if (groom < 0 || static_cast<std::size_t>(groom) >= sc.grooms.size())
      throw Error(path + ": --groom " + std::to_string(groom) + " does not exist, the scene has " +
                  std::to_string(sc.grooms.size()) + " groom(s)");
    strands = sc.grooms[static_cast<std::size_t>(groom)].strands;
    mesh = sc.grooms[static_cast<std::size_t>(groom)].mesh;
  } else {
    mesh = std::make_shared<const HairMesh>(loadHairMesh(path));
  }
  CyHair h;
  StrandSet s;
  if (strands) {
    s = renderer.generateStrands(*strands);
    name = strands->name;
    h.defaultThickness = strands->appearance.strandWidth;
  } else {
    s = renderer.generateStrands(*mesh);
    name = mesh->name;
    h.defaultThickness = mesh->appearance.strandWidth;
  }
  h.segments.reserve(s.pointCounts.size());
  for (std::uint32_t c : s.pointCounts) h.segments.push_back(c - 1);
  h.points = s.points;
  h.colors.reserve(s.points.size());
  if (mesh) {
    for (float w : s.w) {
      glm::vec3 c =
          mesh->appearance.rootColor + (mesh->appearance.tipColor - mesh->appearance.rootColor) * w;
      h.colors.insert(h.colors.end(), {c.x, c.y, c.z});
    }
  } else if (!s.look.empty() && strands->appearance.useFileColor && !strands->colors.empty()) {
    for (std::size_t i = 0; i < s.look.size(); i += 4)
      h.colors.insert(h.colors.end(), {s.look[i], s.look[i + 1], s.look[i + 2]});
  }
  h.info = "clhair export-strands: " + name;
  return h;
}

int cmdExport(const DeviceOptions& opts, const std::string& groomPath, const std::string& out,
              int groom) {
  const std::string ext = lowerExtension(out);
  if (ext != ".hair" && ext != ".data" && ext != ".tfx" && ext != ".ply")
    throw Error(out + ": " +
                (ext.empty() ? std::string("has no extension to choose a strand format by")
                             : "no strand-file writer for extension \"" + ext + "\"") +
                " (use .hair: cyHair, .data: USC-HairSalon, .tfx: TressFX 4.0, .ply: PLY)");
  checkOutputPath(out);
  Device dev = Device::open(opts);
  Renderer renderer(dev);
  CyHair h = exportSource(renderer, dev.info().maxAlloc, groomPath, groom);
  if (ext == ".tfx") {
    // TressFX needs one point count for all strands, and AMD's runtime a power of two in
    // 4..64: resample along the arc length (points only, like USC-HairSalon).
    TressFxHair t;
    const std::uint32_t n = tressFxVertexCount(h);
    t.hair = resampleStrands(h, n);
    writeTressFx(t, out);
    std::printf("%s: %zu strands, resampled to %u points each (TressFX 4.0)\n", out.c_str(),
                h.segments.size(), n);
    return 0;
  }
  if (ext == ".data")
    writeUscHair(h, out);  // points only: the format has no colour or thickness
  else if (ext == ".ply")
    writePlyStrands(h, out);  // points and colours
  else
    writeCyHair(h, out);
  std::printf("%s: %zu strands, %zu points\n", out.c_str(), h.segments.size(), h.points.size() / 3);
  return 0;
}

std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

struct CompareFlags {
  std::string errorMap;
  double ppd = kFlipDefaultPpd;
  bool json = false;
};

// PSNR and RMSE on sRGB display values, mean LDR-FLIP, and optionally the FLIP error map:
// magma colours for 8-bit formats, raw error values for float formats (.exr, .hdr).
int cmdCompare(const std::string& pathA, const std::string& pathB, const CompareFlags& f) {
  if (!(f.ppd >= kFlipMinPpd && f.ppd <= kFlipMaxPpd))
    throw Error("--ppd " + shortNumber(f.ppd) + " is outside " + shortNumber(kFlipMinPpd) + ".." +
                shortNumber(kFlipMaxPpd) + " (FLIP's default viewing setup is 67)");
  if (!f.errorMap.empty()) checkImageOutput(f.errorMap);  // before the work
  Image a = readImage(pathA);
  Image b = readImage(pathB);
  requireSameSize(a, b, pathA, pathB);
  ImageComparison c = compareImages(a, b, f.ppd);
  if (!f.errorMap.empty()) {
    const std::string ext = lowerExtension(f.errorMap);
    const bool raw = ext == ".exr" || ext == ".hdr";
    writeImage(flipErrorImage(c.flip, !raw), f.errorMap);
  }
  const bool identical = std::isinf(c.psnr.psnrDb);
  if (f.json) {
    // JSON has no infinity: identical images report "psnr_db": null.
    nlohmann::json j = {{"reference", pathA},
                        {"test", pathB},
                        {"width", a.width},
                        {"height", a.height},
                        {"psnr_db", nullptr},
                        {"rmse", c.psnr.rmse},
                        {"mse", c.psnr.mse},
                        {"flip_mean", c.flip.mean},
                        {"ppd", f.ppd},
                        {"error_map", nullptr},
                        {"within_one_code", c.withinOneCode}};
    if (!identical) j["psnr_db"] = c.psnr.psnrDb;
    if (!f.errorMap.empty()) j["error_map"] = f.errorMap;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::printf("%s vs %s: %dx%d\n", pathA.c_str(), pathB.c_str(), a.width, a.height);
  if (identical)
    std::printf("  PSNR  inf dB      (identical in sRGB)\n");
  else
    std::printf("  PSNR  %.4f dB   (sRGB R, G, B; peak 1)\n", c.psnr.psnrDb);
  std::printf("  RMSE  %.6f     (sRGB R, G, B in [0, 1])\n", c.psnr.rmse);
  std::printf("  FLIP  %.6f     (mean LDR-FLIP, %g pixels per degree)\n", c.flip.mean, f.ppd);
  std::printf("  within 1/255  %.4f %% of pixels (largest sRGB channel difference)\n",
              100.0 * c.withinOneCode);
  if (!f.errorMap.empty()) std::printf("  error map  %s\n", f.errorMap.c_str());
  return 0;
}

// ---- fit-mesh: a hair mesh fitted to a strand file (docs/fitting.md) ----------------------

struct FitMeshFlags {
  std::string input, output, report, head, appearance;
  FitOptions options;
  bool quiet = false;
};

CLI::App* addFitMeshCommand(CLI::App& app, FitMeshFlags& f) {
  auto* cmd = app.add_subcommand(
      "fit-mesh", "fit a hair mesh to a strand file (.hair, .data, .tfx; docs/fitting.md)");
  cmd->add_option("strands", f.input, "strand file")->required();
  cmd->add_option("-o,--output", f.output, "output hair-mesh file (.json)")->required();
  cmd->add_option("--bundles", f.options.bundles,
                  "bundles to aim for, 1.." + std::to_string(kFitMaxBundles) +
                      " (default: one per 64 strands)");
  cmd->add_option("--layers", f.options.layers, "layers per bundle, 2..64 (default 16)");
  cmd->add_option("--report", f.report, "write the fit report (JSON) here");
  cmd->add_option("--head", f.head,
                  "head mesh (.obj, in the strand file's units and axes): the root layer is "
                  "placed on it");
  cmd->add_option("--appearance", f.appearance,
                  "take colours and fibre BSDF from this hair-mesh file (default: the strand "
                  "file's colours when it has them)");
  cmd->add_option("--fibre-width", f.options.fibreWidth,
                  "fibre width (file units; default: the file's thickness, else 7e-5)");
  cmd->add_option("--shape-weight", f.options.shapeWeight,
                  "weight of strand shape against root position when clustering (default 1)");
  cmd->add_option("--seed", f.options.seed, "the mesh's seed (default 1)");
  cmd->add_option("--error-sample", f.options.errorSample,
                  "measure the distance of this many input strands, evenly spread (0: all)");
  cmd->add_flag("-q,--quiet", f.quiet, "print nothing on success");
  return cmd;
}

int cmdFitMesh(FitMeshFlags f) {
  TriangleMesh head;
  if (!f.head.empty()) {
    head = loadTriangleMesh(f.head);
    f.options.head = &head;
  }
  HairMesh look;
  if (!f.appearance.empty()) look = loadHairMesh(f.appearance);
  std::uint64_t skipped = 0;
  std::vector<std::string> warnings;
  const StrandGroom groom = loadStrandGroom(f.input, 16ull << 30, &skipped, &warnings);
  for (const std::string& w : warnings) std::fprintf(stderr, "clhair: warning: %s\n", w.c_str());
  if (skipped > 0)
    std::fprintf(stderr, "clhair: warning: %s: %llu single-point strands left out\n",
                 f.input.c_str(), static_cast<unsigned long long>(skipped));
  FitResult r = fitHairMesh(groom, f.options);
  if (!f.appearance.empty()) {
    const float width = r.mesh.appearance.strandWidth;
    r.mesh.appearance = look.appearance;
    if (f.options.fibreWidth > 0.0f) r.mesh.appearance.strandWidth = width;
  }
  saveHairMesh(r.mesh, f.output);
  std::error_code ec;
  r.report.strandFileBytes = std::filesystem::file_size(f.input, ec);
  if (ec) r.report.strandFileBytes = 0;
  r.report.meshFileBytes = std::filesystem::file_size(f.output, ec);
  if (ec) r.report.meshFileBytes = 0;
  if (!f.report.empty()) writeFitReport(r.report, f.report);
  if (f.quiet) return 0;
  const FitReport& rep = r.report;
  std::printf("%s: %d bundles, %d layers, %d vertices, %zu strands (%zu in)\n", f.output.c_str(),
              rep.bundles, rep.layers, rep.vertices, rep.strandsOut, rep.strandsIn);
  if (rep.error.strands > 0)
    std::printf(
        "  distance to the nearest generated strand: mean %.3g m (%.2f fibre widths), "
        "95th percentile %.3g m (%.2f)\n",
        rep.error.meanM, rep.error.meanWidths, rep.error.p95M, rep.error.p95Widths);
  if (rep.strandFileBytes > 0)
    std::printf(
        "  size: %llu bytes, %.3f %% of the strand file\n",
        static_cast<unsigned long long>(rep.meshFileBytes),
        100.0 * static_cast<double>(rep.meshFileBytes) / static_cast<double>(rep.strandFileBytes));
  std::printf("  time: %.2f s\n", rep.seconds);
  for (const std::string& n : rep.notes) std::printf("  note: %s\n", n.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"clhair: real-time strand hair rendering on OpenCL"};
  app.require_subcommand(1);
  DeviceOptions opts;
  app.add_option("--device", opts.selector,
                 "device: P:D indices or a name substring (env CLHAIR_DEVICE)");
  app.add_option(
      "--subgroup", opts.subgroup,
      "force a sub-group backend: single, local, khr, intel, nvptx, amd (env CLHAIR_SUBGROUP)");
  app.add_option("--kernel-dir", opts.kernelDir,
                 "read kernels from this source tree (env CLHAIR_KERNEL_DIR)");
  bool verbose = false;
  app.add_flag("--verbose", verbose,
               "on an error, print its details (the device list, a build log) after its line "
               "instead of writing them to a log file the line names");

  auto* devices = app.add_subcommand("devices", "list OpenCL devices and their capabilities");

  auto* render = app.add_subcommand("render", "render a scene to an image");
  std::string scenePath, out;
  RenderFlags rf;
  render->add_option("scene", scenePath, "scene JSON file")->required();
  render->add_option("-o,--output", out, "output image (.png, .exr, ...)")->required();
  render->add_option("--width", rf.width, "override the scene's width");
  render->add_option("--height", rf.height, "override the scene's height");
  render->add_option("--camera", rf.camera, "frame the grooms with a preset: close, mid, far");
  render->add_option("--lod", rf.lod, "LOD: on, off, or auto (as each groom says)");
  render->add_option("--msaa", rf.msaa, "software MSAA samples per pixel: 1, 2, 4, 8");
  render->add_option("--dispatch", rf.dispatch,
                     "strand dispatch sizing: auto, readback, overlaunch, persistent");
  render->add_option("--ao", rf.ao, "baked ambient occlusion: on (default) or off");
  render->add_option("--visibility", rf.visibility,
                     "grooms' baked visibility (scene key \"visibility\"): on (default) or off");
  render->add_option("--lod-bsdf", rf.lodBsdf,
                     "BSDF of strands LOD widened for a cluster: single (default, the "
                     "single-fibre BSDF) or aggregated (Huang 2024)");
  render->add_option("--filter", rf.filter,
                     "reconstruction filter with MSAA 1: on, off, auto (as the scene says; by "
                     "default Huang's filter in one view, Lipp's in several), lipp or huang (on, "
                     "with that method; docs/scene-format.md)");
  render
      ->add_option("--reference", rf.referenceMethod,
                   "render the ground truth, the average of --spp shifted true-width passes "
                   "whose hair is traced as round curves (embree, the default) or drawn by the "
                   "strand pass (raster); or path: paths traced through the full groom, light "
                   "scattered between fibres (docs/hair-shading.md)")
      ->expected(0, 1)
      ->check(CLI::IsMember({"embree", "raster", "path"}));
  render->add_option("--path-events", rf.pathEvents,
                     "--reference path: scattering events per path, 1..1024 (default 64; 1: "
                     "direct light at the first fibre seen, shadowed)");
  render->add_option("--spp", rf.spp,
                     "samples per pixel of --reference (default 256), or jittered passes of "
                     "--quality final (default " +
                         std::to_string(kDefaultFinalPasses) + ")");
  render->add_option("--shadow-lod", rf.shadowLod,
                     "LOD of the lights' passes: camera (default: the light's view, no more "
                     "strands than the camera's LOD draws), light (the light's view alone) or "
                     "off (every strand)");
  render->add_option("--quality", rf.quality,
                     "draft (one sample per pixel, the scene's filter), good (" +
                         std::to_string(kGoodMsaa) +
                         " samples per pixel shaded once per visible strand point) or final "
                         "(--spp jittered passes accumulated); default: the scene's \"quality\", "
                         "draft");
  render->add_option("--frames", rf.frames,
                     "frames of an animated scene: N, FIRST-LAST or FIRST-LAST:STEP (default 1); "
                     "#### in -o becomes the zero-padded frame number");
  render->add_option("--aov", rf.aov,
                     "layers for compositing in one multi-channel EXR: a comma-separated list of "
                     "rgba, z, alpha, tangent, motion, strand, or all (docs/aovs.md)");
  render->add_option("--views", rf.views,
                     "views of a scene with \"cameras\": all (default) or a comma-separated list "
                     "of names (\"camera\": the scene's camera); %v in -o becomes the view's name");
  render->add_flag("--skip-existing", rf.skipExisting,
                   "leave frames whose output file exists (resume a range)");
  render->add_flag("-q,--quiet", rf.quiet, "print nothing on success");
  render->add_option("--frames-in-flight", rf.framesInFlight,
                     "frames the device draws while earlier ones are read back and written "
                     "(1.." +
                         std::to_string(kMaxFramesInFlight) + ", default 2)");
  render->add_option("--encode-threads", rf.encodeThreads,
                     "threads converting and writing images (0: one per core but one, at most 8)");
  render->add_flag("--passes", rf.passes,
                   "print the first frame's graph: its passes, buffers and host waits");
  render->add_flag("--stats", rf.stats,
                   "print the strands and segments each groom instance draws, and the totals");
  render->add_option("--temporal", rf.temporal,
                     "temporal reprojection: blend each frame's hair with the K frames before it, "
                     "carried along the motion vectors (0: off; default: the scene's \"temporal\", "
                     "off; DESIGN.md)");
  render->add_option("--segment-budget", rf.segmentBudget,
                     "most segments of all grooms per frame (0: none; default: the scene's)");
  render->add_option("--budget-rule", rf.budgetRule,
                     "how the segment budget is shared: screen (default: each groom by its "
                     "screen area) or uniform (one factor for every groom)");
  render->add_option("--screen-boxes", rf.screenBoxes,
                     "run each groom's G-buffer clear, hair linking, Huang's filter and its "
                     "compositing over the groom's screen box: on (default) or off (the whole "
                     "frame; the same image, for timing)");
  render->add_option("--png-compression", rf.write.pngCompression,
                     "zlib level of PNG files: 0 (none) .. 9 (smallest); default 1, fast "
                     "(bench/README.md, \"Image writing\")");
  render->add_option("--exr-compression", rf.write.exrCompression,
                     "OpenEXR compression: none, rle, zips, zip (default), piz, pxr24, b44, b44a, "
                     "dwaa, dwab (the last four lossy)");
  render->add_option("--raster", rf.raster,
                     "strand raster: lines (default: centre samples, Lipp) or coverage "
                     "(trapezoids with analytic coverage, three layers and a coverage layer; "
                     "scene key \"raster\")");

  auto* groom = app.add_subcommand("groom", "write a generated hair mesh");
  std::string preset, groomOut;
  long long strands = -1;
  groom->add_option("--preset", preset, "long_wavy, curly_medium, fur_sphere or tiny")->required();
  groom->add_option("-o,--output", groomOut, "output hair-mesh file (.json)")->required();
  groom->add_option("--strands", strands, "override the strand count");

  auto* bakeCmd = app.add_subcommand("bake-ao", "bake ambient occlusion into a hair-mesh file");
  std::string bakeIn, bakeOut;
  bakeCmd->add_option("groom", bakeIn, "hair-mesh file")->required();
  bakeCmd->add_option("-o,--output", bakeOut, "output hair-mesh file with per-vertex AO")
      ->required();

  auto* visCmd = app.add_subcommand(
      "bake-visibility",
      "bake a groom's spherical visibility for self-shadowing (Embree; docs/scene-format.md)");
  std::string visScene, visOut;
  BakeVisibilityFlags vf;
  visCmd->add_option("scene", visScene, "scene file: the groom and its head")->required();
  visCmd->add_option("-o,--output", visOut, "output baked visibility file (.clhvis)")->required();
  visCmd->add_option("--groom", vf.groom, "index of the groom in the scene (default 0)");
  visCmd->add_option("--rays", vf.rays,
                     "rays per sample point (default " + std::to_string(vf.rays) + ")");
  visCmd->add_option(
      "--points-per-cell", vf.perCell,
      "sample points per (u, v, w) cell (default " + std::to_string(vf.perCell) + ")");
  visCmd->add_option("--max-events", vf.maxEvents,
                     "a ray's scattering events are clamped at this count (1.." +
                         std::to_string(kMaxEventsLimit) + ", default " +
                         std::to_string(vf.maxEvents) +
                         "; about 5 / absorption is closest to the true shadowing)");
  visCmd->add_flag("-v,--verbose", vf.verbose,
                   "print each phase's wall and CPU time to stderr (the tracing phase also "
                   "its threads' time waiting for a core)");
  visCmd->add_option("--directions", vf.directions,
                     "per-point (default): each sample point its own stratified set of directions; "
                     "per-cell: one set per cell dealt out to its points");
  visCmd->add_option("--cell-stride", vf.cellStride,
                     "bake only about one occupied cell in N (by hash), the rest left zero: a "
                     "sample of the table for estimator studies (default 1: every cell)");
  visCmd->add_option("--transmittance-out", vf.transmittanceOut,
                     "estimator study: trace every point in the same --rays directions and also "
                     "write each cell's mean transmittance per direction before the SH fit "
                     "(scripts/compare-visibility.py --transmittance)");

  auto* exportCmd = app.add_subcommand("export-strands",
                                       "write the generated strands as a cyHair .hair file "
                                       "(USC-HairSalon when the name ends in .data, "
                                       "TressFX 4.0 for .tfx, PLY for .ply)");
  std::string groomPath, hairOut;
  int exportGroom = 0;
  exportCmd
      ->add_option("groom", groomPath,
                   "hair-mesh file, strand file, or scene (its groom as drawn, children "
                   "included)")
      ->required();
  exportCmd->add_option("-o,--output", hairOut, "output .hair, .data, .tfx or .ply file")
      ->required();
  exportCmd->add_option("--groom", exportGroom, "the scene's groom to export (default 0)");

  auto* compare =
      app.add_subcommand("compare", "compare image B against reference A: PSNR, RMSE, mean FLIP");
  std::string compareA, compareB;
  CompareFlags cf;
  compare->add_option("reference", compareA, "reference image")->required();
  compare->add_option("test", compareB, "test image (same size)")->required();
  compare->add_option("--error-map", cf.errorMap,
                      "write the FLIP error map (.png: magma colours, .exr: raw values)");
  compare->add_option("--ppd", cf.ppd, "FLIP pixels per degree of visual angle (default 67)");
  compare->add_flag("--json", cf.json, "print the results as JSON");

  FitMeshFlags fitFlags;
  auto* fitCmd = addFitMeshCommand(app, fitFlags);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help is the one "error" that succeeds; every other parse failure is reported like
    // any other error: one line, exit 1 (not CLI11's own codes and two-line message).
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    const std::string unknown = unknownSubcommand(app, argc, argv);
    std::fprintf(stderr, "clhair: error: %s (see clhair --help)\n",
                 unknown.empty() ? oneLine(e.what()).c_str() : unknown.c_str());
    return 1;
  }
  rf.framesGiven = render->count("--frames") > 0;
  rf.widthGiven = render->count("--width") > 0;
  rf.reference = render->count("--reference") > 0;
  rf.sppGiven = render->count("--spp") > 0;
  rf.heightGiven = render->count("--height") > 0;
  captureDriverOutput(true);  // a compiler's own lines go into an error's details
  try {
    DeviceOptions resolved = DeviceOptions::fromEnvironment(opts);
    if (*devices) return cmdDevices(resolved);
    if (*render) return cmdRender(resolved, scenePath, out, rf);
    if (*groom) {
      if (groom->count("--strands") > 0 && strands < 0)
        throw Error("--strands " + std::to_string(strands) +
                    " is negative; expected a strand count 0..50000000");
      return cmdGroom(preset, groomOut, strands);
    }
    if (*exportCmd) return cmdExport(resolved, groomPath, hairOut, exportGroom);
    if (*bakeCmd) return cmdBakeAo(resolved, bakeIn, bakeOut);
    if (*visCmd) return cmdBakeVisibility(resolved, visScene, visOut, vf);
    if (*compare) return cmdCompare(compareA, compareB, cf);
    if (*fitCmd) return cmdFitMesh(fitFlags);
  } catch (const Error& e) {
    reportError(e.what(), e.details(), verbose);
    return 1;
  } catch (const cl::Error& e) {
    reportError(std::string("OpenCL call ") + e.what() + " failed with " + clErrorName(e.err()) +
                    " (" + std::to_string(e.err()) + ")",
                "", verbose);
    return 1;
  } catch (const std::exception& e) {
    reportError(e.what(), "", verbose);
    return 1;
  }
  return 1;
}
