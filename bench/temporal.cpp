// temporal.cpp — the benchmark's temporal section (clhair_bench --only temporal):
// A 30-frame orbit: mean frame-to-frame change for SWR1, SWR1+F (Lipp's filter), SWR1 with Huang's
// filter and its parts, MSAA 4, and with temporal reprojection (clhair/temporal.h) on, after SWR1,
// Lipp's filter or Huang's: flicker, FLIP against a per-frame reference (--temporal-ref-spp), and
// on a fast shot the hair left in the pixels the groom vacated.
#include "harness.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "clhair/temporal.h"
#include "metrics/image_metrics.h"

namespace clhair::bench {

void runTemporal(Run& r) {
  // flicker: a 30-frame orbit, the mean absolute frame-to-frame change of sRGB values;
  // with temporal reprojection (clhair/temporal.h) also the error against a per-frame
  // reference (ghosting adds error, flicker alone does not) and, on a shot whose groom
  // moves fast, the hair left behind in the pixels it vacated
  const int tw = r.opt.quick ? 320 : r.opt.qualityWidth,
            th = r.opt.quick ? 180 : r.opt.qualityHeight;
  const int frames = r.opt.quick ? 8 : 30;
  std::set<std::string> temporalChosen;  // --quality-configs, the names this section has
  for (std::size_t at = 0; !r.opt.qualityConfigs.empty() && at <= r.opt.qualityConfigs.size();) {
    const std::size_t comma =
        std::min(r.opt.qualityConfigs.find(',', at), r.opt.qualityConfigs.size());
    temporalChosen.insert(r.opt.qualityConfigs.substr(at, comma - at));
    at = comma + 1;
  }
  struct Config {
    const char* name;
    int msaa, filter;
    int history;    // temporal reprojection: frames of history, 0 off
    bool protect;   // the depth rule and the neighbourhood clamp
    int huang = 0;  // 0: Lipp's filter; else Huang's: 1 linking, 2 + alpha fix, 3 + filter
    Quality quality = Quality::Draft;  // RenderOptions::quality
  };
  const Config configs[] = {{"SWR1", 1, 0, 0, true},
                            {"good", 1, 0, 0, true, 0, Quality::Good},
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
    t.ref = r.b.renderer.renderReference(s, r.opt.temporalRefSpp, ReferenceMethod::Embree);
    Scene bare = s;
    bare.grooms.clear();
    const Frame background = r.b.renderer.render(bare);
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
    o.filter = c.filter ? Toggle::On : Toggle::Off;
    o.lod = Toggle::Off;
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
    Scene s = r.scenes[0];
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
    hairPerFrame +=
        static_cast<std::size_t>(std::count(truth.back().mask.begin(), truth.back().mask.end(), 1));
  }
  hairPerFrame /= static_cast<std::size_t>(frames);
  r.md << "\n## Temporal stability (" << r.groomNames[0] << ", mid, " << frames
       << "-frame orbit of 0.5 deg per frame, " << tw << "x" << th
       << ")\n\nFlicker: mean absolute sRGB change between consecutive frames (lower is "
          "steadier). FLIP: mean over the frames of the mean FLIP over the hair's pixels "
          "against that frame's Embree reference ("
       << r.opt.temporalRefSpp
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
        r.b.renderer, [&](long long f) { return protectedScene(orbitAt(f), c); }, optionsOf(c), 0);
    double total = 0.0, flip = 0.0, totalHair = 0.0;
    std::vector<float> prev;
    double renderMs = 0.0;
    TemporalStats steps;
    for (int f = 0; f < frames; ++f) {
      const auto r0 = std::chrono::steady_clock::now();
      const Frame fr = seq.render(f);
      renderMs +=
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0).count();
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
    r.md << "| " << c.name << " | " << fmt(flicker, 5) << " | " << fmt(flickerHair, 4) << " | "
         << fmt(flip, 4) << " | " << fmt(dropped, 0) << " / " << fmt(clamped, 0) << " | "
         << fmt(renderMs / frames, 0) << " | " << seq.framesRendered() << " |\n";
    // the first three rows keep their flat numbers in bench.json (earlier reports)
    if (c.history == 0) r.report["temporal"][c.name] = flicker;
    r.report["temporal_study"][c.name] = {{"flicker", flicker},
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
    r.md << "| (none: --quality-configs names none of this section's rows) | |\n";
    std::fprintf(stderr, "temporal: --quality-configs names none of this section's rows\n");
  }
  // a fast shot: the groom translated sideways about 8 px a frame, camera still
  const int fastFrames = r.opt.quick ? 5 : 10;
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
    o.lod = Toggle::Off;
    o.filter = Toggle::On;
    o.aovs = true;
    FrameSequence own(r.b.renderer, fastAt, o, 0);
    for (int f = 0; f < fastFrames; ++f) ownAlpha.push_back(own.render(f).aovs.hairAlpha);
  }
  r.md << "\nFast shot (the same groom translated " << fmt(step, 4)
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
        r.b.renderer, [&](long long f) { return protectedScene(fastAt(f), c); }, o, 0);
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
    r.md << "| " << c.name << " | " << vacated << " | " << fmt(mean, 5) << " | " << fmt(worst, 4)
         << " | " << fmt(share, 4) << " | " << fmt(flip, 4) << " | "
         << fmt(static_cast<double>(steps.rejected) / fastFrames, 0) << " / "
         << fmt(static_cast<double>(steps.clamped) / fastFrames, 0) << " |\n";
    r.report["temporal_study"]["fast_shot"][c.name] = {
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

}  // namespace clhair::bench
