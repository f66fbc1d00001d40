// quality.cpp — the benchmark's quality section (clhair_bench --only quality):
// Lipp Fig. 7: SWR1, SWR1+F, SWR1+F+L (LOD strands with the single-fibre BSDF, and with Huang's
// aggregated one), MSAA 2/4/8, the coverage raster (Kulikov 2025) at close/mid/far, FLIP and PSNR
// against the reference (--ref embree: the strands traced as round curves, the default; raster:
// jittered true-width strand passes), with frame times; at mid also SWR1 against the other
// reference and the two references' times.
#include "harness.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "clhair/image.h"
#include "clhair/progressive.h"
#include "metrics/image_metrics.h"

namespace clhair::bench {

void runQuality(Run& r) {
  // Lipp Fig. 7: each configuration against the reference (average of refSpp jittered
  // true-width passes), FLIP and PSNR, with its frame time.
  const int qw = r.opt.quick ? 320 : r.opt.qualityWidth,
            qh = r.opt.quick ? 180 : r.opt.qualityHeight;
  const ReferenceMethod refMethod = parseReferenceMethod(r.opt.refName);
  const ReferenceMethod otherMethod =
      refMethod == ReferenceMethod::Embree ? ReferenceMethod::Raster : ReferenceMethod::Embree;
  if (r.opt.qualityGrooms != "1" && r.opt.qualityGrooms != "2" && r.opt.qualityGrooms != "both")
    throw Error("--quality-grooms must be 1, 2 or both, not \"" + r.opt.qualityGrooms + "\"");
  if (r.opt.qualityLights != "plain" && r.opt.qualityLights != "maps" &&
      r.opt.qualityLights != "both")
    throw Error("--quality-lights must be plain, maps or both, not \"" + r.opt.qualityLights +
                "\"");
  std::filesystem::create_directories(r.opt.out + "/quality");
  struct Config {
    const char* name;
    int msaa, filter, lod;
    bool promote;          // the filter's strand connection (Lipp §3.3.2)
    int huang;             // 0: Lipp's filter; else Huang's: 1 linking, 2 + alpha fix, 3 + filter
    int lodAggregate = 0;  // LOD strands: single fibre or aggregated BCSDF (Huang 2024)
    RasterMode raster = RasterMode::Lines;  // or coverage (Kulikov 2025, clhair/coverage.h)
    // segment budget: -1 the scene's (2 M segments by default), 0 none; with LOD a
    // groom over the budget keeps fewer, wider strands (docs/scene-format.md)
    std::int64_t budget = -1;
    int points = 0;  // 1: shaded once per visible strand point (RenderOptions::pointShading)
    Quality quality = Quality::Draft;  // RenderOptions::quality (draft: the fields above)
    int finalPasses = 0;  // final: passes (the first N of one progressive run per cell)
    FinalPath finalPath = FinalPath::Default;  // final: RenderOptions::finalPath
  };
  const Config configs[] = {
      {"SWR1", 1, 0, 0, true, 0},
      {"SWR1+F", 1, 1, 0, true, 0},
      {"SWR1+F+L", 1, 1, 1, true, 0},
      {"SWR1+F+L aggregated", 1, 1, 1, true, 0, 1},
      {"SWR1+L", 1, 0, 1, true, 0},
      {"SWR1+L aggregated", 1, 0, 1, true, 0, 1},
      {"SWR1+F, no promotion", 1, 1, 0, false, 0},
      {"SWR1+H linking", 1, 1, 0, true, 1},
      {"SWR1+H linking+alpha fix", 1, 1, 0, true, 2},
      {"SWR1+H (linking+alpha fix+anisotropic)", 1, 1, 0, true, 3},
      {"SWR1+H+L", 1, 1, 1, true, 3},
      {"SWR1+H+L no budget", 1, 1, 1, true, 3, 0, RasterMode::Lines, 0},
      {"SWR MSAA 2", 2, 0, 0, true, 0},
      {"SWR MSAA 4", 4, 0, 0, true, 0},
      {"SWR MSAA 8", 8, 0, 0, true, 0},
      {"SWR MSAA 4 per point", 4, 0, 0, true, 0, 0, RasterMode::Lines, -1, 1},
      {"SWR MSAA 8 per point", 8, 0, 0, true, 0, 0, RasterMode::Lines, -1, 1},
      {"SWR1 per point", 1, 0, 0, true, 0, 0, RasterMode::Lines, -1, 1},
      {"good", 1, 0, 0, true, 0, 0, RasterMode::Lines, -1, 0, Quality::Good},
      {"final 4", 1, 0, 0, true, 0, 0, RasterMode::Lines, -1, 0, Quality::Final, 4},
      {"final 16", 1, 0, 0, true, 0, 0, RasterMode::Lines, -1, 0, Quality::Final, 16},
      {"final 64", 1, 0, 0, true, 0, 0, RasterMode::Lines, -1, 0, Quality::Final, 64},
      {"final SWR1 4", 1, 0, 0, true, 0, 0, RasterMode::Lines, -1, 0, Quality::Final, 4,
       FinalPath::OneSample},
      {"final SWR1 16", 1, 0, 0, true, 0, 0, RasterMode::Lines, -1, 0, Quality::Final, 16,
       FinalPath::OneSample},
      {"final SWR1 64", 1, 0, 0, true, 0, 0, RasterMode::Lines, -1, 0, Quality::Final, 64,
       FinalPath::OneSample},
      {"SWR coverage", 1, 0, 0, true, 0, 0, RasterMode::Coverage}};
  auto splitList = [](const std::string& list) {
    std::set<std::string> items;
    for (std::size_t at = 0; !list.empty() && at <= list.size();) {
      const std::size_t comma = std::min(list.find(',', at), list.size());
      items.insert(list.substr(at, comma - at));
      at = comma + 1;
    }
    return items;
  };
  const std::set<std::string> chosen = splitList(r.opt.qualityConfigs);
  const std::set<std::string> distances = splitList(r.opt.qualityDistances);
  for (const std::string& name : distances)
    if (name != "close" && name != "mid" && name != "far")
      throw Error("--quality-distances: no distance \"" + name + "\" (close, mid, far)");
  for (const std::string& name : chosen)
    if (std::none_of(std::begin(configs), std::end(configs),
                     [&](const Config& c) { return name == c.name; }))
      throw Error("--quality-configs: no configuration \"" + name + "\"");
  if (!r.opt.refCache.empty()) std::filesystem::create_directories(r.opt.refCache);
  // the reference of one groom and distance, from the cache when it holds it
  auto reference = [&](const Scene& s, int g, int d, ReferenceMethod method, std::string ltag) {
    // the path reference shadows every light by the geometry whatever the lights say:
    // one reference serves both lightings, and its mask is always from the depth
    const bool traced = method == ReferenceMethod::Path;
    if (traced) ltag.clear();
    const std::string path = r.opt.refCache + "/groom" + std::to_string(g + 1) + "_" + ltag +
                             r.distNames[d] + "_" + std::to_string(s.width) + "x" +
                             std::to_string(s.height) + "_" + referenceMethodName(method) + "_" +
                             std::to_string(r.opt.refSpp) + "spp.exr";
    // the depth (the hair mask of the lighting with maps) as raw floats beside it
    const std::string depthPath = path + ".depth";
    Frame f;
    if (!r.opt.refCache.empty() && std::filesystem::exists(path)) {
      f.color = readImage(path);
      if (ltag.empty() && !traced) return f;  // plain: the mask is from the colour alone
      f.depth.resize(static_cast<std::size_t>(f.color.width) * f.color.height);
      std::ifstream in(depthPath, std::ios::binary);
      in.read(reinterpret_cast<char*>(f.depth.data()),
              static_cast<std::streamsize>(f.depth.size() * sizeof(float)));
      if (in && in.gcount() == static_cast<std::streamsize>(f.depth.size() * sizeof(float)))
        return f;
    }
    f = r.b.renderer.renderReference(s, r.opt.refSpp, method);
    if (!r.opt.refCache.empty()) {
      writeImage(f.color, path);
      std::ofstream o(depthPath, std::ios::binary);
      o.write(reinterpret_cast<const char*>(f.depth.data()),
              static_cast<std::streamsize>(f.depth.size() * sizeof(float)));
    }
    return f;
  };
  // mean linear luminance over the hair's pixels (brighter or darker than the reference)
  auto hairLuminance = [](const Frame& f, const std::vector<char>& mask) {
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < mask.size(); ++i)
      if (mask[i]) {
        ++n;
        sum += 0.2126 * f.color.rgba[4 * i] + 0.7152 * f.color.rgba[4 * i + 1] +
               0.0722 * f.color.rgba[4 * i + 2];
      }
    return sum / std::max<std::size_t>(n, 1);
  };
  auto wallMs = [](auto&& fn) {
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  json q;
  for (int run = 0; run < 4; ++run) {  // plain lights, then lights with maps
    const int lighting = run / 2, g = run % 2;
    if ((g == 0 && r.opt.qualityGrooms == "2") || (g == 1 && r.opt.qualityGrooms == "1")) continue;
    // lighting 1: every light of the groom's scene with a deep opacity map, so that the
    // reference (maps of the full groom) and the frames (maps drawn with their LOD) are
    // shadowed between fibres by the same model
    const bool maps = lighting == 1;
    if ((maps && r.opt.qualityLights == "plain") || (!maps && r.opt.qualityLights == "maps"))
      continue;
    const std::string ltag = maps ? "maps_" : "";               // plain keeps its file names
    const std::string gtag = ltag + (g == 0 ? "" : "groom2_");  // groom1 keeps its names
    r.md << "\n## Quality against the reference (" << r.groomNames[g] << ", " << qw << "x" << qh
         << ", " << referenceMethodName(refMethod) << " reference " << r.opt.refSpp << " spp"
         << (maps ? ", every light with a deep opacity map" : "") << ")\n\nOver the hair's pixels ("
         << (maps || refMethod == ReferenceMethod::Path
                 ? "where a sample of the reference saw hair in front of the scene: the hair "
                   "also shadows the head"
                 : "where the reference differs from the scene without hair")
         << "): mean FLIP (lower is better) / PSNR dB / frame ms. Whole-image values are in "
            "bench.json. SWR1+H: Huang's filter (DESIGN.md).\n\n| configuration |";
    for (int d = 0; d < 3; ++d)
      if (distances.count(r.distNames[d])) r.md << " " << r.distNames[d] << " |";
    r.md << "\n|---|";
    for (int d = 0; d < 3; ++d)
      if (distances.count(r.distNames[d])) r.md << "---|";
    r.md << "\n";
    std::map<std::string, std::vector<std::string>> cells;
    json& ql = maps ? q["lights_maps"] : q;
    json& qg = g == 0 ? ql : ql["groom2"];
    std::ostringstream refMd;  // the two references at mid
    for (int d = 0; d < 3; ++d) {
      if (!distances.count(r.distNames[d])) continue;
      Scene s = framed(r.scenes[g], r.dists[d], qw, qh);
      for (Light& light : s.lights) light.shadows = maps;
      Frame ref;
      const double refMs = wallMs([&] { ref = reference(s, g, d, refMethod, ltag); });
      qg["reference"][r.distNames[d]] = {
          {"method", referenceMethodName(refMethod)}, {"spp", r.opt.refSpp}, {"wall_ms", refMs}};
      std::fprintf(stderr, "quality %s%s %s: %s reference, %d spp, %.1f s\n", ltag.c_str(),
                   r.groomNames[g], r.distNames[d], referenceMethodName(refMethod), r.opt.refSpp,
                   refMs / 1000.0);
      Scene bare = s;
      bare.grooms.clear();
      const Frame background = r.b.renderer.render(bare);
      std::vector<char> hairMask(ref.color.rgba.size() / 4, 0);
      // the hair's shadows change the head too (maps, and always in the path reference):
      // the mask is where a sample of the reference saw hair
      const bool depthMask = maps || refMethod == ReferenceMethod::Path;
      for (std::size_t i = 0; i < hairMask.size(); ++i)
        if (depthMask)
          hairMask[i] = ref.depth[i] < background.depth[i] * (1.0f - 1e-6f);
        else
          for (int c = 0; c < 3; ++c)
            hairMask[i] |=
                std::fabs(ref.color.rgba[4 * i + c] - background.color.rgba[4 * i + c]) > 1e-4f;
      qg["reference"][r.distNames[d]]["hair_luminance"] = hairLuminance(ref, hairMask);
      const std::string refPath =
          r.opt.out + "/quality/" + gtag + r.distNames[d] + "_reference.png";
      writeImage(ref.color, refPath);
      // the scene without hair: the hair's pixels are where the reference differs from it
      writeImage(background.color,
                 r.opt.out + "/quality/" + gtag + r.distNames[d] + "_background.png");
      // quality final: one progressive run per pass path and cell, whose first N passes
      // give the row of N passes (the rows of fewer passes are its prefixes)
      std::map<FinalPath, std::unique_ptr<ProgressiveStill>> finals;
      for (const Config& c : configs) {
        if (!chosen.empty() && !chosen.count(c.name)) continue;
        RenderOptions o;
        o.msaa = c.msaa;
        o.filter = c.filter ? Toggle::On : Toggle::Off;
        o.lod = c.lod ? Toggle::On : Toggle::Off;
        o.lodAggregate = c.lodAggregate != 0;
        o.raster = c.raster;
        o.segmentBudget = c.budget;
        // draft rows say whether they shade per point; good and final leave it to the level
        if (c.quality == Quality::Draft) o.pointShading = c.points ? Toggle::On : Toggle::Off;
        o.quality = c.quality;
        o.finalPath = c.finalPath;
        Scene sc = s;
        useFilter(sc, c.huang, c.promote);
        Frame f;
        if (c.finalPasses > 0) {
          std::unique_ptr<ProgressiveStill>& acc = finals[c.finalPath];
          if (!acc) acc = std::make_unique<ProgressiveStill>(r.b.renderer, s, o);
          acc->add(acc->passes(), std::max(c.finalPasses - acc->passes(), 0));
          f = acc->frame();
        } else {
          f = r.b.renderer.render(sc, o);
        }
        // --runs 0 (quick tuning runs): the times of this one frame; final: the sum of
        // its passes' times
        Measured m;
        if (r.opt.runs > 0 && c.finalPasses == 0) {
          m = r.b.measure(sc, o, false);
        } else {
          for (const StageTime& t : f.timings) m.stages[t.stage] = summarize({t.ms});
          m.total = summarize({f.totalMs()});
        }
        ImageComparison cmp = compareImages(ref.color, f.color);
        // the same measures restricted to the hair's pixels
        const double psnrHair = computePsnr(ref.color, f.color, &hairMask).psnrDb;
        double flipHair = 0.0;
        std::size_t nHair = 0;
        for (std::size_t i = 0; i < hairMask.size(); ++i)
          if (hairMask[i]) {
            ++nHair;
            flipHair += cmp.flip.error[i];
          }
        flipHair /= std::max<std::size_t>(nHair, 1);
        std::string name = c.name;
        std::string file = name;
        for (char& ch : file)
          if (ch == ' ' || ch == '+' || ch == ',' || ch == '(' || ch == ')') ch = '_';
        writeImage(f.color, r.opt.out + "/quality/" + gtag + r.distNames[d] + "_" + file + ".png");
        // the filter's share of the frame: Huang's link and filter stages, or Lipp's
        const double filterMs = stageMedian(m, "link") + stageMedian(m, "filter");
        cells[name].push_back(fmt(flipHair, 4) + " / " + fmt(psnrHair, 1) + " / " +
                              fmt(m.total.median));
        qg[name][r.distNames[d]] = {{"flip_hair", flipHair},
                                    {"psnr_hair_db", psnrHair},
                                    {"flip", cmp.flip.mean},
                                    {"psnr_db", cmp.psnr.psnrDb},
                                    {"frame_ms", m.total.median},
                                    {"hair_pixels", nHair},
                                    {"hair_luminance", hairLuminance(f, hairMask)},
                                    {"filter_ms", filterMs},
                                    {"linked_pixels", f.stats.linkedPixels},
                                    {"link_turned_away", f.stats.linkTurnedAway}};
        std::fprintf(stderr,
                     "quality %s%s %s %s: hair FLIP %.4f PSNR %.1f (image FLIP %.4f), frame "
                     "%.1f ms, filter %.1f ms\n",
                     ltag.c_str(), r.groomNames[g], c.name, r.distNames[d], flipHair, psnrHair,
                     cmp.flip.mean, m.total.median, filterMs);
        if (!maps && g == 0 && d == 1 && c.msaa == 1 && c.filter == 0 && c.lod == 0 &&
            c.raster == RasterMode::Lines && c.quality == Quality::Draft && c.points == 0) {
          // SWR1 at mid against the other reference too, over the same hair pixels
          Frame other;
          const double otherMs = wallMs([&] { other = reference(s, g, d, otherMethod, ltag); });
          writeImage(other.color, r.opt.out + "/quality/mid_reference_" +
                                      referenceMethodName(otherMethod) + ".png");
          const double flipOther = maskedFlip(other.color, f.color, hairMask);
          const double flipRefs = maskedFlip(ref.color, other.color, hairMask);
          const char* a = referenceMethodName(refMethod);
          const char* o = referenceMethodName(otherMethod);
          refMd << "\nSWR1 at mid, mean FLIP over the hair against each reference (" << r.opt.refSpp
                << " spp): " << a << " " << fmt(flipHair, 4) << ", " << o << " "
                << fmt(flipOther, 4) << "; the " << o << " reference against the " << a
                << " one: " << fmt(flipRefs, 4) << ". Reference wall time: " << a << " "
                << fmt(refMs / 1000.0, 1) << " s, " << o << " " << fmt(otherMs / 1000.0, 1)
                << " s.\n";
          q["references_mid"] = {{"swr1_flip_hair_" + std::string(a), flipHair},
                                 {"swr1_flip_hair_" + std::string(o), flipOther},
                                 {"flip_hair_between_references", flipRefs},
                                 {std::string(a) + "_wall_ms", refMs},
                                 {std::string(o) + "_wall_ms", otherMs}};
          std::fprintf(stderr, "quality SWR1 mid: hair FLIP %.4f vs %s, %.4f vs %s\n", flipHair, a,
                       flipOther, o);
        }
      }
    }
    for (const Config& c : configs) {
      if (!chosen.empty() && !chosen.count(c.name)) continue;
      r.md << "| " << c.name << " |";
      for (const std::string& cell : cells[c.name]) r.md << " " << cell << " |";
      r.md << "\n";
    }
    r.md << refMd.str();
  }
  r.report["quality"] = q;
  r.report["quality_size"] = std::to_string(qw) + "x" + std::to_string(qh);
  r.md << "\nImages: `" << r.opt.out << "/quality/`.\n";
}

}  // namespace clhair::bench
