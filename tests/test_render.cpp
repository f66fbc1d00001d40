// test_render.cpp — whole-frame properties: determinism across runs and, in float, across
// CPU thread counts (float_frames.h), an empty scene equals its background, hair lands
// where the groom projects.
#include <cmath>
#include <cstring>
#include <filesystem>

#include "clhair/renderer.h"
#include "float_frames.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair {
namespace {

Scene smallScene(const std::string& preset, std::int64_t strands, int w = 160, int h = 120) {
  HairMesh mesh = makeGroomPreset(preset);
  mesh.strandCount = strands;
  mesh.appearance.minHitDiameterPx = 1.0f;  // gap-free lines: coverage without the filter
  Scene s;
  s.width = w;
  s.height = h;
  s.background = glm::vec3(0.1f, 0.2f, 0.3f);
  Light l;
  l.direction = glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
  l.intensity = 2.0f;
  s.lights.push_back(l);
  s.grooms.push_back({preset, std::make_shared<const HairMesh>(std::move(mesh)), glm::mat4(1.0f)});
  s.camera = framePreset(s, CameraPreset::Close, 30.0f, 15.0f);
  return s;
}

TEST(Render, TwoRendersAreBitIdentical) {
  Scene s = smallScene("curly_medium", 3000);
  Renderer a(test::sharedDevice());
  Frame f1 = a.render(s);
  Frame f2 = a.render(s);
  Renderer b(test::sharedDevice());
  Frame f3 = b.render(s);
  ASSERT_EQ(f1.color.rgba.size(), f2.color.rgba.size());
  EXPECT_TRUE(std::memcmp(f1.color.rgba.data(), f2.color.rgba.data(), f1.color.rgba.size() * 4) ==
              0);
  EXPECT_TRUE(std::memcmp(f1.color.rgba.data(), f3.color.rgba.data(), f1.color.rgba.size() * 4) ==
              0);
  EXPECT_TRUE(std::memcmp(f1.depth.data(), f3.depth.data(), f1.depth.size() * 4) == 0);
}

TEST(Render, EmptySceneIsExactlyTheBackground) {
  Scene s;
  s.width = 37;  // not a multiple of the 8x8 work-groups
  s.height = 19;
  s.background = glm::vec3(0.25f, 0.5f, 0.75f);
  Renderer r(test::sharedDevice());
  Frame f = r.render(s);
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const float* p = f.color.pixel(x, y);
      ASSERT_EQ(p[0], 0.25f);
      ASSERT_EQ(p[1], 0.5f);
      ASSERT_EQ(p[2], 0.75f);
      ASSERT_EQ(p[3], 1.0f);
      ASSERT_TRUE(std::isinf(f.depth[static_cast<std::size_t>(y) * s.width + x]));
    }
}

TEST(Render, HairCoversItsProjectionAndNothingElse) {
  Scene s = smallScene("fur_sphere", 20000, 200, 150);
  Renderer r(test::sharedDevice());
  Frame f = r.render(s);
  // the fur ball is centered: hair in the middle, untouched background in the corners
  int hair = 0, total = 0;
  for (int y = 60; y < 90; ++y)
    for (int x = 85; x < 115; ++x) {
      ++total;
      const float* p = f.color.pixel(x, y);
      hair += std::fabs(p[0] - 0.1f) + std::fabs(p[1] - 0.2f) + std::fabs(p[2] - 0.3f) > 1e-3f;
    }
  EXPECT_GT(hair, total * 9 / 10);
  for (int y : {0, s.height - 1})
    for (int x : {0, s.width - 1}) {
      const float* p = f.color.pixel(x, y);
      EXPECT_EQ(p[0], 0.1f);
      EXPECT_EQ(p[2], 0.3f);
    }
  EXPECT_EQ(f.stats.strandsDrawn, 20000u);
  EXPECT_GT(f.stageMs("strands"), 0.0);
}

// Bit-identical float frames (colour, alpha, depth) with 1, 2 and 3 CPU threads, on every
// device whose thread count can be set (float_frames.h).
TEST(Render, ThreadCountsGiveBitIdenticalFloatFrames) {
  const std::string dir = test::scratchDir();
  const std::string scene = dir + "/scene.json";
  {
    std::FILE* fp = std::fopen(scene.c_str(), "w");
    ASSERT_TRUE(fp);
    std::fprintf(fp, R"({"resolution": [120, 90], "camera": {"preset": "close", "azimuth": 40},
      "lights": [{"type": "point", "position": [0.2, 0.3, 0.3], "intensity": 0.2, "shadows": true},
                 {"type": "directional", "direction": [-0.3, 0.8, 0.4], "intensity": 1.0}],
      "shadows": {"resolution": 64},
      "spheres": [{"center": [0, -0.02, 0], "radius": 0.01}],
      "grooms": [{"file": "%s", "strands": 400}]})",
                 test::assetPath("grooms/tiny.hairmesh.json").c_str());
    std::fclose(fp);
  }
  test::expectBitIdenticalAcrossThreadCounts(scene, dir);
}

}  // namespace
}  // namespace clhair
