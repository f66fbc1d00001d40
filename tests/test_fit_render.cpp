// test_fit_render.cpp — fitted hair meshes through the renderer (clhair/fit.h, docs/fitting.md).
//
// A mesh fitted to the tiny preset's strands passes the hair-mesh reader's validation and
// renders through every path (plain, LOD, segment budget, wind, strand export, whose
// device strands match the fitter's CPU generator). The round trip: the tiny preset's
// exported strands fitted, compared by strand distance, hair FLIP and mask IoU against the
// yardstick of the same preset with another seed. A blonde strand file's fit keeps its colour.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "clhair/fit.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "fit/fit_error.h"
#include "fit/fit_strands.h"
#include "fit_groom.h"
#include "groom/presets.h"
#include "metrics/colour_difference.h"
#include "metrics/image_metrics.h"
#include "test_util.h"

namespace clhair {
namespace {
// A scene of one groom file seen from the side at 96 x 72, one directional light; `extra`
// is merged into the groom entry.
std::string writeGroomScene(const std::string& dir, const std::string& groomFile,
                            const nlohmann::json& extra = nlohmann::json::object()) {
  nlohmann::json g = {{"file", groomFile}};
  g.update(extra);
  const nlohmann::json scene = {
      {"resolution", {96, 72}},
      {"camera", {{"position", {0.0, 0.03, 0.16}}, {"target", {0.0, 0.025, 0.0}}, {"fov", 35}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 0.8, 0.5}}}}},
      {"grooms", {g}}};
  const std::string path = dir + "/scene.json";
  std::ofstream(path) << scene.dump(2);
  return path;
}

std::size_t hairPixels(const Frame& f) {
  return static_cast<std::size_t>(std::count_if(f.aovs.hairAlpha.begin(), f.aovs.hairAlpha.end(),
                                                [](float a) { return a >= 0.5f; }));
}

// The tiny preset's strands, fitted.
FitResult fittedTiny(std::int64_t strands, int bundles) {
  HairMesh src = makeGroomPreset("tiny");
  src.strandCount = strands;
  FitOptions o;
  o.bundles = bundles;
  o.evaluate = false;
  FitResult r = fitHairMesh(test::strandsOf(src), o);
  r.mesh.appearance = src.appearance;
  return r;
}

TEST(FitRenders, FittedMeshPassesValidationAndRendersThroughEveryPath) {
  const std::string dir = test::scratchDir();
  FitResult r = fittedTiny(3000, 12);
  r.mesh.ao.assign(r.mesh.positions.size(), 1.0f);  // no AO bake in this test
  saveHairMesh(r.mesh, dir + "/fit.hairmesh.json");
  const HairMesh back = loadHairMesh(dir + "/fit.hairmesh.json");  // the reader validates
  EXPECT_EQ(back.faces.size(), r.mesh.faces.size());
  EXPECT_EQ(back.strandCount, 3000);
  Renderer renderer(test::sharedDevice());
  RenderOptions o;
  o.aovs = true;
  const Scene scene = loadScene(writeGroomScene(dir, dir + "/fit.hairmesh.json"));
  const Frame plain = renderer.render(scene, o);
  EXPECT_EQ(plain.stats.strandsDrawn, 3000u);
  EXPECT_GT(hairPixels(plain), 200u);
  // LOD at a distance: fewer strands, still hair
  o.lod = Toggle::On;
  o.lodLambdaScale = 0.05f;
  const Frame lod = renderer.render(scene, o);
  EXPECT_LT(lod.stats.strandsDrawn, 3000u);
  EXPECT_GT(lod.stats.strandsDrawn, 0u);
  EXPECT_GT(hairPixels(lod), 100u);
  // a segment budget below the groom's segments
  o.lodLambdaScale = 1.0f;
  o.segmentBudget = 8000;
  const Frame budget = renderer.render(scene, o);
  EXPECT_TRUE(budget.stats.overBudget);
  EXPECT_LE(budget.stats.segmentsPlanned, 8000u);
  EXPECT_GT(hairPixels(budget), 100u);
  // wind: the cage moves, so do the strands
  const Scene windy = loadScene(writeGroomScene(
      dir, dir + "/fit.hairmesh.json",
      {{"wind", {{"strength", 0.02}, {"direction", {1, 0, 0}}, {"frequency", 1}}}}));
  RenderOptions w;
  w.aovs = true;
  const Frame w1 = renderer.render(sceneAtFrame(windy, 1), w);
  const Frame w7 = renderer.render(sceneAtFrame(windy, 7), w);
  EXPECT_GT(hairPixels(w7), 200u);
  EXPECT_FALSE(w1.color.rgba == w7.color.rgba);
  // export: the device's strands are the fitter's (the generator's CPU reference)
  const StrandSet set = renderer.generateStrands(back);
  const fit::GeneratedStrands cpu = fit::generateStrandsCpu(back, 0);
  ASSERT_EQ(set.pointCounts.size(), cpu.count());
  float worst = 0.0f;
  for (std::size_t i = 0; i < cpu.data.size(); ++i)
    worst = std::max(worst, glm::length(glm::vec3(set.points[3 * i], set.points[3 * i + 1],
                                                  set.points[3 * i + 2]) -
                                        cpu.data[i]));
  EXPECT_LT(worst, 1e-4f);  // the kernel's fast sine and power against the C library's
}

// Mean FLIP over the pixels where either frame has hair.
double hairFlip(const Frame& a, const Frame& b) {
  const ImageComparison c = compareImages(a.color, b.color);
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.aovs.hairAlpha.size(); ++i)
    if (a.aovs.hairAlpha[i] >= 1.0f / 255.0f || b.aovs.hairAlpha[i] >= 1.0f / 255.0f) {
      sum += c.flip.error[i];
      ++n;
    }
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

double maskIoU(const Frame& a, const Frame& b) {
  std::size_t i = 0, u = 0;
  for (std::size_t p = 0; p < a.aovs.hairAlpha.size(); ++p) {
    const bool x = a.aovs.hairAlpha[p] >= 0.5f, y = b.aovs.hairAlpha[p] >= 0.5f;
    i += x && y;
    u += x || y;
  }
  return u > 0 ? static_cast<double>(i) / static_cast<double>(u) : 1.0;
}

// The tiny preset at 6000 strands, AO open (the fit's mesh carries none either).
HairMesh tiny6000() {
  HairMesh src = makeGroomPreset("tiny");
  src.strandCount = 6000;
  src.ao.assign(src.positions.size(), 1.0f);
  return src;
}

// `src`'s strands as export-strands writes them (generated on the device).
StrandGroom exportedStrands(Renderer& renderer, const HairMesh& src) {
  const StrandSet exported = renderer.generateStrands(src);
  StrandGroom strands;
  strands.name = "tiny";
  strands.pointCounts = exported.pointCounts;
  for (std::size_t i = 0; i < exported.points.size(); i += 3)
    strands.points.push_back(
        glm::vec3(exported.points[i], exported.points[i + 1], exported.points[i + 2]));
  return strands;
}

TEST(FitRoundTrip, FittedGroomIsAsCloseAsTheOriginalWithAnotherSeed) {
  // the tiny preset's strands as export-strands writes them (generated on the device), a
  // mesh fitted to them, and as the yardstick the same preset with another seed: a groom
  // of the same cage and styling whose strands differ one by one
  const std::string dir = test::scratchDir();
  Renderer renderer(test::sharedDevice());
  const HairMesh src = tiny6000();
  const StrandGroom strands = exportedStrands(renderer, src);
  FitOptions o;
  o.bundles = 48;
  o.errorSample = 2000;
  FitResult r = fitHairMesh(strands, o);
  r.mesh.appearance = src.appearance;
  r.mesh.ao.assign(r.mesh.positions.size(), 1.0f);
  HairMesh reseeded = src;
  reseeded.seed = src.seed + 1;

  // strands: the fit's distance to the input against the reseeded groom's
  const fit::FitStrands in = fit::prepareFitStrands(strands, kFitSamples, 0.0f, 0);
  std::vector<std::size_t> measured;
  for (std::size_t i = 0; i < in.count(); i += 3) measured.push_back(i);
  auto meanDistance = [&](const HairMesh& m) {
    const std::vector<float> d =
        fit::strandDistances(in, measured, fit::generateStrandsCpu(m, 0), 0);
    double sum = 0.0;
    for (float v : d) sum += v;
    return sum / static_cast<double>(d.size());
  };
  const double fitted = meanDistance(r.mesh), other = meanDistance(reseeded);
  EXPECT_LT(fitted, 1.25 * other) << "fitted " << fitted << " m, reseeded " << other << " m";

  // renders, one camera for all three
  saveHairMesh(src, dir + "/src.hairmesh.json");
  saveHairMesh(r.mesh, dir + "/fit.hairmesh.json");
  saveHairMesh(reseeded, dir + "/seed.hairmesh.json");
  RenderOptions ro;
  ro.aovs = true;
  const Scene s0 = loadScene(writeGroomScene(dir, dir + "/src.hairmesh.json"));
  const Frame f0 = renderer.render(s0, ro);
  Scene s1 = s0, s2 = s0;
  s1.grooms[0].mesh = std::make_shared<const HairMesh>(loadHairMesh(dir + "/fit.hairmesh.json"));
  s2.grooms[0].mesh = std::make_shared<const HairMesh>(loadHairMesh(dir + "/seed.hairmesh.json"));
  const Frame f1 = renderer.render(s1, ro), f2 = renderer.render(s2, ro);
  // the hair's outline: within a few per cent of what reseeding keeps
  EXPECT_GE(maskIoU(f0, f1), maskIoU(f0, f2) - 0.03);
  const double flipFit = hairFlip(f0, f1), flipSeed = hairFlip(f0, f2);
  EXPECT_LT(flipFit, 1.25 * flipSeed) << "fitted " << flipFit << ", reseeded " << flipSeed;
  std::printf(
      "round trip: mean distance %.3g m (reseeded %.3g m), hair FLIP %.4f (reseeded %.4f), "
      "mask IoU %.4f (reseeded %.4f)\n",
      fitted, other, flipFit, flipSeed, maskIoU(f0, f1), maskIoU(f0, f2));
}

// A blonde strand file (the tiny preset's strands, colours from a darker root to a lighter
// tip per point, as a script would write them) and the mesh fitted to it, in one scene: the
// mean colour of their hair within ΔE 5 (CIE76 of the mean 8-bit sRGB colour over the pixels
// either draws with alpha >= 0.5). A file's colour is its fibres' albedo; the fit turns it
// into the mesh colour of the same absorption.
TEST(FitColour, BlondeStrandFileFitKeepsItsColour) {
  const std::string dir = test::scratchDir();
  Renderer renderer(test::sharedDevice());
  const HairMesh src = tiny6000();
  StrandGroom strands = exportedStrands(renderer, src);
  strands.name = "blonde";
  strands.appearance = src.appearance;
  strands.appearance.useFileColor = true;
  const glm::vec3 root(0.80f, 0.62f, 0.36f), tip(1.0f, 0.92f, 0.62f);
  for (std::uint32_t n : strands.pointCounts)
    for (std::uint32_t k = 0; k < n; ++k)
      strands.colors.push_back(glm::mix(root, tip, float(k) / float(std::max(n, 2u) - 1)));
  FitOptions o;
  o.bundles = 48;
  o.evaluate = false;
  o.fibreWidth = src.appearance.strandWidth;
  const FitResult r = fitHairMesh(strands, o);
  EXPECT_FALSE(r.mesh.appearance.useMelanin);

  saveHairMesh(src, dir + "/src.hairmesh.json");
  RenderOptions ro;
  ro.aovs = true;
  Scene s0 = loadScene(writeGroomScene(dir, dir + "/src.hairmesh.json"));
  s0.ambient = glm::vec3(0.1f);
  s0.grooms[0] = GroomInstance("blonde", std::make_shared<const StrandGroom>(strands));
  Scene s1 = s0;
  s1.grooms[0] = GroomInstance("fit", std::make_shared<const HairMesh>(r.mesh));
  const Frame f0 = renderer.render(s0, ro), f1 = renderer.render(s1, ro);
  std::vector<char> mask(f0.aovs.hairAlpha.size(), 0);
  std::size_t n = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    mask[i] = f0.aovs.hairAlpha[i] >= 0.5f && f1.aovs.hairAlpha[i] >= 0.5f;
    n += mask[i] ? 1u : 0u;
  }
  ASSERT_GT(n, 200u) << "the two grooms overlap on screen";
  const std::array<double, 3> c0 = meanSrgb(f0.color, mask), c1 = meanSrgb(f1.color, mask);
  const double de = deltaE(c0, c1);
  RecordProperty("delta_e", std::to_string(de));
  std::printf("file (%.0f, %.0f, %.0f), fit (%.0f, %.0f, %.0f): ΔE %.2f over %zu pixels\n", c0[0],
              c0[1], c0[2], c1[0], c1[1], c1[2], de, n);
  EXPECT_LE(de, 5.0);
}

}  // namespace
}  // namespace clhair
