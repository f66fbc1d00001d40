// test_quality.cpp — quality levels (clhair/progressive.h): what each level renders, and the
// progressive still of quality final: one pass is one jittered frame of the pass path, two
// halves of 2k passes merged are exactly one run of 2k passes, and the same passes give the
// same bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "clhair/image.h"
#include "clhair/progressive.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair::test {
namespace {

Scene smallGroom() {
  HairMesh m = makeGroomPreset("tiny");
  m.strandCount = 400;
  Scene s;
  s.width = 40;
  s.height = 30;
  s.grooms.emplace_back("tiny", std::make_shared<const HairMesh>(m));
  s.camera = framePreset(s, CameraPreset::Close, 30.0f, 15.0f);
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
  s.lights.push_back(l);
  return s;
}

bool sameBytes(const Frame& a, const Frame& b) {
  return a.color.rgba.size() == b.color.rgba.size() &&
         std::memcmp(a.color.rgba.data(), b.color.rgba.data(), a.color.rgba.size() * 4) == 0;
}

float maxAbsDiff(const Frame& a, const Frame& b) {
  float m = 0.0f;
  for (std::size_t k = 0; k < a.color.rgba.size(); ++k)
    m = std::max(m, std::fabs(a.color.rgba[k] - b.color.rgba[k]));
  return m;
}

TEST(Quality, LevelsResolveToTheirOptions) {
  Scene s = smallGroom();
  RenderOptions o;
  EXPECT_EQ(qualityLevel(s, o), Quality::Draft);
  RenderOptions d = qualityOptions(s, o);
  EXPECT_EQ(d.msaa, 1);
  EXPECT_EQ(d.pointShading, Toggle::Off);
  EXPECT_EQ(d.filter, Toggle::Default) << "draft keeps the scene's filter";
  s.quality.level = Quality::Good;
  const RenderOptions g = qualityOptions(s, o);
  EXPECT_EQ(g.msaa, kGoodMsaa);
  EXPECT_EQ(g.pointShading, kGoodPointShading ? Toggle::On : Toggle::Off);
  EXPECT_EQ(g.filter, Toggle::Off);
  RenderOptions pointOption;  // --shading point
  pointOption.pointShading = Toggle::On;
  EXPECT_EQ(qualityOptions(s, pointOption).pointShading, Toggle::On);
  EXPECT_EQ(qualityOptions(s, pointOption).msaa, kGoodMsaa);
  o.quality = Quality::Draft;  // the option wins over the scene
  EXPECT_EQ(qualityOptions(s, o).msaa, 1);
  o.quality = Quality::Final;
  EXPECT_EQ(finalPasses(s, o), kDefaultFinalPasses);
  const RenderOptions pass = qualityOptions(s, o);  // final's pass path
  EXPECT_EQ(pass.msaa, kFinalPassGood ? kGoodMsaa : 1);
  EXPECT_EQ(pass.filter, Toggle::Off);
  s.quality.spp = 8;
  EXPECT_EQ(finalPasses(s, o), 8);
  o.spp = 3;
  EXPECT_EQ(finalPasses(s, o), 3);
  Renderer r(sharedDevice());
  EXPECT_NE(errorOf([&] { r.submit(s, o); }).find("render()"), std::string::npos);
}

// Good: the frame draws 4 samples per pixel, unfiltered, shaded as kGoodPointShading says;
// with point shading asked for (--shading point) it shades once per visible point (its
// points counted).
TEST(Quality, GoodIsMsaa4UnfilteredShadedAsAsked) {
  Scene s = smallGroom();
  Renderer r(sharedDevice());
  RenderOptions o;
  o.quality = Quality::Good;
  const Frame good = r.render(s, o);
  EXPECT_EQ(good.stats.pointsShaded > 0u, kGoodPointShading);
  RenderOptions explicitGood;
  explicitGood.msaa = kGoodMsaa;
  explicitGood.pointShading = kGoodPointShading ? Toggle::On : Toggle::Off;
  explicitGood.filter = Toggle::Off;
  EXPECT_TRUE(sameBytes(good, r.render(s, explicitGood)));
  o.pointShading = Toggle::On;
  const Frame points = r.render(s, o);
  EXPECT_GT(points.stats.pointsShaded, 0u);
  explicitGood.pointShading = Toggle::On;
  EXPECT_TRUE(sameBytes(points, r.render(s, explicitGood)));
}

// One pass of final is the pass path's frame at pass 0's offset, to the accumulator's
// resolution (2^-24 of linear radiance); pass 1 is the frame at pass 1's offset.
TEST(Quality, OneFinalPassIsOneJitteredFrame) {
  Scene s = smallGroom();
  Renderer r(sharedDevice());
  RenderOptions o;
  o.quality = Quality::Final;
  o.spp = 1;
  const Frame final1 = r.render(s, o);
  RenderOptions pass = qualityOptions(s, o);
  finalJitter(0, pass.jitterX, pass.jitterY);
  const Frame jittered0 = r.render(s, pass);
  EXPECT_LE(maxAbsDiff(final1, jittered0), 1e-6f);
  ProgressiveStill second(r, s, o);
  second.add(1, 1);
  finalJitter(1, pass.jitterX, pass.jitterY);
  EXPECT_NE(pass.jitterX, 0.0f);
  const Frame jittered1 = r.render(s, pass);
  EXPECT_LE(maxAbsDiff(second.frame(), jittered1), 1e-6f);
  EXPECT_GT(maxAbsDiff(jittered0, jittered1), 1e-3f) << "the passes' offsets should matter";
}

// 2k passes as two merged halves are byte for byte one run of 2k passes; a second run of
// the same passes gives the same bytes.
TEST(Quality, FinalHalvesMergeIntoTheWholeRun) {
  Scene s = smallGroom();
  Renderer r(sharedDevice());
  RenderOptions o;
  o.quality = Quality::Final;
  const int k = 2;
  ProgressiveStill first(r, s, o), second(r, s, o), whole(r, s, o);
  first.add(0, k);
  second.add(k, k);
  first.merge(second);
  whole.add(0, 2 * k);
  EXPECT_EQ(first.passes(), 2 * k);
  EXPECT_TRUE(sameBytes(first.frame(), whole.frame()));
  o.spp = 2 * k;
  EXPECT_TRUE(sameBytes(r.render(s, o), whole.frame())) << "final is deterministic";
  // and it is an average: not any one pass
  RenderOptions pass = qualityOptions(s, o);
  EXPECT_GT(maxAbsDiff(whole.frame(), r.render(s, pass)), 1e-4f);
}

// The command line: a bad level, shading or shadow LOD is one error line and no image;
// --shading sample and point give different frames, good's default being the one
// kGoodPointShading names. The default scene draws with its defaults: at 48x32, LOD from the
// screen draws about a twentieth of the strands the camera and the maps draw with LOD off.
TEST(Quality, CommandLineFlags) {
  const std::string dir = scratchDir();
  const std::string out = dir + "/out.png";
  const std::string scene = quote(assetPath("scenes/default.json"));
  for (const std::string& bad : {std::string("--quality best"), std::string("--shading pixel"),
                                 std::string("--shadow-lod near")}) {
    const CommandResult r =
        runCli("render " + scene + " --width 48 --height 32 -o " + quote(out) + " " + bad);
    SCOPED_TRACE(bad + ":\n" + r.output);
    EXPECT_NE(r.exitCode, 0);
    EXPECT_NE(onlyErrorLine(r.output).find(bad.substr(0, bad.find(' '))), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  auto render = [&](const std::string& flags, const std::string& file) {
    const CommandResult r = runCli("render " + scene + " --width 48 --height 32 -o " +
                                   quote(dir + "/" + file) + " " + flags);
    EXPECT_EQ(r.exitCode, 0) << flags << "\n" << r.output;
    return readImage(dir + "/" + file);
  };
  const Image good = render("--quality good", "good.exr");
  const Image sample2 = render("--quality good --shading sample", "sample2.exr");
  const Image point = render("--quality good --shading point", "point.exr");
  ASSERT_EQ(sample2.rgba.size(), point.rgba.size());
  EXPECT_EQ(good.rgba, kGoodPointShading ? point.rgba : sample2.rgba) << "good's default";
  EXPECT_NE(sample2.rgba, point.rgba) << "--shading point should change how the frame is shaded";
}

}  // namespace
}  // namespace clhair::test
