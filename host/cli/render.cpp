// render.cpp — the frames of `clhair render`: each frame (or the views of one) is submitted
// to the Renderer, drawn while earlier ones are read back and handed to the WriteQueue's
// threads; references, temporal sequences and --quality final stills are rendered one by
// one. Prints each frame's line (or progress of a sequence), --stats and --passes. The
// checks before the first frame are planRender's (render_plan.cpp).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <memory>

#include "clhair/error.h"
#include "clhair/progressive.h"
#include "clhair/temporal.h"
#include "io/draw_warnings.h"
#include "io/json_util.h"
#include "io/safe_write.h"
#include "io/view_notes.h"
#include "render.h"

namespace clhair::cli {

namespace {

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
    if (!g.lod) std::printf(", without LOD");
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
  else if (std::none_of(st.grooms.begin(), st.grooms.end(),
                        [](const GroomDrawStats& g) { return g.drawn && g.lod; }))
    std::printf(" (no groom drawn with LOD: the budget of %llu applies to none)\n",
                static_cast<unsigned long long>(st.segmentBudget));
  else
    std::printf(
        " (budget %llu over the grooms drawn with LOD, which asked for %llu: "
        "not reached)\n",
        static_cast<unsigned long long>(st.segmentBudget),
        static_cast<unsigned long long>(st.segmentsBeforeBudget));
  std::printf("host waits: %llu\n", static_cast<unsigned long long>(st.hostWaits));
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

}  // namespace

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
  RenderPlan plan = planRender(opts, scenePath, out, f);
  const bool quiet = f.quiet;
  const std::vector<long long>& frames = plan.frames;
  const std::vector<Aov>& aovs = plan.aovs;
  const Device& dev = plan.dev;
  const Scene& scene = plan.scene;
  const std::vector<View>& views = plan.views;
  const bool several = plan.several, temporal = plan.temporal, final = plan.finalQuality;
  RenderOptions& ro = plan.ro;
  const CameraPreset* preset = plan.preset ? &*plan.preset : nullptr;
  const ReferenceOptions& ref = plan.ref;
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
      writer.submit([channels, header = aovAttributes(shots[0], aovs), path, w = q.width,
                     h = q.height,
                     o = f.write] { writeChannels(*channels, w, h, path, o, header); });
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
    if (frame.stats.pathRays > 0 && frame.stageMs("paths") > 0.0)
      std::printf("  %-10s %9.3f M rays/s (%llu rays)\n", "paths",
                  1e-3 * static_cast<double>(frame.stats.pathRays) / frame.stageMs("paths"),
                  static_cast<unsigned long long>(frame.stats.pathRays));
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
      if (rendered == 0 && inFlight.empty()) {
        for (const std::string& w : viewWarnings(still, scenePath))
          std::fprintf(stderr, "clhair: warning: %s\n", w.c_str());
        // notes are for a person watching: -q (print nothing on success) leaves them out
        // the filtered hair of a faint groom is widened by the renderer (faint_groom.h)
        const bool filtered = ro.msaa == 1 && isOn(ro.filter, still.filter.enabled) &&
                              ro.pointShading != Toggle::On && !ro.trueWidth &&
                              ro.raster.value_or(still.raster) != RasterMode::Coverage;
        if (!quiet)
          for (const std::string& n : viewNotes(still, scenePath, filtered))
            std::fprintf(stderr, "clhair: note: %s\n", n.c_str());
      }
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

}  // namespace clhair::cli
