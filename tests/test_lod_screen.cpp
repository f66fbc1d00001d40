// test_lod_screen.cpp — LOD from the screen (DESIGN.md, "LOD from the screen"): the strand
// count per bundle follows its width in pixels, not the strands of the groom; the strands
// drawn grow with the image; LOD that keeps every strand draws the LOD-off image; shipped
// grooms draw with LOD unless told otherwise; the deep opacity maps are built once over
// final's passes and again when their light moves, at a resolution that follows the
// camera's view of the grooms.
#include <algorithm>
#include <cstring>
#include <memory>
#include <string>

#include "clhair/lod_math.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "frame/shadow_maps.h"
#include "groom/presets.h"
#include "test_util.h"

namespace clhair {
namespace {

using namespace gpu;

TEST(LodScreenMath, StrandsPerPixelOfWidth) {
  // ceil(width * per_px + delta), between 1 and N
  EXPECT_EQ(clh_lod_strands_screen(10.0f, 4.0f, 1000u, 0.0f), 40u);
  EXPECT_EQ(clh_lod_strands_screen(10.0f, 4.0f, 1000u, 0.5f), 41u);     // ceil(40.5)
  EXPECT_EQ(clh_lod_strands_screen(2.6f, 4.0f, 1000u, 0.0f), 11u);      // ceil(10.4)
  EXPECT_EQ(clh_lod_strands_screen(0.0f, 4.0f, 1000u, 0.0f), 1u);       // at least one
  EXPECT_EQ(clh_lod_strands_screen(500.0f, 4.0f, 1000u, 0.3f), 1000u);  // at most N
  EXPECT_EQ(clh_lod_strands_screen(10.0f, 4.0f, 0u, 0.3f), 0u);         // empty stays empty
  // the count does not follow the groom's strands: only the cap at N does
  EXPECT_EQ(clh_lod_strands_screen(10.0f, 4.0f, 5000u, 0.2f),
            clh_lod_strands_screen(10.0f, 4.0f, 100u, 0.2f));
  // the record widens the kept strands by N / N_LOD and takes C from L as before
  const ClhLodRecord r = clh_lod_record_screen(0.25f, 10.0f, 4.0f, 400u, 0.0f, 8u, 129u, 0.5f);
  EXPECT_EQ(r.strands, 40u);
  EXPECT_FLOAT_EQ(r.coverage, 10.0f);
  EXPECT_EQ(r.control_points, clh_lod_control_points(0.25f, 8u, 129u));
}

// long_wavy with `strands` strands, LOD from the screen, seen close in a w x h image.
Scene wavyScene(std::int64_t strands, int w, int h, float perPixel = kLodStrandsPerPixel) {
  HairMesh m = makeGroomPreset("long_wavy");
  m.strandCount = strands;
  m.lod.enabled = true;
  m.lod.strandsPerPixel = perPixel;
  Scene s;
  s.width = w;
  s.height = h;
  s.grooms.emplace_back("wavy", std::make_shared<const HairMesh>(m), glm::mat4(1.0f));
  s.camera = reframeCamera(s, CameraPreset::Close);
  return s;
}

RenderOptions rasterOnly() {
  RenderOptions o;
  o.rasterOnly = true;  // the strand pass is all the statistics need
  o.segmentBudget = 0;
  return o;
}

TEST(LodScreen, SegmentsFollowTheImageWidth) {
  Renderer r(test::sharedDevice());
  const FrameStats big = r.render(wavyScene(30000, 320, 180), rasterOnly()).stats;
  const FrameStats half = r.render(wavyScene(30000, 160, 90), rasterOnly()).stats;
  RecordProperty("segments_320", std::to_string(big.segmentsPlanned));
  RecordProperty("segments_160", std::to_string(half.segmentsPlanned));
  ASSERT_GT(big.segmentsPlanned, 0u);
  ASSERT_LT(big.strandsDrawn, 30000u);  // LOD left strands out at the larger size too
  // strands per pixel of width: half the width, about half the strands (each bundle's count
  // is rounded up, so a little more than half); Lipp's L alone keeps the same count
  const double ratio = double(half.segmentsPlanned) / double(big.segmentsPlanned);
  EXPECT_GT(ratio, 0.4);
  EXPECT_LT(ratio, 0.65);
  // and the count follows the pixels, not the groom's strands
  const FrameStats denser = r.render(wavyScene(60000, 320, 180), rasterOnly()).stats;
  EXPECT_NEAR(double(denser.strandsDrawn) / double(big.strandsDrawn), 1.0, 0.05);
}

TEST(LodScreen, KeepingEveryStrandDrawsTheLodOffImage) {
  Renderer r(test::sharedDevice());
  // every bundle wider than a strand per 1/10000 pixel and L = 1: LOD keeps everything
  Scene s = wavyScene(4000, 96, 64, 1e4f);
  HairMesh m = *s.grooms[0].mesh;
  m.lod.lambda = 1e3f;
  s.grooms[0].mesh = std::make_shared<const HairMesh>(m);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = glm::vec3(0.3f, 1.0f, 0.5f);
  l.shadows = true;
  s.lights.push_back(l);
  RenderOptions on, off;
  off.lod = Toggle::Off;
  const Frame a = r.render(s, on), b = r.render(s, off);
  EXPECT_EQ(a.stats.strandsDrawn, 4000u);
  ASSERT_EQ(a.color.rgba.size(), b.color.rgba.size());
  EXPECT_EQ(std::memcmp(a.color.rgba.data(), b.color.rgba.data(), a.color.rgba.size() * 4), 0);
  // and where LOD does leave strands out, the images differ (the comparison can fail)
  Scene fewer = wavyScene(4000, 96, 64, 1.0f);
  fewer.lights = s.lights;
  const Frame c = r.render(fewer, on), d = r.render(fewer, off);
  EXPECT_LT(c.stats.strandsDrawn, 4000u);
  EXPECT_NE(std::memcmp(c.color.rgba.data(), d.color.rgba.data(), c.color.rgba.size() * 4), 0);
}

TEST(LodScreen, ShippedGroomsAndStrandFilesDrawWithLod) {
  for (const char* name : {"long_wavy", "curly_medium", "fur_sphere", "tiny"}) {
    const HairMesh m =
        loadHairMesh(test::assetPath(std::string("grooms/") + name + ".hairmesh.json"));
    EXPECT_TRUE(m.lod.enabled) << name;
    EXPECT_FLOAT_EQ(m.lod.strandsPerPixel, kLodStrandsPerPixel) << name;
  }
  const Scene s = loadScene(test::assetPath("scenes/head_mesh.json"));
  for (const GroomInstance& g : s.grooms) {
    if (g.strands) {
      EXPECT_TRUE(g.strands->lod.enabled) << g.name;
    }
  }
}

// A small groom under one shadowed light, for the maps' reuse.
Scene mappedScene() {
  Scene s = wavyScene(3000, 64, 48);
  Light l;
  l.type = Light::Type::Directional;
  l.direction = glm::vec3(0.3f, 1.0f, 0.5f);
  l.shadows = true;
  s.lights.push_back(l);
  return s;
}

TEST(ShadowReuse, MapIsBuiltOnceOverFinalPassesAndAgainWhenItsLightMoves) {
  Renderer r(test::sharedDevice());
  Scene s = mappedScene();
  RenderOptions o;
  o.quality = Quality::Final;
  o.spp = 4;
  // the passes differ only by their jitter, which the map does not depend on
  EXPECT_EQ(r.render(s, o).stats.shadowMapsBuilt, 1u);
  EXPECT_EQ(r.render(s, o).stats.shadowMapsBuilt, 0u);   // a second still of the same scene
  s.lights[0].direction = glm::vec3(-0.3f, 1.0f, 0.5f);  // the light moves: built again, once
  EXPECT_EQ(r.render(s, o).stats.shadowMapsBuilt, 1u);
  o.reuseShadows = false;  // every pass builds its own
  EXPECT_EQ(r.render(s, o).stats.shadowMapsBuilt, 4u);
}

TEST(ShadowReuse, MapResolutionFollowsTheCamerasViewOfTheGrooms) {
  EXPECT_EQ(ShadowMaps::mapResolution(512, 10.0f), 64);
  EXPECT_EQ(ShadowMaps::mapResolution(512, 100.0f), 128);
  EXPECT_EQ(ShadowMaps::mapResolution(512, 129.0f), 256);
  EXPECT_EQ(ShadowMaps::mapResolution(512, 5000.0f), 512);  // never above the scene's
  EXPECT_EQ(ShadowMaps::mapResolution(48, 5000.0f), 48);
  Renderer r(test::sharedDevice());
  Scene s = mappedScene();
  s.shadows.resolution = 1024;
  s.width = 320;
  s.height = 180;
  RenderOptions o;
  o.rasterOnly = true;
  const int close = r.render(s, o).stats.shadowResolution;
  s.camera = reframeCamera(s, CameraPreset::Far);
  const int far = r.render(s, o).stats.shadowResolution;
  RecordProperty("close", std::to_string(close));
  RecordProperty("far", std::to_string(far));
  EXPECT_LE(close, 1024);
  EXPECT_LT(far, close);
  o.shadowResFromCamera = false;
  EXPECT_EQ(r.render(s, o).stats.shadowResolution, 1024);
}

}  // namespace
}  // namespace clhair
