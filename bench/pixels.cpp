// pixels.cpp — a frame's cost against its pixels (DESIGN.md, "LOD from the screen").
//
// Three tables:
// - the default scene (assets/scenes/default.json) at every size of --pixel-sizes, as it
//   rendered before LOD from the screen (its groom without LOD, the maps at the scene's
//   resolution, the lights' passes with Lipp's LOD) and with the defaults: segments
//   and strands drawn, the shadow, strand and whole-frame device times (maps built in every
//   frame, as a still builds them) and the wall clock;
// - LOD off against the defaults: FLIP against the Embree reference (--ref-spp, kept in
//   --ref-cache) over the hair's
//   pixels for the grooms of --quality-grooms at the distances of --quality-distances and
//   the sizes of --pixel-sizes, with each cell's frame time;
// - with --pixel-final: quality final at the first size (the scene's spp), with the kept
//   assembly and with every pass assembling again, against the
//   Embree reference at the same spp, both timed by the wall clock (the reference's BVH
//   build included), and their FLIP and good's against the --ref-spp reference; then final
//   and good again with the reference's own maps (every strand in the lights' passes, at the
//   scene's resolution), which separates the maps' LOD from the camera's sampling.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "clhair/error.h"
#include "clhair/image.h"
#include "clhair/progressive.h"
#include "harness.h"
#include "metrics/image_metrics.h"

namespace clhair::bench {

namespace {

struct Size {
  int w = 0, h = 0;
};

std::vector<Size> parseSizes(const std::string& text) {
  std::vector<Size> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    Size s;
    char x = 0;
    std::stringstream one(item);
    if (!(one >> s.w >> x >> s.h) || x != 'x' || s.w < 16 || s.h < 16)
      throw Error("--pixel-sizes: \"" + item + "\" is not WxH (at least 16x16)");
    out.push_back(s);
  }
  if (out.empty()) throw Error("--pixel-sizes: no size");
  return out;
}

double wallMs(const std::function<void()>& fn) {
  const auto t0 = std::chrono::steady_clock::now();
  fn();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

RenderOptions optionsOf(Toggle lod) {
  RenderOptions o;
  o.lod = lod;
  o.reuseShadows = false;  // every frame builds its maps, as a still does
  if (lod == Toggle::Off) o.shadowResFromCamera = false;
  return o;
}

// The scene as it rendered before LOD from the screen: its grooms without LOD and Lipp's
// strand count in the lights' passes (render it with shadowResFromCamera off).
Scene before(Scene s) {
  for (GroomInstance& g : s.grooms)
    if (g.mesh) {
      auto m = std::make_shared<HairMesh>(*g.mesh);
      m->lod.enabled = false;
      m->lod.strandsPerPixel = 0.0f;
      g.mesh = m;
    }
  return s;
}

// The Embree reference of s at spp, from the cache folder when it holds it.
Frame reference(Run& r, const Scene& s, const std::string& tag, int spp) {
  const std::string path = r.opt.refCache + "/pixels_" + tag + "_" + std::to_string(s.width) + "x" +
                           std::to_string(s.height) + "_embree_" + std::to_string(spp) + "spp.exr";
  Frame f;
  if (!r.opt.refCache.empty() && std::filesystem::exists(path)) {
    f.color = readImage(path);
    return f;
  }
  f = r.b.renderer.renderReference(s, spp, ReferenceMethod::Embree);
  if (!r.opt.refCache.empty()) {
    std::filesystem::create_directories(r.opt.refCache);
    writeImage(f.color, path);
  }
  return f;
}

// The hair's pixels: where the reference differs from the scene without grooms.
std::vector<char> hairMask(Run& r, const Scene& s, const Frame& ref) {
  Scene bare = s;
  bare.grooms.clear();
  const Frame empty = r.b.renderer.render(bare, optionsOf(Toggle::Off));
  std::vector<char> mask(static_cast<std::size_t>(s.width) * s.height, 0);
  for (std::size_t i = 0; i < mask.size(); ++i)
    for (int c = 0; c < 3; ++c)
      mask[i] |= std::fabs(ref.color.rgba[4 * i + c] - empty.color.rgba[4 * i + c]) > 1e-4f;
  return mask;
}

std::string sizeName(const Size& z) { return std::to_string(z.w) + "x" + std::to_string(z.h); }

void costTable(Run& r, const std::vector<Size>& sizes) {
  Scene base = loadScene(std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json");
  r.md << "\n## A frame's cost against its pixels (assets/scenes/default.json, maps built in "
          "every frame, device-time medians of "
       << r.b.runs << " runs)\n\n"
       << "| size | settings | segments | strands | map texels | shadow ms | strands ms | frame ms "
          "| "
          "wall ms |\n|---|---|---|---|---|---|---|---|---|\n";
  json& j = r.report["pixels"]["cost"];
  std::map<std::string, double> frameMs;
  for (const Size& z : sizes) {
    Scene s = base;
    s.width = z.w;
    s.height = z.h;
    for (int row = 0; row < 2; ++row) {
      RenderOptions o = optionsOf(Toggle::Default);
      if (row == 0) o.shadowResFromCamera = false;
      const Scene& rs = row == 0 ? before(s) : s;
      const Frame f = r.b.renderer.render(rs, o);  // warm-up and the counts
      const Measured m = r.b.measure(rs, o, false);
      const char* name = row == 0 ? "before" : "default";
      const int res = f.stats.shadowResolution;
      r.md << "| " << sizeName(z) << " | " << name << " | " << f.stats.segmentsPlanned << " | "
           << f.stats.strandsDrawn << " | " << res << "x" << res << " | "
           << fmt(stageMedian(m, "shadow"), 1) << " | " << fmt(stageMedian(m, "strands"), 1)
           << " | " << fmt(m.total.median, 1) << " | " << fmt(m.wall.median, 1) << " |\n";
      j.push_back({{"size", sizeName(z)},
                   {"pixels", z.w * z.h},
                   {"lod", name},
                   {"segments", f.stats.segmentsPlanned},
                   {"strands", f.stats.strandsDrawn},
                   {"map_resolution", res},
                   {"shadow_ms", stageMedian(m, "shadow")},
                   {"strands_ms", stageMedian(m, "strands")},
                   {"frame_ms", m.total.median},
                   {"wall_ms", m.wall.median}});
      std::fprintf(stderr, "pixels %s LOD %s: %llu segments, frame %.1f ms\n", sizeName(z).c_str(),
                   name, static_cast<unsigned long long>(f.stats.segmentsPlanned), m.total.median);
      frameMs[sizeName(z) + name] = m.total.median;
    }
  }
  const auto ratio = [&](const char* a, const char* b) {
    const auto ia = frameMs.find(std::string(a) + "default");
    const auto ib = frameMs.find(std::string(b) + "default");
    if (ia == frameMs.end() || ib == frameMs.end() || ib->second <= 0.0) return;
    r.md << "\nDefault frame at " << a << " / at " << b << ": " << fmt(ia->second / ib->second, 3)
         << ".";
    r.report["pixels"]["ratio"][std::string(a) + "/" + b] = ia->second / ib->second;
  };
  ratio("480x270", "1920x1080");
  ratio("960x540", "1920x1080");
  r.md << "\n";
}

// One column of the FLIP table: LOD off, the defaults, or the defaults with another number
// of strands per pixel (k > 0) or with the maps at the scene's resolution.
struct Column {
  std::string name;
  Toggle lod = Toggle::Default;
  float k = 0.0f;  // > 0: every groom's strands per pixel
  bool sceneMaps = false;
  bool fullPoints = false;  // L = 1 (λ 1000): every control point
};

Scene withStrandsPerPixel(Scene s, float k, bool fullPoints) {
  for (GroomInstance& g : s.grooms)
    if (g.mesh) {
      auto m = std::make_shared<HairMesh>(*g.mesh);
      if (k > 0.0f) m->lod.strandsPerPixel = k;
      if (fullPoints) m->lod.lambda = 1000.0f;
      g.mesh = m;
    }
  return s;
}

void flipTable(Run& r, const std::vector<Size>& sizes) {
  std::vector<Column> cols = {{"LOD off", Toggle::Off}, {"default", Toggle::Default}};
  std::stringstream ks(r.opt.pixelK);
  for (std::string k; std::getline(ks, k, ',');)
    if (!k.empty())  // "16" or "16f" (every control point)
      cols.push_back({"k " + k, Toggle::Default, std::stof(k), false, k.back() == 'f'});
  if (r.opt.pixelParts.find("scenemaps") != std::string::npos)
    cols.push_back({"default, maps at the scene's resolution", Toggle::Default, 0.0f, true});
  r.md << "\n## LOD from the screen against LOD off (Embree reference " << r.opt.refSpp
       << " spp, mean FLIP over the hair's pixels / segments drawn; in brackets the FLIP over "
          "LOD off's)\n\n| groom | distance | size |";
  for (const Column& c : cols) r.md << " " << c.name << " |";
  r.md << "\n|---|---|---|";
  for (std::size_t c = 0; c < cols.size(); ++c) r.md << "---|";
  r.md << "\n";
  json& j = r.report["pixels"]["flip"];
  std::stringstream dist(r.opt.qualityDistances);
  std::vector<std::string> distances;
  for (std::string d; std::getline(dist, d, ',');) distances.push_back(d);
  for (int g = 0; g < 2; ++g) {
    if ((g == 0 && r.opt.qualityGrooms == "2") || (g == 1 && r.opt.qualityGrooms == "1")) continue;
    for (int d = 0; d < 3; ++d) {
      if (std::find(distances.begin(), distances.end(), r.distNames[d]) == distances.end())
        continue;
      for (const Size& z : sizes) {
        const Scene s = framed(r.scenes[g], r.dists[d], z.w, z.h);
        const std::string tag = "groom" + std::to_string(g + 1) + "_" + r.distNames[d];
        const Frame ref = reference(r, s, tag, r.opt.refSpp);
        const std::vector<char> mask = hairMask(r, s, ref);
        r.md << "| " << (g + 1) << " | " << r.distNames[d] << " | " << sizeName(z) << " |";
        double off = 0.0;
        for (const Column& c : cols) {
          RenderOptions o = optionsOf(c.lod);
          if (c.sceneMaps) o.shadowResFromCamera = false;
          const Frame f = r.b.renderer.render(
              c.k > 0.0f || c.fullPoints ? withStrandsPerPixel(s, c.k, c.fullPoints) : s, o);
          const double flip = maskedFlip(ref.color, f.color, mask);
          if (c.lod == Toggle::Off) off = flip;
          r.md << " " << fmt(flip, 4) << " / " << f.stats.segmentsPlanned;
          if (c.lod != Toggle::Off) r.md << " (" << fmt(flip / std::max(off, 1e-9), 3) << ")";
          r.md << " |";
          j.push_back({{"groom", g + 1},
                       {"distance", r.distNames[d]},
                       {"size", sizeName(z)},
                       {"column", c.name},
                       {"flip", flip},
                       {"ratio", flip / std::max(off, 1e-9)},
                       {"segments", f.stats.segmentsPlanned},
                       {"device_ms", f.totalMs()}});
          std::fprintf(stderr, "pixels flip groom%d %s %s %s: %.4f (%.3f), %llu segments\n", g + 1,
                       r.distNames[d], sizeName(z).c_str(), c.name.c_str(), flip,
                       flip / std::max(off, 1e-9),
                       static_cast<unsigned long long>(f.stats.segmentsPlanned));
        }
        r.md << "\n";
      }
    }
  }
}

void finalTable(Run& r, const Size& z) {
  Scene s = loadScene(std::string(CLHAIR_SOURCE_DIR) + "/assets/scenes/default.json");
  s.width = z.w;
  s.height = z.h;
  s.camera = reframeCamera(s, CameraPreset::Close);
  const Frame ref = reference(r, s, "default_close", r.opt.refSpp);
  const std::vector<char> mask = hairMask(r, s, ref);
  const int spp = finalPasses(s, RenderOptions{});
  RenderOptions fo;
  fo.quality = Quality::Final;
  // Every still and frame timed builds its own maps (a frame of the far camera before it
  // changes what they depend on) after a warm-up that built every kernel.
  Scene far = s;
  far.camera = reframeCamera(s, CameraPreset::Far);
  auto timed = [&](const RenderOptions& o, Frame& out) {
    r.b.renderer.render(far, RenderOptions{});
    return wallMs([&] { out = r.b.renderer.render(s, o); });
  };
  {
    RenderOptions warm = fo;
    warm.spp = 2;
    r.b.renderer.render(s, warm);
    warm.finalSubset = 2;
    r.b.renderer.render(s, warm);
    warm.reuseAssembly = false;
    r.b.renderer.render(s, warm);
  }
  Frame fin, again, good, traced;
  const double finMs = timed(fo, fin);
  RenderOptions ao = fo;  // every pass assembling its strands again (before the kept assembly)
  ao.reuseAssembly = false;
  const double againMs = timed(ao, again);
  // passes that each draw one strand in N, widened (RenderOptions::finalSubset)
  std::vector<std::pair<int, Frame>> subsets;
  std::vector<double> subsetMs;
  for (int n : {2, 4}) {
    RenderOptions so = fo;
    so.finalSubset = n;
    subsets.emplace_back(n, Frame{});
    subsetMs.push_back(timed(so, subsets.back().second));
  }
  RenderOptions go;
  go.quality = Quality::Good;
  const double goodMs = timed(go, good);
  // final and good with the reference's maps: every strand in the lights' passes, at the
  // scene's resolution (Renderer::renderReference), so what remains is the camera's own
  // sampling and LOD
  Frame finMaps, goodMaps;
  RenderOptions fm = fo, gm = go;
  fm.shadowLod = gm.shadowLod = Toggle::Off;
  fm.shadowResFromCamera = gm.shadowResFromCamera = false;
  const double finMapsMs = timed(fm, finMaps), goodMapsMs = timed(gm, goodMaps);
  const double tracedMs =
      wallMs([&] { traced = r.b.renderer.renderReference(s, spp, ReferenceMethod::Embree); });
  const double fFin = maskedFlip(ref.color, fin.color, mask),
               fGood = maskedFlip(ref.color, good.color, mask),
               fTraced = maskedFlip(ref.color, traced.color, mask);
  r.md << "\n## Final against the Embree reference (assets/scenes/default.json, close, "
       << sizeName(z) << ", " << spp << " spp; FLIP over the hair's pixels against the "
       << r.opt.refSpp << "-spp reference; wall clock)\n\n"
       << "| still | wall ms | FLIP |\n|---|---|---|\n"
       << "| final, " << spp << " passes | " << fmt(finMs, 0) << " | " << fmt(fFin, 4) << " |\n"
       << "| final, " << spp << " passes assembling their strands again | " << fmt(againMs, 0)
       << " | " << fmt(maskedFlip(ref.color, again.color, mask), 4) << " |\n";
  for (std::size_t i = 0; i < subsets.size(); ++i) {
    const double f = maskedFlip(ref.color, subsets[i].second.color, mask);
    r.md << "| final, " << spp << " passes of one strand in " << subsets[i].first << " | "
         << fmt(subsetMs[i], 0) << " | " << fmt(f, 4) << " |\n";
    r.report["pixels"]["final_subset_" + std::to_string(subsets[i].first)] = {{"ms", subsetMs[i]},
                                                                              {"flip", f}};
  }
  r.md << "| Embree, " << spp << " spp (BVH build included) | " << fmt(tracedMs, 0) << " | "
       << fmt(fTraced, 4) << " |\n"
       << "| good | " << fmt(goodMs, 0) << " | " << fmt(fGood, 4) << " |\n";
  const double fFinMaps = maskedFlip(ref.color, finMaps.color, mask),
               fGoodMaps = maskedFlip(ref.color, goodMaps.color, mask);
  r.md << "| final, " << spp << " passes, the reference's maps (lights' passes without LOD) | "
       << fmt(finMapsMs, 0) << " | " << fmt(fFinMaps, 4) << " |\n"
       << "| good, the reference's maps | " << fmt(goodMapsMs, 0) << " | " << fmt(fGoodMaps, 4)
       << " |\n"
       << "\nfinal / Embree time: " << fmt(finMs / std::max(tracedMs, 1e-9), 3)
       << " (assembling again: " << fmt(againMs / std::max(tracedMs, 1e-9), 3) << ")"
       << "; final's FLIP / good's: " << fmt(fFin / std::max(fGood, 1e-9), 3)
       << "; maps built over final's passes: " << fin.stats.shadowMapsBuilt
       << ". With the reference's maps: final's FLIP / good's "
       << fmt(fFinMaps / std::max(fGoodMaps, 1e-9), 3) << ", / the default good's "
       << fmt(fFinMaps / std::max(fGood, 1e-9), 3) << ".\n";
  r.report["pixels"]["final"] = {{"spp", spp},
                                 {"final_ms", finMs},
                                 {"final_flip", fFin},
                                 {"final_assembling_again_ms", againMs},
                                 {"embree_ms", tracedMs},
                                 {"embree_flip", fTraced},
                                 {"good_ms", goodMs},
                                 {"good_flip", fGood},
                                 {"maps_built", fin.stats.shadowMapsBuilt},
                                 {"final_reference_maps_ms", finMapsMs},
                                 {"final_reference_maps_flip", fFinMaps},
                                 {"good_reference_maps_ms", goodMapsMs},
                                 {"good_reference_maps_flip", fGoodMaps}};
}

}  // namespace

void runPixels(Run& r) {
  const std::vector<Size> sizes = parseSizes(r.opt.pixelSizes);
  if (r.opt.pixelParts.find("cost") != std::string::npos) costTable(r, sizes);
  if (r.opt.pixelParts.find("flip") != std::string::npos) flipTable(r, sizes);
  if (r.opt.pixelParts.find("final") != std::string::npos) finalTable(r, sizes.front());
}

}  // namespace clhair::bench
