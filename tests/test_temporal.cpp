// test_temporal.cpp — temporal reprojection of the hair (clhair/temporal.h).
//
// The step on synthetic planes: history carried along the motion vectors lands where the
// hair now is (blend of the two colours, exactly), and a square of hair that moved leaves no
// trail where it was (alpha 0 there) with the depth rule and the clamp, while without both it
// does (so the check can fail). End to end on the tiny groom: a static scene with a history of
// 3 frames renders exactly the still (the history was blended, not skipped); a groom translated
// about 4.6 px a frame leaves hair alpha below 0.01 in the pixels it vacated (and above 0.05
// without the protection); with reprojection off FrameSequence and the CLI give the frame of
// today byte for byte; bad values are refused with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "clhair/aov.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/temporal.h"
#include "test_util.h"

namespace clhair::test {
namespace {

using nlohmann::json;

// ---- the step on synthetic planes -------------------------------------------------------

constexpr int kW = 16, kH = 12;

// A frame's AOVs: background everywhere except a square of hair (x0 .. x0+3, rows 4..7) of
// premultiplied grey `value`, alpha `alpha`, depth 1, whose motion is `motionX` pixels.
FrameAovs squareFrame(int x0, float value, float alpha, float motionX) {
  FrameAovs a;
  const std::size_t pixels = static_cast<std::size_t>(kW) * kH;
  a.hair.assign(pixels * 4, 0.0f);
  a.z.assign(pixels, kAovBackgroundZ);
  a.motion.assign(pixels * 2, 0.0f);
  for (int y = 4; y < 8; ++y)
    for (int x = x0; x < x0 + 4; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * kW + x;
      a.hair[p * 4] = a.hair[p * 4 + 1] = a.hair[p * 4 + 2] = value;
      a.hair[p * 4 + 3] = alpha;
      a.z[p] = 1.0f;
      a.motion[p * 2] = motionX;
    }
  return a;
}

float at(const std::vector<float>& hair, int x, int y, int c) {
  return hair[(static_cast<std::size_t>(y) * kW + x) * 4 + c];
}

TEST(Temporal, HistoryFollowsTheMotionVectors) {
  // The square was at x 4..7 and is at 8..11 now; its motion points 4 px left (to where it
  // was). Without the clamp the blend is 0.5 * 0.6 + 0.5 * 0.2 = 0.4 exactly inside it; with
  // the motion ignored the sample would fall on the background and be dropped (0.6).
  const FrameAovs before = squareFrame(4, 0.2f, 1.0f, 0.0f);
  const FrameAovs now = squareFrame(8, 0.6f, 1.0f, -4.0f);
  TemporalParams p;
  p.history = 1;
  p.clamp = false;
  TemporalStats st;
  const std::vector<float> out = reprojectHair(now, before, before.hair, kW, kH, p, &st);
  for (int y = 4; y < 8; ++y)
    for (int x = 8; x < 12; ++x) {
      EXPECT_EQ(at(out, x, y, 0), 0.4f) << x << "," << y;
      EXPECT_EQ(at(out, x, y, 3), 1.0f) << x << "," << y;
    }
  EXPECT_EQ(st.rejected + st.blended + st.outside, static_cast<std::uint64_t>(kW * kH));
  // with the clamp, the current neighbourhood (all 0.6 inside the square) wins
  p.clamp = true;
  const std::vector<float> clamped = reprojectHair(now, before, before.hair, kW, kH, p);
  EXPECT_EQ(at(clamped, 9, 5, 0), 0.6f);
}

TEST(Temporal, AMovedSquareLeavesNoTrail) {
  // The background does not move (motion 0), so the pixels the square left (x 4..6, more
  // than a pixel from where it is now) sample the old square at the same place.
  const FrameAovs before = squareFrame(4, 0.5f, 1.0f, 0.0f);
  const FrameAovs now = squareFrame(8, 0.5f, 1.0f, -4.0f);
  auto trail = [&](bool clamp, bool depth) {
    TemporalParams p;
    p.history = 1;
    p.clamp = clamp;
    p.rejectDepth = depth;
    const std::vector<float> out = reprojectHair(now, before, before.hair, kW, kH, p);
    float worst = 0.0f;
    for (int y = 4; y < 8; ++y)
      for (int x = 4; x < 7; ++x) worst = std::max(worst, at(out, x, y, 3));
    return worst;
  };
  EXPECT_LT(trail(true, true), 1e-3f);
  EXPECT_LT(trail(true, false), 1e-3f);           // the clamp alone
  EXPECT_LT(trail(false, true), 1e-3f);           // the depth rule alone
  EXPECT_NEAR(trail(false, false), 0.5f, 1e-6f);  // unprotected: half the old hair remains
}

TEST(Temporal, BadPlanesAndBlendAreRefused) {
  const FrameAovs a = squareFrame(4, 0.5f, 1.0f, 0.0f);
  TemporalParams p;
  EXPECT_NE(errorOf([&] { reprojectHair(a, a, a.hair, kW + 1, kH, p); }).find("values, need"),
            std::string::npos);
  p.blend = 0.0f;
  EXPECT_NE(errorOf([&] { reprojectHair(a, a, a.hair, kW, kH, p); }).find("blend"),
            std::string::npos);
}

// ---- end to end on the tiny groom -------------------------------------------------------

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// The tiny groom seen along -z from 0.2 away at width x height; `groom` adds to its entry and
// `extra` to the scene.
std::string writeScene(const std::string& dir, int width, int height,
                       const json& groom = json::object(), const json& extra = json::object()) {
  json g = {{"file", assetPath("grooms/tiny.hairmesh.json")}, {"strands", 400}};
  g.update(groom);
  json scene = {
      {"resolution", {width, height}},
      {"camera", {{"position", {0.0, 0.03, 0.2}}, {"target", {0.0, 0.025, 0.0}}, {"fov", 35}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 0.8, 0.5}}}}},
      {"grooms", {g}}};
  scene.update(extra);
  const std::string path = dir + "/scene.json";
  writeFile(path, scene.dump(2));
  return path;
}

TEST(Temporal, StaticSceneEqualsTheStill) {
  const std::string dir = scratchDir();
  const Scene still = loadScene(writeScene(dir, 64, 48));
  Renderer r(sharedDevice());
  const Frame want = r.render(still, RenderOptions{});
  RenderOptions o;
  o.temporal = 3;
  FrameSequence seq(
      r, [&](long long) { return still; }, o);
  const Frame got = seq.render(5);
  ASSERT_EQ(got.color.rgba.size(), want.color.rgba.size());
  // the history is the same hair at the same place: blend 0.5 of equal values is exact
  EXPECT_TRUE(got.color.rgba == want.color.rgba);
  EXPECT_EQ(seq.lastHistory(), 3);
  EXPECT_EQ(seq.framesRendered(), 4u);  // frames 2..5
  EXPECT_EQ(seq.lastStats().blended, 3u * 64u * 48u);
  EXPECT_EQ(seq.lastStats().rejected, 0u);
  // another blend weight rounds differently, within 1e-6
  Scene other = still;
  other.temporal.blend = 0.3f;
  FrameSequence seq3(
      r, [&](long long) { return other; }, o);
  const Frame f3 = seq3.render(5);
  float worst = 0.0f;
  for (std::size_t i = 0; i < want.color.rgba.size(); ++i)
    worst = std::max(worst, std::fabs(f3.color.rgba[i] - want.color.rgba[i]));
  EXPECT_LE(worst, 1e-6f);
}

// Frames 1..4 of the tiny groom translated 0.008 world units in x per frame (about 4.6 px at
// 96x72); the largest and mean blended hair alpha over the pixels frame 4 vacated: hair
// (alpha >= 0.5) in frame 3's own render, no hair within a pixel in frame 4's.
void trailOfTranslatedGroom(bool protect, float& worst, double& mean, std::size_t& vacated) {
  const std::string dir = scratchDir();
  const json keys = {
      {"keys",
       {{{"frame", 1}, {"translate", {0, 0, 0}}}, {{"frame", 4}, {"translate", {0.024, 0, 0}}}}}};
  Scene shot = loadScene(writeScene(dir, 96, 72, {{"transform", keys}}));
  shot.temporal.clamp = protect;
  shot.temporal.rejectDepth = protect;
  Renderer r(sharedDevice());
  RenderOptions own;
  own.aovs = true;
  const Scene s3 = sceneAtFrame(shot, 3.0), s4 = sceneAtFrame(shot, 4.0);
  const Frame f3 = r.render(s3, own), f4 = r.render(s4, own);
  RenderOptions o;
  o.aovs = true;
  o.temporal = 3;
  FrameSequence seq(
      r, [&](long long n) { return sceneAtFrame(shot, static_cast<double>(n)); }, o);
  const Frame out = seq.render(4);
  worst = 0.0f;
  mean = 0.0;
  vacated = 0;
  const int w = 96, h = 72;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * w + x;
      if (!(f3.aovs.hairAlpha[p] >= 0.5f)) continue;
      bool hairNear = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = std::clamp(x + dx, 0, w - 1), qy = std::clamp(y + dy, 0, h - 1);
          hairNear = hairNear || f4.aovs.hairAlpha[static_cast<std::size_t>(qy) * w + qx] > 0.0f;
        }
      if (hairNear) continue;
      ++vacated;
      worst = std::max(worst, out.aovs.hairAlpha[p]);
      mean += out.aovs.hairAlpha[p];
      // nothing blended in: the frame's own colour, exactly
      if (protect) {
        for (int c = 0; c < 4; ++c) EXPECT_EQ(out.color.rgba[p * 4 + c], f4.color.rgba[p * 4 + c]);
      }
    }
  if (vacated > 0) mean /= static_cast<double>(vacated);
}

TEST(Temporal, RigidlyTranslatedGroomLeavesNoTrail) {
  float worst = 1.0f;
  double mean = 1.0;
  std::size_t vacated = 0;
  trailOfTranslatedGroom(true, worst, mean, vacated);
  std::printf("protected: %zu vacated pixels, blended hair alpha there max %.6f mean %.6f\n",
              vacated, worst, mean);
  ASSERT_GT(vacated, 20u);
  EXPECT_LT(worst, 0.01f);
  // the same shot without the depth rule and the clamp: the old hair shows where it was
  trailOfTranslatedGroom(false, worst, mean, vacated);
  std::printf("unprotected: %zu vacated pixels, blended hair alpha there max %.6f mean %.6f\n",
              vacated, worst, mean);
  ASSERT_GT(vacated, 20u);
  EXPECT_GT(mean, 0.05);
}

TEST(Temporal, OffIsTheFrameOfToday) {
  const std::string dir = scratchDir();
  const json keys = {{"keys", {{{"frame", 1}, {"rotate_y", 0}}, {{"frame", 9}, {"rotate_y", 40}}}}};
  const std::string path = writeScene(dir, 64, 48, {{"transform", keys}});
  const Scene shot = loadScene(path);
  Renderer r(sharedDevice());
  const Frame want = r.render(sceneAtFrame(shot, 5.0), RenderOptions{});
  RenderOptions o;
  o.temporal = 0;
  FrameSequence seq(
      r, [&](long long n) { return sceneAtFrame(shot, static_cast<double>(n)); }, o);
  EXPECT_TRUE(seq.render(5).color.rgba == want.color.rgba);
  o.temporal = -1;  // the scene's: off by default
  FrameSequence byScene(
      r, [&](long long n) { return sceneAtFrame(shot, static_cast<double>(n)); }, o);
  EXPECT_TRUE(byScene.render(5).color.rgba == want.color.rgba);
  EXPECT_EQ(byScene.lastHistory(), 0);
  // and the CLI: no flag, --temporal 0, and the scene key at 0 write the same bytes; with a
  // history the frame differs (the reprojection reaches the image)
  auto run = [&](const std::string& scene, const std::string& name, const std::string& extra) {
    const CommandResult c = runCli("render " + quote(scene) + " --frames 5 -o " +
                                   quote(dir + "/" + name + ".####.exr") + " " + extra);
    EXPECT_EQ(c.exitCode, 0) << c.output;
    return readBytes(dir + "/" + name + ".0005.exr");
  };
  const std::string plain = run(path, "plain", "");
  ASSERT_GT(plain.size(), 100u);
  EXPECT_TRUE(plain == run(path, "zero", "--temporal 0"));
  const std::string keyed =
      writeScene(dir, 64, 48, {{"transform", keys}}, {{"temporal", {{"history", 0}}}});
  EXPECT_TRUE(plain == run(keyed, "key0", ""));
  EXPECT_FALSE(plain == run(path, "two", "--temporal 2"));
  const std::string on =
      writeScene(dir, 64, 48, {{"transform", keys}}, {{"temporal", {{"history", 2}}}});
  EXPECT_TRUE(run(on, "keyed2", "") == run(path, "flag2", "--temporal 2"));
  EXPECT_TRUE(plain == run(on, "flag0", "--temporal 0"));  // the flag overrides the key
}

TEST(Temporal, BadValuesAreRefusedWithOneLine) {
  const std::string dir = scratchDir();
  const std::string path = writeScene(dir, 32, 24);
  for (const char* bad : {"9", "x", "1.5"}) {
    const CommandResult c = runCli("render " + quote(path) + " -o " + quote(dir + "/o.png") +
                                   " --temporal '" + bad + "'");
    EXPECT_NE(c.exitCode, 0) << bad;
    EXPECT_NE(onlyErrorLine(c.output).find("--temporal"), std::string::npos) << c.output;
  }
  const CommandResult ref = runCli("render " + quote(path) + " -o " + quote(dir + "/o.png") +
                                   " --temporal 2 --reference --spp 1");
  EXPECT_NE(ref.exitCode, 0);
  EXPECT_NE(onlyErrorLine(ref.output).find("--reference"), std::string::npos) << ref.output;
  for (const json& t : {json{{"history", 9}}, json{{"blend", 0}}, json{{"depth", 1}}}) {
    const std::string scene = writeScene(dir, 32, 24, json::object(), {{"temporal", t}});
    const CommandResult c = runCli("render " + quote(scene) + " -o " + quote(dir + "/o.png"));
    EXPECT_NE(c.exitCode, 0) << t.dump();
    EXPECT_NE(onlyErrorLine(c.output).find("temporal"), std::string::npos) << c.output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/o.png"));
}

}  // namespace
}  // namespace clhair::test
