// lod_far.cpp — see lod_far.h.
#include "lod_far.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include "clhair/scene.h"
#include "masked_flip.h"

namespace clhair::bench {

namespace {

struct Row {
  const char* name;
  Toggle lod;         // RenderOptions::lod
  Toggle shadowLod;   // RenderOptions::shadowLod
  Toggle fromCamera;  // RenderOptions::shadowLodCamera
  DispatchMode mode = DispatchMode::Auto;
};

struct Timed {
  std::map<std::string, double> stages;  // medians
  double total = 0.0;
  FrameStats stats;
  Frame frame;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

RenderOptions optionsOf(const Row& r) {
  RenderOptions o;
  o.lod = r.lod;
  o.shadowLod = r.shadowLod;
  o.shadowLodCamera = r.fromCamera;
  o.dispatch = r.mode;
  o.reuseShadows = false;  // every frame builds its maps: their passes are timed
  return o;
}

Timed timeRow(Renderer& renderer, const Scene& s, const Row& r, int runs, int warmup) {
  const RenderOptions o = optionsOf(r);
  for (int i = 0; i < warmup; ++i) renderer.render(s, o);
  std::map<std::string, std::vector<double>> stages;
  std::vector<double> totals;
  Timed t;
  for (int i = 0; i < std::max(runs, 1); ++i) {
    Frame f = renderer.render(s, o);
    for (const StageTime& st : f.timings) stages[st.stage].push_back(st.ms);
    totals.push_back(f.totalMs());
    if (i == 0) {
      t.stats = f.stats;
      t.frame = std::move(f);
    }
  }
  for (auto& [k, v] : stages) t.stages[k] = median(v);
  t.total = median(totals);
  return t;
}

double stage(const Timed& t, const char* name) {
  auto it = t.stages.find(name);
  return it == t.stages.end() ? 0.0 : it->second;
}

std::string fmt(double v, int digits = 1) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.*f", digits, v);
  return b;
}

}  // namespace

void lodFarSection(Renderer& renderer, const LodFarOptions& o, std::ostringstream& md,
                   nlohmann::json& report) {
  Scene s = loadScene(o.scene);
  s.width = o.width;
  s.height = o.height;
  s.camera = reframeCamera(s, CameraPreset::Far);
  constexpr Toggle kOn = Toggle::On, kOff = Toggle::Off, kDefault = Toggle::Default;
  const Row rows[] = {
      {"LOD off", kOff, kOff, kOff},
      {"LOD, lights' passes capped by the camera's LOD (default)", kOn, kDefault, kDefault},
      {"LOD, lights' passes in the light's view alone", kOn, kDefault, kOff},
      {"LOD, full-detail maps", kOn, kOff, kOff}};
  std::vector<Timed> timed;
  for (const Row& r : rows) {
    timed.push_back(timeRow(renderer, s, r, o.runs, o.warmup));
    std::fprintf(stderr, "lodfar %s: strands %.1f ms, shadow %.1f ms, total %.1f ms\n", r.name,
                 stage(timed.back(), "strands"), stage(timed.back(), "shadow"), timed.back().total);
  }
  nlohmann::json& j = report["lodfar"];
  md << "\n## LOD at a distance (" << o.scene << ", far, " << o.width << "x" << o.height
     << ", maps rebuilt every frame, device-time medians of " << o.runs << " runs)\n\n"
     << "| configuration | strands ms | shadow ms | frame ms | camera strands | map strands |\n"
     << "|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < timed.size(); ++k) {
    const Timed& t = timed[k];
    md << "| " << rows[k].name << " | " << fmt(stage(t, "strands")) << " | "
       << fmt(stage(t, "shadow")) << " | " << fmt(t.total) << " | " << t.stats.strandsDrawn << " | "
       << t.stats.shadowStrandsDrawn << " |\n";
    j["rows"].push_back({{"name", rows[k].name},
                         {"strands_ms", stage(t, "strands")},
                         {"shadow_ms", stage(t, "shadow")},
                         {"frame_ms", t.total},
                         {"strands", t.stats.strandsDrawn},
                         {"map_strands", t.stats.shadowStrandsDrawn}});
  }
  const double off = stage(timed[0], "strands"), on = stage(timed[1], "strands"),
               light = stage(timed[2], "strands");
  const double offBoth = off + stage(timed[0], "shadow"), onBoth = on + stage(timed[1], "shadow");
  md << "\nStrand stage with LOD off / with LOD: " << fmt(off / std::max(on, 1e-9), 2)
     << "x (the light's view alone: " << fmt(off / std::max(light, 1e-9), 2)
     << "x); strand and shadow stages together: " << fmt(offBoth / std::max(onBoth, 1e-9), 2)
     << "x.\n";
  j["strands_ratio"] = off / std::max(on, 1e-9);
  j["strands_ratio_light_view"] = off / std::max(light, 1e-9);
  j["strands_shadow_ratio"] = offBoth / std::max(onBoth, 1e-9);

  // the strand pass's sizing with LOD (the default's rows)
  md << "\n| dispatch sizing, with LOD | strands ms |\n|---|---|\n";
  for (DispatchMode m :
       {DispatchMode::ReadBack, DispatchMode::OverLaunch, DispatchMode::Persistent}) {
    Row r = rows[1];
    r.mode = m;
    const Timed t = timeRow(renderer, s, r, o.runs, o.warmup);
    md << "| " << dispatchModeName(m) << " | " << fmt(stage(t, "strands")) << " |\n";
    j["dispatch"][dispatchModeName(m)] = stage(t, "strands");
  }

  // the pixels the hair's shadow darkens: the LOD-off frame against the same frame without
  // hair shadows, luminance down by more than 2 %
  Scene unshadowed = s;
  for (Light& l : unshadowed.lights) l.shadows = false;
  const Frame lit = renderer.render(unshadowed, optionsOf(rows[0]));
  const Frame& ref = timed[0].frame;
  std::vector<char> mask(ref.depth.size(), 0);
  std::size_t shadowed = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    auto lum = [&](const Frame& f) {
      return 0.2126 * f.color.rgba[4 * i] + 0.7152 * f.color.rgba[4 * i + 1] +
             0.0722 * f.color.rgba[4 * i + 2];
    };
    mask[i] = lum(ref) < 0.98 * lum(lit) ? 1 : 0;
    shadowed += mask[i];
  }
  // the same pixels without hair in them (the hair's shadow on the head and the scene),
  // where the frames differ by their shadows alone and not by the camera's LOD: hair is
  // where the unshadowed LOD-off frame differs from the scene without grooms
  Scene bare = unshadowed;
  bare.grooms.clear();
  const Frame empty = renderer.render(bare, optionsOf(rows[0]));
  std::vector<char> onScene(mask.size(), 0);
  std::size_t sceneShadowed = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    bool hair = false;
    for (int c = 0; c < 3; ++c)
      hair |= std::fabs(lit.color.rgba[4 * i + c] - empty.color.rgba[4 * i + c]) > 1e-4f;
    onScene[i] = mask[i] && !hair ? 1 : 0;
    sceneShadowed += onScene[i];
  }
  const double sceneOnVsOff = maskedFlip(timed[1].frame.color, timed[0].frame.color, onScene);
  const double sceneFullVsOff = maskedFlip(timed[3].frame.color, timed[0].frame.color, onScene);
  const double capVsFull = maskedFlip(timed[1].frame.color, timed[3].frame.color, mask);
  const double lightVsFull = maskedFlip(timed[2].frame.color, timed[3].frame.color, mask);
  const double onVsOff = maskedFlip(timed[1].frame.color, timed[0].frame.color, mask);
  md << "\nOver the " << shadowed
     << " pixels the hair's shadow darkens (LOD off, by more than 2 %), mean FLIP: capped maps "
        "against full-detail maps (the same camera LOD) "
     << fmt(capVsFull, 4) << "; the light's view alone against full-detail maps "
     << fmt(lightVsFull, 4) << "; the LOD frame against the LOD-off frame " << fmt(onVsOff, 4)
     << ".\n";
  md << "Over the " << sceneShadowed
     << " of them without hair in front (the shadow on the head and the scene), mean FLIP "
        "against the LOD-off frame: the LOD frame with capped maps "
     << fmt(sceneOnVsOff, 4) << ", with full-detail maps " << fmt(sceneFullVsOff, 4) << ".\n";
  j["scene_shadowed_pixels"] = sceneShadowed;
  j["scene_flip_lod_vs_off"] = sceneOnVsOff;
  j["scene_flip_full_maps_vs_off"] = sceneFullVsOff;
  j["shadowed_pixels"] = shadowed;
  j["flip_capped_vs_full_maps"] = capVsFull;
  j["flip_light_view_vs_full_maps"] = lightVsFull;
  j["flip_lod_vs_off"] = onVsOff;
}

}  // namespace clhair::bench
