// look.cpp — the benchmark's look section (clhair_bench --only look): the colour of the hair
// against the path-traced reference, light scattered between fibres included.
//
// The quality section measures the raster against references that share its assumptions;
// this one measures what a user sees: both bench grooms at eumelanin 0.3 (blonde), 1.3
// (brown) and 8 (black), and two blonde strand files (groom1's strands exported with a per-point
// colour: (1.0, 0.925, 0.569), the colour of a public blonde cyHair groom, which absorbs no red,
// and a darker (0.8, 0.62, 0.36)), at close, mid and
// far, every light with a deep opacity map (the default), against `--reference path` at
// --ref-spp samples (>= 256 for the published table). Per cell and level (draft, good, final
// with --look-final-passes passes): mean FLIP over the hair's pixels (where a sample of the
// reference saw hair), the mean colour of those pixels (sRGB, 8 bit) and its CIE76 distance
// in CIELAB (D65) to the reference's mean colour, and the frame's time. --quality-grooms
// picks the bench grooms (1, the default, with the strand file; 2; both), --look-rows some of
// their rows by tag. --look-scattering
// both adds rows with the light between fibres left out, and the draft as it was before
// (one scattering event, the bench scenes' lights without maps). --look-light lights or
// ambient keeps one kind of light; --look-path-events 1 (lights) or 2 (ambient) makes the
// reference single scattering, for the single-scattering rows (DESIGN.md, "Hair the colour
// of hair": the two errors measured apart).
#include "harness.h"
#include "look_scales.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "clhair/image.h"
#include "clhair/progressive.h"
#include "metrics/colour_difference.h"
#include "metrics/image_metrics.h"

namespace clhair::bench {
namespace {

std::string colourText(const std::array<double, 3>& c) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "(%.0f, %.0f, %.0f)", c[0], c[1], c[2]);
  return buf;
}

}  // namespace

void runLook(Run& r) {
  const int qw = r.opt.quick ? 320 : r.opt.qualityWidth,
            qh = r.opt.quick ? 180 : r.opt.qualityHeight;
  const std::string dir = r.opt.out + "/look";
  std::filesystem::create_directories(dir);
  if (!r.opt.refCache.empty()) std::filesystem::create_directories(r.opt.refCache);
  struct Groom {
    std::string tag, name;
    int scene;               // bench scene (0 groom1, 1 groom2)
    float eu;                // eumelanin at root and tip (hair meshes), or < 0: the strand file
    glm::vec3 colour{1.0f};  // the strand file's colour
  };
  std::vector<Groom> grooms;
  for (int g = 0; g < 2; ++g)
    for (float eu : {0.3f, 1.3f, 8.0f}) {
      char tag[32];
      std::snprintf(tag, sizeof(tag), "groom%d_eu%.1f", g + 1, eu);
      grooms.push_back({tag, std::string(r.groomNames[g]) + ", eumelanin " + fmt(eu, 1), g, eu});
    }
  grooms.push_back({"blonde_file", "groom1's strands, file colour (1.0, 0.925, 0.569)", 0, -1.0f,
                    glm::vec3(1.0f, 0.925f, 0.569f)});
  grooms.push_back({"dark_blonde_file", "groom1's strands, file colour (0.8, 0.62, 0.36)", 0, -1.0f,
                    glm::vec3(0.8f, 0.62f, 0.36f)});
  struct Level {
    const char* name;
    Quality quality;
    bool multipleScattering;
    bool plain = false;  // the bench scenes' lights without maps (the defaults before)
  };
  std::vector<Level> levels = {{"draft", Quality::Draft, true},
                               {"good", Quality::Good, true},
                               {"final", Quality::Final, true}};
  if (r.opt.lookScattering == "both") {
    levels.push_back({"draft, single scattering", Quality::Draft, false});
    levels.push_back({"good, single scattering", Quality::Good, false});
    levels.push_back({"draft before: single scattering, no maps", Quality::Draft, false, true});
  }
  json q;
  std::ostringstream scalesMd, contrastMd;  // --look-scales: two tables after the main one
  r.md << "\n## The look against the path-traced reference (" << qw << "x" << qh << ", path "
       << r.opt.refSpp << " spp, every light with a deep opacity map)\n\nOver the hair's pixels: "
       << "mean FLIP / mean colour ΔE (CIE76, CIELAB D65, of the mean 8-bit sRGB colour) / "
          "frame ms; final: "
       << r.opt.lookFinalPasses << " passes.\n\n| groom | distance | reference colour |";
  for (const Level& l : levels) r.md << " " << l.name << " |";
  r.md << "\n|---|---|---|";
  for (std::size_t i = 0; i < levels.size(); ++i) r.md << "---|";
  r.md << "\n";
  for (const Groom& gr : grooms) {
    // --quality-grooms: 1 (default) groom1 and the strand file, 2 groom2, both
    if ((gr.scene == 0 && r.opt.qualityGrooms == "2") ||
        (gr.scene == 1 && r.opt.qualityGrooms == "1"))
      continue;
    if (!r.opt.lookRows.empty() &&
        ("," + r.opt.lookRows + ",").find("," + gr.tag + ",") == std::string::npos)
      continue;
    for (int d = 0; d < 3; ++d) {
      if (r.opt.qualityDistances.find(r.distNames[d]) == std::string::npos) continue;
      Scene s = framed(r.scenes[gr.scene], r.dists[d], qw, qh);
      for (Light& light : s.lights) light.shadows = true;
      if (r.opt.lookLight == "ambient") s.lights.clear();
      if (r.opt.lookLight == "lights") s.ambient = glm::vec3(0.0f);
      if (gr.eu >= 0.0f) {
        HairMesh m = *s.grooms[0].mesh;
        m.appearance.useMelanin = true;
        m.appearance.eumelanin[0] = m.appearance.eumelanin[1] = gr.eu;
        s.grooms[0].mesh = std::make_shared<const HairMesh>(std::move(m));
      } else {
        StrandGroom sg = *r.exportedGroom1();
        sg.colors.assign(sg.points.size(), gr.colour);
        sg.appearance.useFileColor = true;
        GroomInstance gi = s.grooms[0];
        gi.mesh.reset();
        gi.strands = std::make_shared<const StrandGroom>(std::move(sg));
        s.grooms[0] = gi;
      }
      const std::string cell = gr.tag + "_" + r.distNames[d];
      // the light and the events in the name when they are not the defaults
      std::string variant;
      if (r.opt.lookLight != "all") variant += "_" + r.opt.lookLight;
      if (r.opt.lookPathEvents != 64) variant += "_" + std::to_string(r.opt.lookPathEvents) + "ev";
      if (r.opt.lookRefSeed != 1) variant += "_seed" + std::to_string(r.opt.lookRefSeed);
      const std::string refPath = r.opt.refCache + "/look_" + cell + "_" + std::to_string(qw) +
                                  "x" + std::to_string(qh) + "_path_" +
                                  std::to_string(r.opt.refSpp) + "spp" + variant + ".exr";
      Frame ref;
      double refMs = 0.0;
      if (!r.opt.refCache.empty() && std::filesystem::exists(refPath) &&
          std::filesystem::exists(refPath + ".depth")) {
        ref.color = readImage(refPath);
        ref.depth.resize(static_cast<std::size_t>(qw) * qh);
        std::ifstream in(refPath + ".depth", std::ios::binary);
        in.read(reinterpret_cast<char*>(ref.depth.data()),
                static_cast<std::streamsize>(ref.depth.size() * sizeof(float)));
      } else {
        const auto t0 = std::chrono::steady_clock::now();
        ReferenceOptions ro;
        ro.method = ReferenceMethod::Path;
        ro.spp = r.opt.refSpp;
        ro.pathEvents = r.opt.lookPathEvents;
        ro.pathSeed = r.opt.lookRefSeed;
        ref = r.b.renderer.renderReference(s, ro);
        refMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count();
        if (!r.opt.refCache.empty()) {
          writeImage(ref.color, refPath);
          std::ofstream o(refPath + ".depth", std::ios::binary);
          o.write(reinterpret_cast<const char*>(ref.depth.data()),
                  static_cast<std::streamsize>(ref.depth.size() * sizeof(float)));
        }
      }
      writeImage(ref.color, dir + "/" + cell + "_path.png");
      Scene bare = s;
      bare.grooms.clear();
      const Frame background = r.b.renderer.render(bare);
      std::vector<char> mask(ref.depth.size(), 0);
      std::size_t nHair = 0;
      for (std::size_t i = 0; i < mask.size(); ++i) {
        mask[i] = ref.depth[i] < background.depth[i] * (1.0f - 1e-6f);
        nHair += mask[i] ? 1u : 0u;
      }
      const std::array<double, 3> refColour = meanSrgb(ref.color, mask);
      json& qc = q[gr.tag][r.distNames[d]];
      qc["reference"] = {{"spp", r.opt.refSpp},
                         {"wall_ms", refMs},
                         {"mean_srgb", refColour},
                         {"chroma", chroma(refColour)},
                         {"hair_pixels", nHair}};
      if (r.opt.lookScales) {
        const json rc = octaveContrast(ref.color, mask);
        qc["scales"]["reference"] = {{"octave_contrast", rc}};
        contrastMd << "| " << gr.name << " | " << r.distNames[d] << " | path |";
        for (double v : rc.get<std::vector<double>>()) contrastMd << " " << fmt(v, 3) << " |";
        contrastMd << "\n";
      }
      std::fprintf(stderr, "look %s %s: path %d spp %.1f s, hair %s\n", gr.tag.c_str(),
                   r.distNames[d], r.opt.refSpp, refMs / 1000.0, colourText(refColour).c_str());
      r.md << "| " << gr.name << " | " << r.distNames[d] << " | " << colourText(refColour) << " |";
      for (const Level& l : levels) {
        RenderOptions o;
        o.quality = l.quality;
        o.multipleScattering = l.multipleScattering;
        Scene sl = s;
        if (l.plain)
          for (Light& light : sl.lights) light.shadows = false;
        Frame f;
        const auto t0 = std::chrono::steady_clock::now();
        if (l.quality == Quality::Final) {
          ProgressiveStill still(r.b.renderer, sl, o);
          still.add(0, r.opt.lookFinalPasses);
          f = still.frame();
        } else {
          f = r.b.renderer.render(sl, o);
        }
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        const double flip = maskedFlip(ref.color, f.color, mask);
        const std::array<double, 3> colour = meanSrgb(f.color, mask);
        const double de = deltaE(colour, refColour);
        if (r.opt.lookScales) {
          // where the error lives in scale (look_scales.h)
          json matched, contrast = octaveContrast(f.color, mask);
          scalesMd << "| " << gr.name << " | " << r.distNames[d] << " | " << l.name << " | "
                   << fmt(flip, 4) << " |";
          for (int radius : lookScaleRadii()) {
            const double mf =
                maskedFlip(ref.color, matchCoarserThan(ref.color, f.color, mask, radius), mask);
            matched[std::to_string(radius)] = mf;
            scalesMd << " " << fmt(mf, 4) << " |";
          }
          scalesMd << "\n";
          contrastMd << "| " << gr.name << " | " << r.distNames[d] << " | " << l.name << " |";
          for (double v : contrast.get<std::vector<double>>())
            contrastMd << " " << fmt(v, 3) << " |";
          contrastMd << "\n";
          json corr = json::array();  // NaN (a flat band) as null
          for (double v : octaveCorrelation(ref.color, f.color, mask))
            corr.push_back(std::isfinite(v) ? json(v) : json(nullptr));
          contrastMd << "| | | " << l.name << ": correlation with the path image |";
          for (const json& v : corr)
            contrastMd << " " << (v.is_number() ? fmt(v.get<double>(), 2) : std::string("-"))
                       << " |";
          contrastMd << "\n";
          qc["scales"][l.name] = {{"flip_coarser_matched", matched},
                                  {"octave_contrast", contrast},
                                  {"octave_correlation", corr}};
          std::fprintf(
              stderr,
              "look %s %s %s: FLIP with every feature coarser than 1/2/4/8/16/32 px exact: %s\n",
              gr.tag.c_str(), r.distNames[d], l.name, matched.dump().c_str());
        }
        std::string file = l.name;
        for (char& ch : file)
          if (ch == ' ' || ch == ',' || ch == ':') ch = '_';
        writeImage(f.color, dir + "/" + cell + "_" + file + ".png");
        qc[l.name] = {{"flip_hair", flip},
                      {"delta_e", de},
                      {"mean_srgb", colour},
                      {"chroma", chroma(colour)},
                      {"wall_ms", ms}};
        r.md << " " << fmt(flip, 3) << " / " << fmt(de, 1) << " / " << fmt(ms, 0) << " |";
        std::fprintf(stderr,
                     "look %s %s %s: FLIP %.4f, dE %.2f, %s (chroma %.1f vs %.1f), %.0f ms\n",
                     gr.tag.c_str(), r.distNames[d], l.name, flip, de, colourText(colour).c_str(),
                     chroma(colour), chroma(refColour), ms);
      }
      r.md << "\n";
    }
  }
  if (r.opt.lookScales) {
    r.md << "\nWhere the error is in scale (`--look-scales`): mean FLIP over the hair as "
            "rendered, then with every feature coarser than r pixels made exact (each channel "
            "scaled by the reference's mean over the (2r+1)^2 box around the pixel over the "
            "test's), a lower bound for any change that only moves coarser features.\n\n"
            "| groom | distance | level | as rendered |";
    for (int radius : lookScaleRadii()) r.md << " r = " << radius << " |";
    r.md << "\n|---|---|---|---|";
    for (std::size_t i = 0; i < lookScaleRadii().size(); ++i) r.md << "---|";
    r.md << "\n" << scalesMd.str();
    r.md << "\nContrast per octave of scale: RMS over the hair of the log luminance's band "
            "between box radii (pixel to 1, 1 to 2, ... 16 to 32), then the standard deviation "
            "of the 32-pixel average; below each level's, the correlation of its bands with the "
            "path image's (1: its bright and dark features of that scale sit where the path "
            "image's do).\n\n| groom | distance | image |";
    int prev = 0;
    for (int radius : lookScaleRadii()) {
      r.md << " " << prev << "-" << radius << " |";
      prev = radius;
    }
    r.md << " > " << prev << " |\n|---|---|---|";
    for (std::size_t i = 0; i <= lookScaleRadii().size(); ++i) r.md << "---|";
    r.md << "\n" << contrastMd.str();
  }
  r.report["look"] = q;
  r.md << "\nImages: `" << dir << "/`.\n";
}

}  // namespace clhair::bench
